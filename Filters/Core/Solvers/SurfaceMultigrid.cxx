#include "Solvers/SurfaceMultigrid.h"

#include "Solvers/SparseFactorization.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace beltrami
{

namespace
{

/// Levels stop at this many rows (solved by a sparse Cholesky), or where a
/// level keeps more than MostKept of the finer one's rows (many tiny
/// components, each of which keeps a sample).
constexpr Index CoarsestRows = 1000;
constexpr double MostKept = 0.6;

/// Gauss-Seidel sweeps before and after the coarse correction: two took
/// 18 and 5 iterations where one took 25 and 7 (order-2 and order-1 steps
/// of the clean 300k-triangle bunny), 57 and 14 where one took 86 and 21
/// (with noise of 0.3% of the diagonal), in about the same time.
constexpr int Sweeps = 2;

/// Columns cycled together (the order-2 solver's 3 complex columns are 6).
constexpr int MostColumns = 6;

/// A graph with a point per row (one level of the hierarchy).
struct PointGraph
{
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<Index> Neighbors;
  std::vector<double> Points;

  Index Rows() const { return static_cast<Index>(Offsets.size() - 1); }
};

/// The samples: a maximal set of rows at least three edges apart, taken in
/// row order (coarse[i] = the sample's coarse row, or -1).
std::vector<Index> Samples(const PointGraph& g, Index& count)
{
  const Index n = g.Rows();
  std::vector<Index> coarse(n, -1);
  std::vector<std::uint8_t> covered(n, 0);
  count = 0;
  for (Index i = 0; i < n; ++i)
  {
    if (covered[i])
    {
      continue;
    }
    coarse[i] = count++;
    covered[i] = 1;
    for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
    {
      const Index j = g.Neighbors[k];
      covered[j] = 1;
      for (std::int64_t l = g.Offsets[j]; l < g.Offsets[j + 1]; ++l)
      {
        covered[g.Neighbors[l]] = 1;
      }
    }
  }
  return coarse;
}

double Distance(const double* a, const double* b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/// The sample nearest each row along the edges (multi-source Dijkstra).
std::vector<Index> NearestSamples(const PointGraph& g, const std::vector<Index>& coarse)
{
  const Index n = g.Rows();
  std::vector<Index> region(n, -1);
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (Index i = 0; i < n; ++i)
  {
    if (coarse[i] >= 0)
    {
      region[i] = coarse[i];
      distance[i] = 0.0;
      queue.emplace(0.0, i);
    }
  }
  while (!queue.empty())
  {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > distance[i])
    {
      continue;
    }
    for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
    {
      const Index j = g.Neighbors[k];
      const double e = d + Distance(&g.Points[3 * i], &g.Points[3 * j]);
      if (e < distance[j])
      {
        distance[j] = e;
        region[j] = region[i];
        queue.emplace(e, j);
      }
    }
  }
  return region;
}

/// The coarse graph: samples joined where their regions touch.
PointGraph CoarseGraph(const PointGraph& g, const std::vector<Index>& coarse, const std::vector<Index>& region,
  Index count)
{
  const Index n = g.Rows();
  // Rows by region (counting sort).
  std::vector<std::int64_t> start(static_cast<std::size_t>(count) + 1, 0);
  for (Index i = 0; i < n; ++i)
  {
    ++start[region[i] + 1];
  }
  for (Index a = 0; a < count; ++a)
  {
    start[a + 1] += start[a];
  }
  std::vector<Index> members(n);
  std::vector<std::int64_t> next(start.begin(), start.end() - 1);
  for (Index i = 0; i < n; ++i)
  {
    members[next[region[i]]++] = i;
  }
  PointGraph c;
  c.Points.resize(3 * static_cast<std::size_t>(count));
  c.Offsets.resize(static_cast<std::size_t>(count) + 1, 0);
  std::vector<Index> touching;
  for (Index a = 0; a < count; ++a)
  {
    touching.clear();
    for (std::int64_t m = start[a]; m < start[a + 1]; ++m)
    {
      const Index i = members[m];
      if (coarse[i] == a)
      {
        std::copy(&g.Points[3 * i], &g.Points[3 * i] + 3, &c.Points[3 * a]);
      }
      for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
      {
        const Index b = region[g.Neighbors[k]];
        if (b != a)
        {
          touching.push_back(b);
        }
      }
    }
    std::sort(touching.begin(), touching.end());
    touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
    c.Neighbors.insert(c.Neighbors.end(), touching.begin(), touching.end());
    c.Offsets[a + 1] = static_cast<std::int64_t>(c.Neighbors.size());
  }
  return c;
}

bool Adjacent(const PointGraph& g, Index a, Index b)
{
  return std::binary_search(g.Neighbors.begin() + g.Offsets[a], g.Neighbors.begin() + g.Offsets[a + 1], b);
}

/// Row i's prolongation weights (coarse row, weight): the clamped
/// barycentric coordinates of p in the coarse triangle around sample s that
/// holds it best, else on the nearest coarse edge from s, else s alone.
void ProlongationRow(const PointGraph& c, Index s, const double* p, std::vector<std::pair<Index, double>>& row)
{
  row.clear();
  const double* o = &c.Points[3 * s];
  const double d[3] = { p[0] - o[0], p[1] - o[1], p[2] - o[2] };
  double best = -std::numeric_limits<double>::infinity();
  double weights[3] = { 1.0, 0.0, 0.0 };
  Index corners[3] = { s, -1, -1 };
  for (std::int64_t k = c.Offsets[s]; k < c.Offsets[s + 1]; ++k)
  {
    const Index a = c.Neighbors[k];
    const double* pa = &c.Points[3 * a];
    const double e1[3] = { pa[0] - o[0], pa[1] - o[1], pa[2] - o[2] };
    for (std::int64_t l = k + 1; l < c.Offsets[s + 1]; ++l)
    {
      const Index b = c.Neighbors[l];
      if (!Adjacent(c, a, b))
      {
        continue;
      }
      const double* pb = &c.Points[3 * b];
      const double e2[3] = { pb[0] - o[0], pb[1] - o[1], pb[2] - o[2] };
      const double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
      const double g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
      const double g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      const double det = g11 * g22 - g12 * g12;
      if (!(det > 1e-12 * g11 * g22))
      {
        continue; // degenerate
      }
      const double r1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2];
      const double r2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
      const double u = (g22 * r1 - g12 * r2) / det, v = (g11 * r2 - g12 * r1) / det;
      const double score = std::min({ 1.0 - u - v, u, v });
      if (score > best)
      {
        best = score;
        weights[0] = 1.0 - u - v;
        weights[1] = u;
        weights[2] = v;
        corners[1] = a;
        corners[2] = b;
      }
    }
  }
  if (corners[1] < 0)
  {
    // No triangle: the nearest point on the edges from s.
    double nearest = std::numeric_limits<double>::infinity();
    for (std::int64_t k = c.Offsets[s]; k < c.Offsets[s + 1]; ++k)
    {
      const Index a = c.Neighbors[k];
      const double* pa = &c.Points[3 * a];
      const double e[3] = { pa[0] - o[0], pa[1] - o[1], pa[2] - o[2] };
      const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
      if (!(ee > 0.0))
      {
        continue;
      }
      const double t = std::clamp((e[0] * d[0] + e[1] * d[1] + e[2] * d[2]) / ee, 0.0, 1.0);
      const double q[3] = { d[0] - t * e[0], d[1] - t * e[1], d[2] - t * e[2] };
      const double dd = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
      if (dd < nearest)
      {
        nearest = dd;
        weights[0] = 1.0 - t;
        weights[1] = t;
        weights[2] = 0.0;
        corners[1] = a;
      }
    }
  }
  double sum = 0.0;
  for (double& w : weights)
  {
    w = std::isfinite(w) ? std::max(0.0, w) : 0.0;
    sum += w;
  }
  if (!(sum > 0.0))
  {
    row.emplace_back(s, 1.0);
    return;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (corners[k] >= 0 && weights[k] > 0.0)
    {
      row.emplace_back(corners[k], weights[k] / sum);
    }
  }
}

/// The prolongation from the coarse graph to g's rows.
LevelMatrix ProlongationOf(const PointGraph& g, const PointGraph& c, const std::vector<Index>& coarse,
  const std::vector<Index>& region, int threads)
{
  const Index n = g.Rows();
  std::vector<std::array<std::pair<Index, double>, 3>> rows(n);
  std::vector<std::uint8_t> sizes(n);
  ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
    std::vector<std::pair<Index, double>> row;
    for (std::int64_t i = b; i < e; ++i)
    {
      if (coarse[i] >= 0)
      {
        row.assign(1, { coarse[i], 1.0 });
      }
      else
      {
        ProlongationRow(c, region[i], &g.Points[3 * i], row);
      }
      sizes[i] = static_cast<std::uint8_t>(row.size());
      std::copy(row.begin(), row.end(), rows[i].begin());
    }
  });
  LevelMatrix p;
  p.Offsets.resize(static_cast<std::size_t>(n) + 1);
  p.Offsets[0] = 0;
  for (Index i = 0; i < n; ++i)
  {
    p.Offsets[i + 1] = p.Offsets[i] + sizes[i];
  }
  p.Columns.resize(p.Offsets[n]);
  p.Values.resize(p.Offsets[n]);
  for (Index i = 0; i < n; ++i)
  {
    for (int k = 0; k < sizes[i]; ++k)
    {
      p.Columns[p.Offsets[i] + k] = rows[i][k].first;
      p.Values[p.Offsets[i] + k] = rows[i][k].second;
    }
  }
  return p;
}

