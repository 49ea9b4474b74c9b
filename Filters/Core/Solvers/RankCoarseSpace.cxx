#include "Solvers/RankCoarseSpace.h"

#include "Solvers/GraphSolvers.h"
#include "Solvers/Partition.h"
#include "Solvers/SparseFactorization.h"

#include <Eigen/SparseLU>

#include <algorithm>
#include <complex>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace beltrami
{

namespace
{

using Complex = std::complex<double>;
using ComplexMatrix = Eigen::SparseMatrix<Complex, Eigen::ColMajor, int>;
/// A row of the prolongation from the joining level: (coarse row, weight).
using CompositeRow = std::vector<std::pair<std::int64_t, double>>;

/// The product of the prolongations down to level `coarse`, row `position`
/// of the finest level (in the hierarchy's order): its weights on that
/// level's rows, numbered from `first`.
CompositeRow CompositeRowOf(const SurfaceHierarchy& h, int coarse, Index position, std::int64_t first)
{
  CompositeRow row{ { position, 1.0 } }, next;
  for (int l = 0; l < coarse; ++l)
  {
    const LevelMatrix& p = h.Prolongation(l);
    next.clear();
    for (const auto& [i, w] : row)
    {
      for (std::int64_t k = p.Offsets[i]; k < p.Offsets[i + 1]; ++k)
      {
        next.emplace_back(p.Columns[k], w * p.Values[k]);
      }
    }
    std::sort(next.begin(), next.end());
    row.clear();
    for (const auto& e : next)
    {
      if (!row.empty() && row.back().first == e.first)
      {
        row.back().second += e.second;
      }
      else
      {
        row.push_back(e);
      }
    }
  }
  for (auto& e : row)
  {
    e.first += first;
  }
  return row;
}

/// The level of a process's hierarchy that joins the `processes`: for the
/// real systems the finest whose rows, over all of them, stay within
/// JoinedRows (the coarsest where none does), for the complex ones the
/// coarsest.  (The 0.075%-noisy bunny Loop-subdivided once, 151k vertices,
/// on 2 processes: order-1 steps of 4000 h^2 took 9-10 iterations instead
/// of 17-18 on the levels of 1,000 rows a process rather than 126 (serial
/// 5-8); twice, on 2 processes, 8 and 17 instead of 13 and 21 on levels of
/// 4,300 rows rather than 510, each factorized in 0.04-0.06 s.  The complex
/// systems of order 2 took 13 and 44 instead of 15 and 50 but longer, each
/// solve with the complex factors of 8,700 rows costing more than the
/// iterations saved.)
int JoiningLevel(const SurfaceHierarchy& h, int processes, bool complex)
{
  constexpr double JoinedRows = 12000.0;
  int level = complex ? h.Levels() - 1 : 0;
  while (level + 1 < h.Levels() && static_cast<double>(h.Rows(level)) * processes > JoinedRows)
  {
    ++level;
  }
  return level;
}

/// The coarse operator's entries this process adds: (row, column) -> the
/// parts of D and of K.
class CoarseEntries
{
public:
  explicit CoarseEntries(std::int64_t total)
    : Total(total)
  {
  }
  void Add(std::int64_t i, std::int64_t j, double d, double k)
  {
    auto& e = Sums[i * Total + j];
    e.first += d;
    e.second += k;
  }
  /// (row, column, D, K) quadruples of every process.
  std::vector<double> Gathered(const Partition& split) const
  {
    std::vector<double> mine;
    mine.reserve(4 * Sums.size());
    for (const auto& [key, value] : Sums)
    {
      mine.insert(mine.end(), { static_cast<double>(key / Total), static_cast<double>(key % Total), value.first,
                                value.second });
    }
    return split.AllGather(mine);
  }

private:
  std::int64_t Total;
  std::unordered_map<std::int64_t, std::pair<double, double>> Sums;
};

} // namespace

struct RankCoarseSpace::State
{
  const Partition* Split = nullptr;
  const SurfaceMultigrid* Mg = nullptr;
  int Level = 0;                               ///< this process's level that joins the processes
  std::int64_t First = 0, Rows = 0, Total = 0; ///< this process's coarse rows, and all
  bool IsComplex = false, Factored = false;
  SparseFactorization::Matrix RealOperator;
  SparseFactorization Real;
  ComplexMatrix ComplexOperator;
  Eigen::SparseLU<ComplexMatrix> Lu;

  void AddOwnBlock(CoarseEntries& entries) const;
  void AddBorders(const ShiftedLaplacianProblem& pb, const SurfaceHierarchy* h, const std::vector<std::uint8_t>& held,
    CoarseEntries& entries) const;
  void Factorize(const std::vector<double>& quadruples, double factor, int threads);
};

/// The block of this process's coarse rows: its level's Galerkin operators.
void RankCoarseSpace::State::AddOwnBlock(CoarseEntries& entries) const
{
  const LevelMatrix k = Mg->Operator(Level), d = Mg->ShiftOperator(Level);
  for (std::int64_t i = 0; i < Rows; ++i)
  {
    entries.Add(First + i, First + i, d.Diagonal[i], k.Diagonal[i]);
    for (std::int64_t e = k.Offsets[i]; e < k.Offsets[i + 1]; ++e)
    {
      entries.Add(First + i, First + k.Columns[e], d.Values[e], k.Values[e]);
    }
  }
}

/// The couplings between processes: K_vj = -w of an own free row v and a
/// free ghost j, through both rows' prolongations (each process adds its
/// own rows' entries; D is diagonal on the finest level).  The rows on a
/// border are sent to every process, with their prolongations.
void RankCoarseSpace::State::AddBorders(const ShiftedLaplacianProblem& pb, const SurfaceHierarchy* h,
  const std::vector<std::uint8_t>& held, CoarseEntries& entries) const
{
  const Partition& split = *Split;
  const auto freeGhost = [&](Index j) { return !split.IsOwned(j) && !held[j]; };
  std::unordered_map<Index, CompositeRow> border;
  std::vector<double> sent; // (global row, coarse row, weight) triples
  std::unordered_set<std::int64_t> ghosts;
  for (Index v = 0; v < pb.Rows; ++v)
  {
    if (freeGhost(v))
    {
      ghosts.insert(split.GlobalRow(v));
    }
    if (!split.IsOwned(v) || held[v] || std::none_of(pb.Neighbors + pb.Offsets[v], pb.Neighbors + pb.Offsets[v + 1], freeGhost))
    {
      continue;
    }
    const CompositeRow& row = border[v] = CompositeRowOf(*h, Level, h->Position()[v], First);
    for (const auto& [c, w] : row)
    {
      sent.insert(sent.end(), { static_cast<double>(split.GlobalRow(v)), static_cast<double>(c), w });
    }
  }
  std::unordered_map<std::int64_t, CompositeRow> ghostRows;
  const std::vector<double> all = split.AllGather(sent);
  for (std::size_t t = 0; t < all.size(); t += 3)
  {
    const auto global = static_cast<std::int64_t>(all[t]);
    if (ghosts.count(global))
    {
      ghostRows[global].emplace_back(static_cast<std::int64_t>(all[t + 1]), all[t + 2]);
    }
  }
  for (const auto& [v, row] : border)
  {
    for (std::int64_t k = pb.Offsets[v]; k < pb.Offsets[v + 1]; ++k)
    {
      const Index j = pb.Neighbors[k];
      if (!freeGhost(j))
      {
        continue;
      }
      for (const auto& [p, a] : row)
      {
        for (const auto& [q, b] : ghostRows[split.GlobalRow(j)])
        {
          entries.Add(p, q, 0.0, -pb.Weights[k] * a * b);
        }
      }
    }
  }
}

void RankCoarseSpace::State::Factorize(const std::vector<double>& quadruples, double factor, int threads)
{
  std::vector<Eigen::Triplet<double, int>> d, k;
  for (std::size_t t = 0; t < quadruples.size(); t += 4)
  {
    const int i = static_cast<int>(quadruples[t]), j = static_cast<int>(quadruples[t + 1]);
    d.emplace_back(i, j, quadruples[t + 2]);
    k.emplace_back(i, j, quadruples[t + 3]);
  }
  SparseFactorization::Matrix dm(Total, Total), km(Total, Total);
  dm.setFromTriplets(d.begin(), d.end());
  km.setFromTriplets(k.begin(), k.end());
  bool shifted = true; // (every row has a part of D)
  double largest = 0.0;
  for (int i = 0; i < Total; ++i)
  {
    // A coarse row with no operator (its finer rows all held): an identity row.
    if (dm.coeff(i, i) == 0.0 && km.coeff(i, i) == 0.0)
    {
      dm.coeffRef(i, i) = 1.0;
    }
    shifted = shifted && dm.coeff(i, i) > 0.0;
    largest = std::max(largest, dm.coeff(i, i) + factor * km.coeff(i, i));
  }
  // With D on every row the coarse operator is definite on the range of P,
  // but P can have dependent columns: a coarse row whose sample is a ghost
  // (held) keeps only the fine rows it shares with others, and two such
  // rows can be proportional (the bunny on 4 processes, on levels of 1,100
  // rows: D and K shared a null vector, and the factors were rounding
  // noise).  What P maps to zero does not matter to P (P^T A P)^-1 P^T, so
  // a ridge of 1e-10 of the largest diagonal entry makes the matrix
  // definite, and moves its other eigenvalues by that much: a
  // preconditioner's rounding.
  for (int i = 0; shifted && i < Total; ++i)
  {
    dm.coeffRef(i, i) += 1e-10 * largest;
  }
  if (IsComplex)
  {
    ComplexOperator = dm.cast<Complex>() + Complex(0.0, factor) * km.cast<Complex>();
    ComplexOperator.makeCompressed();
    Lu.compute(ComplexOperator);
    Factored = Lu.info() == Eigen::Success;
    return;
  }
  // (The factorization may refer to the matrix: kept.  With the ridge, its
  // pivots' ratio is no test of singularity: the ridge's definite matrix
  // passes whatever it is.)
  RealOperator = dm + factor * km;
  RealOperator.makeCompressed();
  Factored = Real.Compute(RealOperator, true, {}, false, threads, shifted ? 0.0 : 1e-13);
}

RankCoarseSpace::RankCoarseSpace(const ShiftedLaplacianProblem& pb, const SurfaceHierarchy* hierarchy,
  const SurfaceMultigrid* mg, const std::vector<std::uint8_t>& held, double factor, bool complex)
  : S(std::make_unique<State>())
{
  const Partition& split = *pb.Split;
  S->Split = &split;
  S->Mg = mg;
  S->IsComplex = complex;
  S->Level = mg ? JoiningLevel(*hierarchy, split.Size(), complex) : 0;
  S->Rows = mg ? hierarchy->Rows(S->Level) : 0;
  const std::vector<double> counts = split.AllGather({ static_cast<double>(S->Rows) });
  for (int p = 0; p < split.Size(); ++p)
  {
    S->First += p < split.Rank() ? static_cast<std::int64_t>(counts[p]) : 0;
    S->Total += static_cast<std::int64_t>(counts[p]);
  }
  CoarseEntries entries(S->Total);
  if (mg)
  {
    S->AddOwnBlock(entries);
  }
  S->AddBorders(pb, hierarchy, held, entries);
  S->Factorize(entries.Gathered(split), factor, pb.NumberOfThreads);
}

RankCoarseSpace::~RankCoarseSpace() = default;

void RankCoarseSpace::Add(const double* r, double* z, int columns) const
{
  if (!S->Factored)
  {
    return; // (on every process)
  }
  std::vector<double> mine(static_cast<std::size_t>(S->Rows) * columns);
  if (S->Mg)
  {
    S->Mg->RestrictToLevel(S->Level, r, mine.data(), columns);
  }
  const std::vector<double> all = S->Split->AllGather(mine);
  const int parts = S->IsComplex ? 2 : 1, nc = columns / parts;
  Eigen::MatrixXd solution(S->Total, columns);
  if (S->IsComplex)
  {
    Eigen::MatrixXcd b(S->Total, nc);
    for (std::int64_t i = 0; i < S->Total; ++i)
    {
      for (int c = 0; c < nc; ++c)
      {
        b(i, c) = Complex(all[i * columns + c], all[i * columns + nc + c]);
      }
    }
    const Eigen::MatrixXcd x = S->Lu.solve(b);
    solution << x.real(), x.imag();
  }
  else
  {
    solution = S->Real.Solve(Eigen::Map<const Eigen::MatrixXd>(all.data(), columns, S->Total).transpose());
  }
  if (!solution.allFinite() || !S->Mg)
  {
    return;
  }
  for (std::int64_t i = 0; i < S->Rows; ++i)
  {
    for (int c = 0; c < columns; ++c)
    {
      mine[i * columns + c] = solution(S->First + i, c);
    }
  }
  S->Mg->AddProlongedFromLevel(S->Level, mine.data(), z, columns);
}

} // namespace beltrami