/// The transpose of a (rows x columns) matrix stored without diagonal.
LevelMatrix Transpose(const LevelMatrix& a, Index columns)
{
  const Index n = static_cast<Index>(a.Offsets.size() - 1);
  LevelMatrix t;
  t.Offsets.assign(static_cast<std::size_t>(columns) + 1, 0);
  for (const Index c : a.Columns)
  {
    ++t.Offsets[c + 1];
  }
  for (Index c = 0; c < columns; ++c)
  {
    t.Offsets[c + 1] += t.Offsets[c];
  }
  std::vector<std::int64_t> next(t.Offsets.begin(), t.Offsets.end() - 1);
  t.Columns.resize(a.Columns.size());
  t.Values.resize(a.Values.size());
  for (Index i = 0; i < n; ++i)
  {
    for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
    {
      const std::int64_t at = next[a.Columns[k]]++;
      t.Columns[at] = i;
      t.Values[at] = a.Values[k];
    }
  }
  return t;
}

} // namespace

SurfaceHierarchy::SurfaceHierarchy(
  Index rows, const std::int64_t* offsets, const Index* neighbors, const double* points, int numThreads)
{
  const int threads = ResolveThreadCount(numThreads);
  FineOrder = LocalityOrder(rows, offsets, neighbors);
  FinePosition.resize(rows);
  for (Index i = 0; i < rows; ++i)
  {
    FinePosition[FineOrder[i]] = i;
  }
  PointGraph g;
  g.Offsets.resize(static_cast<std::size_t>(rows) + 1);
  g.Points.resize(3 * static_cast<std::size_t>(rows));
  for (Index i = 0; i < rows; ++i)
  {
    const Index v = FineOrder[i];
    for (std::int64_t k = offsets[v]; k < offsets[v + 1]; ++k)
    {
      if (neighbors[k] != v)
      {
        g.Neighbors.push_back(FinePosition[neighbors[k]]);
      }
    }
    std::sort(g.Neighbors.begin() + g.Offsets[i], g.Neighbors.end());
    g.Offsets[i + 1] = static_cast<std::int64_t>(g.Neighbors.size());
    std::copy(points + 3 * static_cast<std::int64_t>(v), points + 3 * static_cast<std::int64_t>(v) + 3,
      &g.Points[3 * i]);
  }
  Sizes.push_back(rows);
  while (g.Rows() > CoarsestRows)
  {
    Index count = 0;
    const std::vector<Index> coarse = Samples(g, count);
    if (count > MostKept * g.Rows())
    {
      break;
    }
    const std::vector<Index> region = NearestSamples(g, coarse);
    PointGraph c = CoarseGraph(g, coarse, region, count);
    Prolongations.push_back(ProlongationOf(g, c, coarse, region, threads));
    Restrictions.push_back(Transpose(Prolongations.back(), count));
    Sizes.push_back(count);
    g = std::move(c);
  }
}

namespace
{

/// One level's operators D and K in one pattern (DValues empty: D is
/// diagonal there).
struct LevelPair
{
  LevelMatrix K;
  std::vector<double> DValues, DDiagonal;
};

/// The Galerkin product R A P of a pair (R = P^T), row by coarse row with a
/// dense accumulator per block of rows.
LevelPair Galerkin(const LevelPair& fine, const LevelMatrix& p, const LevelMatrix& r, Index coarse, int threads)
{
  constexpr Index block = 1024;
  const Index blocks = (coarse + block - 1) / block;
  struct Part
  {
    std::vector<std::int64_t> Counts;
    std::vector<Index> Columns;
    std::vector<double> K, D, KDiagonal, DDiagonal;
  };
  std::vector<Part> parts(blocks);
  const bool dense = !fine.DValues.empty();
  // The accumulators are the threads' own, kept between calls; an entry is
  // current when its stamp is this call's and this row's.
  static std::atomic<std::int64_t> calls{ 0 };
  const std::int64_t call = ++calls;
  ParallelFor(blocks, threads, [&](std::int64_t b0, std::int64_t b1) {
    thread_local std::vector<double> accK, accD;
    thread_local std::vector<std::int64_t> seen;
    if (seen.size() < static_cast<std::size_t>(coarse))
    {
      accK.resize(coarse);
      accD.resize(coarse);
      seen.resize(coarse, -1);
    }
    std::vector<Index> touched;
    for (std::int64_t bl = b0; bl < b1; ++bl)
    {
      Part& part = parts[bl];
      const Index first = static_cast<Index>(bl * block), last = std::min(coarse, first + block);
      for (Index a = first; a < last; ++a)
      {
        touched.clear();
        const std::int64_t stamp = (call << 32) + a;
        const auto add = [&](Index j, double wk, double wd) {
          for (std::int64_t m = p.Offsets[j]; m < p.Offsets[j + 1]; ++m)
          {
            const Index c = p.Columns[m];
            if (seen[c] != stamp)
            {
              seen[c] = stamp;
              accK[c] = accD[c] = 0.0;
              touched.push_back(c);
            }
            accK[c] += wk * p.Values[m];
            accD[c] += wd * p.Values[m];
          }
        };
        for (std::int64_t q = r.Offsets[a]; q < r.Offsets[a + 1]; ++q)
        {
          const Index i = r.Columns[q];
          const double w = r.Values[q];
          add(i, w * fine.K.Diagonal[i], w * fine.DDiagonal[i]);
          for (std::int64_t k = fine.K.Offsets[i]; k < fine.K.Offsets[i + 1]; ++k)
          {
            add(fine.K.Columns[k], w * fine.K.Values[k], dense ? w * fine.DValues[k] : 0.0);
          }
        }
        double kd = 0.0, dd = 0.0;
        std::int64_t count = 0;
        for (const Index c : touched)
        {
          if (c == a)
          {
            kd = accK[c];
            dd = accD[c];
            continue;
          }
          part.Columns.push_back(c);
          part.K.push_back(accK[c]);
          part.D.push_back(accD[c]);
          ++count;
        }
        part.Counts.push_back(count);
        part.KDiagonal.push_back(kd);
        part.DDiagonal.push_back(dd);
      }
    }
  }, {}, 0, 1);
  LevelPair c;
  c.K.Offsets.assign(1, 0);
  for (Part& part : parts)
  {
    for (const std::int64_t count : part.Counts)
    {
      c.K.Offsets.push_back(c.K.Offsets.back() + count);
    }
    c.K.Columns.insert(c.K.Columns.end(), part.Columns.begin(), part.Columns.end());
    c.K.Values.insert(c.K.Values.end(), part.K.begin(), part.K.end());
    c.DValues.insert(c.DValues.end(), part.D.begin(), part.D.end());
    c.K.Diagonal.insert(c.K.Diagonal.end(), part.KDiagonal.begin(), part.KDiagonal.end());
    c.DDiagonal.insert(c.DDiagonal.end(), part.DDiagonal.begin(), part.DDiagonal.end());
  }
  return c;
}

/// The smoother's diagonal: A_ii plus the magnitudes of row i's entries
/// outside its block of ParallelChunkSize rows (the "l1" hybrid
/// Gauss-Seidel of Baker, Falgout, Kolev and Yang 2011: convergent for every
/// symmetric positive definite A, where plain block-hybrid sweeps diverged on
/// noisy meshes, whose cotangent weights can be large and negative).
std::vector<double> SmootherDiagonal(const LevelMatrix& a, int threads)
{
  std::vector<double> d(a.Diagonal);
  ParallelForStatic(a.Rows(), threads, [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t i = lo; i < hi; ++i)
    {
      for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
      {
        if (a.Columns[k] < lo || a.Columns[k] >= hi)
        {
          d[i] += std::abs(a.Values[k]);
        }
      }
    }
  });
  return d;
}

/// One Gauss-Seidel sweep of A x = b on every block of ParallelChunkSize rows
/// (forward or backward within the block, with the smoother's diagonal d),
/// the other blocks' values from `old` (x at the sweep's start).
template <int W>
void Sweep(const LevelMatrix& a, const std::vector<double>& d, const double* b, double* x, double* old,
  bool forward, int threads)
{
  const std::int64_t n = a.Rows();
  std::copy(x, x + n * W, old);
  ParallelForStatic(n, threads, [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t s = 0; s < hi - lo; ++s)
    {
      const std::int64_t i = forward ? lo + s : hi - 1 - s;
      double sum[W];
      for (int c = 0; c < W; ++c)
      {
        sum[c] = b[i * W + c] + (d[i] - a.Diagonal[i]) * x[i * W + c];
      }
      for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
      {
        const std::int64_t j = a.Columns[k];
        const double* xj = (j >= lo && j < hi ? x : old) + j * W;
        for (int c = 0; c < W; ++c)
        {
          sum[c] -= a.Values[k] * xj[c];
        }
      }
      const double inverse = 1.0 / d[i];
      for (int c = 0; c < W; ++c)
      {
        x[i * W + c] = sum[c] * inverse;
      }
    }
  });
}

/// r = b - A x.
template <int W>
void Residual(const LevelMatrix& a, const double* b, const double* x, double* r, int threads)
{
  ParallelForStatic(a.Rows(), threads, [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t i = lo; i < hi; ++i)
    {
      for (int c = 0; c < W; ++c)
      {
        r[i * W + c] = b[i * W + c] - a.Diagonal[i] * x[i * W + c];
      }
      for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
      {
        const double* xj = x + static_cast<std::int64_t>(a.Columns[k]) * W;
        for (int c = 0; c < W; ++c)
        {
          r[i * W + c] -= a.Values[k] * xj[c];
        }
      }
    }
  });
}

/// y = M x (M stored without diagonal: a prolongation or restriction), or
/// y += M x with `add`.
template <int W>
void Multiply(const LevelMatrix& m, const double* x, double* y, bool add, int threads)
{
  ParallelForStatic(static_cast<std::int64_t>(m.Offsets.size()) - 1, threads, [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t i = lo; i < hi; ++i)
    {
      double sum[W] = {};
      for (std::int64_t k = m.Offsets[i]; k < m.Offsets[i + 1]; ++k)
      {
        const double* xj = x + static_cast<std::int64_t>(m.Columns[k]) * W;
        for (int c = 0; c < W; ++c)
        {
          sum[c] += m.Values[k] * xj[c];
        }
      }
      for (int c = 0; c < W; ++c)
      {
        y[i * W + c] = (add ? y[i * W + c] : 0.0) + sum[c];
      }
    }
  });
}

} // namespace

struct SurfaceMultigrid::State
{
  std::shared_ptr<const SurfaceHierarchy> H;
  int Threads = 1;
  std::vector<LevelPair> Pairs;
  std::vector<LevelMatrix> A; ///< D + t K per level
  std::vector<std::vector<double>> SmootherDiagonals;
  std::vector<std::uint8_t> Held; ///< the finest level's, renumbered
  SparseFactorization::Matrix CoarsestMatrix;
  SparseFactorization Coarsest;
  bool Factored = false;
  /// Work vectors per level (MostColumns columns): right-hand side, solution, residual.
  mutable std::vector<std::vector<double>> B, X, R;

  void Combine(double t);
  void CoarsestSolve(int columns) const;
  template <int W>
  void Cycle(int level) const;
};

void SurfaceMultigrid::State::Combine(double t)
{
  A.resize(Pairs.size());
  for (std::size_t l = 0; l < Pairs.size(); ++l)
  {
    const LevelPair& p = Pairs[l];
    LevelMatrix& a = A[l];
    if (a.Offsets.size() != p.K.Offsets.size())
    {
      a.Offsets = p.K.Offsets;
      a.Columns = p.K.Columns;
    }
    a.Values.resize(p.K.Values.size());
    a.Diagonal.resize(p.K.Diagonal.size());
    ParallelFor(static_cast<std::int64_t>(a.Values.size()), Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = s; k < e; ++k)
      {
        a.Values[k] = (p.DValues.empty() ? 0.0 : p.DValues[k]) + t * p.K.Values[k];
      }
    });
    for (std::size_t i = 0; i < a.Diagonal.size(); ++i)
    {
      a.Diagonal[i] = p.DDiagonal[i] + t * p.K.Diagonal[i];
    }
  }
  SmootherDiagonals.resize(A.size());
  for (std::size_t l = 0; l < A.size(); ++l)
  {
    SmootherDiagonals[l] = SmootherDiagonal(A[l], Threads);
  }
  // The coarsest level's sparse Cholesky.
  const LevelMatrix& c = A.back();
  const Index n = c.Rows();
  std::vector<Eigen::Triplet<double, int>> entries;
  for (Index i = 0; i < n; ++i)
  {
    entries.emplace_back(i, i, c.Diagonal[i]);
    for (std::int64_t k = c.Offsets[i]; k < c.Offsets[i + 1]; ++k)
    {
      entries.emplace_back(i, c.Columns[k], c.Values[k]);
    }
  }
  CoarsestMatrix.resize(n, n);
  CoarsestMatrix.setFromTriplets(entries.begin(), entries.end());
  CoarsestMatrix.makeCompressed();
  Factored = n > 0 && Coarsest.Compute(CoarsestMatrix, true, {}, false, Threads);
}

void SurfaceMultigrid::State::CoarsestSolve(int columns) const
{
  const int l = static_cast<int>(A.size()) - 1;
  const Index n = A[l].Rows();
  if (Factored)
  {
    Eigen::MatrixXd b(n, columns);
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < columns; ++c)
      {
        b(i, c) = B[l][i * columns + c];
      }
    }
    const Eigen::MatrixXd x = Coarsest.Solve(b);
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < columns; ++c)
      {
        X[l][i * columns + c] = x.allFinite() ? x(i, c) : 0.0;
      }
    }
    return;
  }
  // Singular (a component of a pure Laplacian without held rows): symmetric
  // Gauss-Seidel sweeps instead (still a symmetric operator).
  std::fill(X[l].begin(), X[l].end(), 0.0);
  WithCount<MostColumns>(columns, [&](auto w) {
    constexpr int W = decltype(w)::value;
    for (int s = 0; s < 4; ++s)
    {
      Sweep<W>(A[l], SmootherDiagonals[l], B[l].data(), X[l].data(), R[l].data(), true, Threads);
      Sweep<W>(A[l], SmootherDiagonals[l], B[l].data(), X[l].data(), R[l].data(), false, Threads);
    }
  });
}

template <int W>
void SurfaceMultigrid::State::Cycle(int l) const
{
  if (l + 1 == static_cast<int>(A.size()))
  {
    CoarsestSolve(W);
    return;
  }
  const LevelMatrix& a = A[l];
  double* x = X[l].data();
  std::fill(X[l].begin(), X[l].begin() + static_cast<std::int64_t>(a.Rows()) * W, 0.0);
  for (int s = 0; s < Sweeps; ++s)
  {
    Sweep<W>(a, SmootherDiagonals[l], B[l].data(), x, R[l].data(), true, Threads);
  }
  Residual<W>(a, B[l].data(), x, R[l].data(), Threads);
  Multiply<W>(H->Restriction(l), R[l].data(), B[l + 1].data(), false, Threads);
  Cycle<W>(l + 1);
  Multiply<W>(H->Prolongation(l), X[l + 1].data(), x, true, Threads);
  for (int s = 0; s < Sweeps; ++s)
  {
    Sweep<W>(a, SmootherDiagonals[l], B[l].data(), x, R[l].data(), false, Threads);
  }
}

SurfaceMultigrid::SurfaceMultigrid(std::shared_ptr<const SurfaceHierarchy> hierarchy, const std::int64_t* offsets,
  const Index* neighbors, const double* weights, const double* diagonal, const double* shift, double factor,
  const std::uint8_t* held, int numThreads)
  : S(std::make_unique<State>())
{
  S->H = std::move(hierarchy);
  S->Threads = ResolveThreadCount(numThreads);
  const SurfaceHierarchy& h = *S->H;
  const Index n = h.Rows(0);
  const std::vector<Index>& order = h.Order();
  const std::vector<Index>& position = h.Position();
  // The finest level, renumbered; held rows are identity rows, uncoupled.
  LevelPair fine;
  fine.K.Diagonal.resize(n);
  fine.DDiagonal.resize(n);
  S->Held.resize(n);
  for (Index i = 0; i < n; ++i)
  {
    const Index v = order[i];
    const bool isHeld = held && held[v];
    S->Held[i] = isHeld;
    fine.K.Diagonal[i] = isHeld ? 0.0 : diagonal[v];
    fine.DDiagonal[i] = isHeld ? 1.0 : (shift ? shift[v] : 0.0);
    for (std::int64_t k = offsets[v]; !isHeld && k < offsets[v + 1]; ++k)
    {
      const Index j = neighbors[k];
      if (j != v && !(held && held[j]))
      {
        fine.K.Columns.push_back(position[j]);
        fine.K.Values.push_back(-weights[k]);
      }
    }
    fine.K.Offsets.push_back(static_cast<std::int64_t>(fine.K.Columns.size()));
  }
  S->Pairs.push_back(std::move(fine));
  for (int l = 0; l + 1 < h.Levels(); ++l)
  {
    // Held rows take no part in the coarse levels.
    if (l == 0 && held)
    {
      LevelMatrix p = h.Prolongation(0), r;
      for (Index i = 0; i < n; ++i)
      {
        for (std::int64_t k = p.Offsets[i]; k < p.Offsets[i + 1]; ++k)
        {
          p.Values[k] = S->Held[i] ? 0.0 : p.Values[k];
        }
      }
      r = Transpose(p, h.Rows(1));
      S->Pairs.push_back(Galerkin(S->Pairs[0], p, r, h.Rows(1), S->Threads));
      continue;
    }
    S->Pairs.push_back(Galerkin(S->Pairs[l], h.Prolongation(l), h.Restriction(l), h.Rows(l + 1), S->Threads));
  }
  S->B.resize(h.Levels());
  S->X.resize(h.Levels());
  S->R.resize(h.Levels());
  for (int l = 0; l < h.Levels(); ++l)
  {
    const std::size_t size = MostColumns * static_cast<std::size_t>(h.Rows(l));
    S->B[l].resize(size);
    S->X[l].resize(size);
    S->R[l].resize(size);
  }
  S->Combine(factor);
}

SurfaceMultigrid::~SurfaceMultigrid() = default;

void SurfaceMultigrid::SetFactor(double factor)
{
  S->Combine(factor);
}

void SurfaceMultigrid::Apply(const double* r, double* z, int columns) const
{
  Cycles(r, z, columns, S->H->Order().data());
}

void SurfaceMultigrid::ApplyInOrder(const double* r, double* z, int columns) const
{
  Cycles(r, z, columns, nullptr);
}

void SurfaceMultigrid::Cycles(const double* r, double* z, int columns, const Index* order) const
{
  const Index n = S->H->Rows(0);
  for (int first = 0; first < columns; first += MostColumns)
  {
    const int w = std::min(MostColumns, columns - first);
    ParallelForStatic(n, S->Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const std::int64_t v = order ? order[i] : i;
        for (int c = 0; c < w; ++c)
        {
          S->B[0][i * w + c] = S->Held[i] ? 0.0 : r[v * columns + first + c];
        }
      }
    });
    WithCount<MostColumns>(w, [&](auto k) { S->Cycle<decltype(k)::value>(0); });
    ParallelForStatic(n, S->Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const std::int64_t v = order ? order[i] : i;
        for (int c = 0; c < w; ++c)
        {
          z[v * columns + first + c] = S->Held[i] ? 0.0 : S->X[0][i * w + c];
        }
      }
    });
  }
}

int SurfaceMultigrid::Levels() const
{
  return static_cast<int>(S->A.size());
}

const LevelMatrix& SurfaceMultigrid::Operator(int level) const
{
  return S->A[level];
}

double SurfaceMultigrid::OperatorComplexity() const
{
  double all = 0.0;
  for (const LevelMatrix& a : S->A)
  {
    all += static_cast<double>(a.Values.size() + a.Diagonal.size());
  }
  return all / static_cast<double>(S->A[0].Values.size() + S->A[0].Diagonal.size());
}

} // namespace beltrami
