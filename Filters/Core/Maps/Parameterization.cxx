#include "Maps/Parameterization.h"

#include "Mesh/Laplacian.h"
#include "Support/LargeBuffer.h"
#include "Solvers/NestedDissection.h"
#include "Mesh/RingGeometry.h"
#include "Solvers/SparseFactorization.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <functional>
#include <new>
#include <numeric>
#include <sstream>
#include <tuple>

namespace beltrami
{

namespace
{

// ---------------------------------------------------------------------------
// A sparse system over "unknowns" (one per vertex and coordinate pair, or one
// per vertex coordinate for the coupled natural map), split into
//   F: solved through a sparse factorization,
//   G: a few extra unknowns solved densely with the constraints (pins whose
//      position is left free when constraints fix the map),
//   D: fixed values.
// The equations are the rows of F and G, plus constraint rows C y = t added
// with Lagrange multipliers (section 5.4.1):
//   [A_FF A_FG C_F^T] [f]   [b_F]
//   [A_GF A_GG C_G^T] [g] = [b_G]      (b = -A_.D d)
//   [C_F  C_G  0    ] [e]   [t  ]
// f is eliminated with the factorization of A_FF, leaving a small dense system.
// Several right-hand-side columns share the matrix (u and v for the
// per-vertex systems).

// The systems' arrays are LargeVectors (2 MiB pages, reused by the next
// run): at 179k vertices they hold some 100 MB, and faulting them in 4 KiB
// pages on this project's virtual machines cost 0.2-0.4 s of a first run.
struct RowMatrix // CSR rows over all unknowns
{
  LargeVector<std::int64_t> Offsets;
  LargeVector<int> Columns;
  LargeVector<double> Values;
};

/// A square compressed matrix (by rows or by columns) in LargeVectors.
struct CompressedMatrix
{
  int Size = 0;
  LargeVector<int> Outer, Inner;
  LargeVector<double> Values;

  SparseFactorization::MatrixView View() const
  {
    return { Size, Size, static_cast<Eigen::Index>(Values.size()), Outer.data(), Inner.data(), Values.data() };
  }

  /// The transpose (rows <-> columns), sorted within each row or column.
  CompressedMatrix Transposed() const
  {
    CompressedMatrix t;
    t.Size = Size;
    t.Outer.assign(static_cast<std::size_t>(Size) + 1, 0);
    t.Inner.resize(Inner.size());
    t.Values.resize(Values.size());
    for (int i : Inner)
    {
      ++t.Outer[i + 1];
    }
    std::partial_sum(t.Outer.begin(), t.Outer.end(), t.Outer.begin());
    std::vector<int> next(t.Outer.begin(), t.Outer.end() - 1);
    for (int r = 0; r < Size; ++r)
    {
      for (int k = Outer[r]; k < Outer[r + 1]; ++k)
      {
        const int at = next[Inner[k]]++;
        t.Inner[at] = r;
        t.Values[at] = Values[k];
      }
    }
    return t;
  }
};

struct ConstraintRow
{
  std::vector<std::pair<int, double>> Entries; ///< (unknown, coefficient)
  std::vector<double> Target;                  ///< per right-hand-side column
};

/// The fill-reducing elimination order of the mesh vertices.
std::vector<Index> VertexOrder(const MeshTopology& topo, const double* points, int threads)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  return NestedDissectionOrder(
    topo.NumberOfVertices(), edges.NeighborOffsets.data(), edges.Neighbors.data(), points, threads);
}

enum UnknownKind : std::uint8_t
{
  KindFactor = 0,
  KindExtra = 1,
  KindFixed = 2,
  KindUnused = 3
};

struct ParameterizationSolver
{
  // Unknown partition.
  std::vector<std::uint8_t> Kind;
  std::vector<int> Slot; // index within its kind
  int NumberFactor = 0, NumberExtra = 0;
  SparseFactorization Factor;
  CompressedMatrix AFF; // compressed columns (the factorization refers to it)
  Eigen::MatrixXd AFD_d; // -A_FD d per column (the right-hand side b_F)
  Eigen::MatrixXd AFG, AGF, AGG, BG;

  /// Splits the rows of `rows` by the kinds, factorizes A_FF and forms the
  /// right-hand sides from `fixedValues` (columns values per unknown).
  /// `vertexOrder`: the elimination order of the mesh vertices, whose
  /// unknowns are numbered vertex-major (one or two per vertex);
  /// `twinPairs`: see SparseFactorization::Compute.
  bool Setup(const RowMatrix& rows, const std::vector<std::uint8_t>& kind,
    const Eigen::MatrixXd& fixedValues, bool symmetric, const std::vector<Index>& vertexOrder,
    bool twinPairs, int threads, std::string& error)
  {
    Kind = kind;
    const int n = static_cast<int>(kind.size());
    Slot.assign(n, -1);
    NumberFactor = NumberExtra = 0;
    for (int i = 0; i < n; ++i)
    {
      if (kind[i] == KindFactor)
      {
        Slot[i] = NumberFactor++;
      }
      else if (kind[i] == KindExtra)
      {
        Slot[i] = NumberExtra++;
      }
    }
    const int columns = static_cast<int>(fixedValues.cols());
    AFD_d = Eigen::MatrixXd::Zero(NumberFactor, columns);
    AFG = Eigen::MatrixXd::Zero(NumberFactor, NumberExtra);
    AGF = Eigen::MatrixXd::Zero(NumberExtra, NumberFactor);
    AGG = Eigen::MatrixXd::Zero(NumberExtra, NumberExtra);
    BG = Eigen::MatrixXd::Zero(NumberExtra, columns);
    // A_FF in compressed rows, each sorted by column: AFF itself when A is
    // symmetric (rows are columns), else transposed afterwards.
    CompressedMatrix byRows;
    byRows.Size = NumberFactor;
    byRows.Outer.assign(static_cast<std::size_t>(NumberFactor) + 1, 0);
    for (int r = 0; r < n; ++r)
    {
      if (kind[r] == KindFactor)
      {
        for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
        {
          byRows.Outer[Slot[r] + 1] += kind[rows.Columns[k]] == KindFactor;
        }
      }
    }
    std::partial_sum(byRows.Outer.begin(), byRows.Outer.end(), byRows.Outer.begin());
    byRows.Inner.resize(static_cast<std::size_t>(byRows.Outer.back()));
    byRows.Values.resize(byRows.Inner.size());
    int* const outer = byRows.Outer.data();
    int* const inner = byRows.Inner.data();
    double* const values = byRows.Values.data();
    for (int r = 0; r < n; ++r)
    {
      if (kind[r] != KindFactor && kind[r] != KindExtra)
      {
        continue;
      }
      int out = kind[r] == KindFactor ? outer[Slot[r]] : 0;
      for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
      {
        const int c = rows.Columns[k];
        const double v = rows.Values[k];
        if (kind[c] == KindFixed)
        {
          for (int col = 0; col < columns; ++col)
          {
            (kind[r] == KindFactor ? AFD_d(Slot[r], col) : BG(Slot[r], col)) -= v * fixedValues(c, col);
          }
        }
        else if (kind[r] == KindFactor && kind[c] == KindFactor)
        {
          inner[out] = Slot[c];
          values[out++] = v;
        }
        else if (kind[r] == KindFactor && kind[c] == KindExtra)
        {
          AFG(Slot[r], Slot[c]) += v;
        }
        else if (kind[r] == KindExtra && kind[c] == KindFactor)
        {
          AGF(Slot[r], Slot[c]) += v;
        }
        else if (kind[r] == KindExtra && kind[c] == KindExtra)
        {
          AGG(Slot[r], Slot[c]) += v;
        }
      }
      if (kind[r] == KindFactor) // sort the row by column (a few entries)
      {
        const int b = outer[Slot[r]], e = outer[Slot[r] + 1];
        for (int i = b + 1; i < e; ++i)
        {
          for (int j = i; j > b && inner[j - 1] > inner[j]; --j)
          {
            std::swap(inner[j - 1], inner[j]);
            std::swap(values[j - 1], values[j]);
          }
        }
      }
    }
    AFF = symmetric ? std::move(byRows) : byRows.Transposed();
    std::vector<int> order;
    order.reserve(static_cast<std::size_t>(NumberFactor));
    const std::size_t perVertex = kind.size() / std::max<std::size_t>(vertexOrder.size(), 1);
    for (Index v : vertexOrder)
    {
      for (std::size_t d = 0; d < perVertex; ++d)
      {
        const std::size_t u = perVertex * static_cast<std::size_t>(v) + d;
        if (kind[u] == KindFactor)
        {
          order.push_back(Slot[u]);
        }
      }
    }
    if (NumberFactor > 0 && !Factor.Compute(AFF.View(), symmetric, order, twinPairs, threads))
    {
      error = "the linear system is singular (degenerate triangles or a disconnected part?)";
      return false;
    }
    return true;
  }

  /// Solves with the constraint rows; returns the values of the F and G
  /// unknowns (columns as in Setup) in `solution` (rows = all unknowns; fixed
  /// and unused rows are left as they are).
  bool Solve(const std::vector<ConstraintRow>& constraints, Eigen::MatrixXd& solution,
    std::string& error) const
  {
    const int columns = static_cast<int>(AFD_d.cols());
    const int r = static_cast<int>(constraints.size());
    Eigen::MatrixXd x0 = NumberFactor ? Factor.Solve(AFD_d) : Eigen::MatrixXd(0, columns);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(NumberExtra, columns);
    Eigen::MatrixXd eta = Eigen::MatrixXd::Zero(r, columns);
    if (NumberExtra + r > 0)
    {
      // Constraint rows split over F (dense columns, r of them) and G.
      Eigen::MatrixXd CF = Eigen::MatrixXd::Zero(NumberFactor, r); // C_F^T
      Eigen::MatrixXd CG = Eigen::MatrixXd::Zero(r, NumberExtra);
      Eigen::MatrixXd t = Eigen::MatrixXd::Zero(r, columns);
      for (int k = 0; k < r; ++k)
      {
        for (const auto& [u, coefficient] : constraints[k].Entries)
        {
          if (Kind[u] == KindFactor)
          {
            CF(Slot[u], k) += coefficient;
          }
          else if (Kind[u] == KindExtra)
          {
            CG(k, Slot[u]) += coefficient;
          }
          else if (Kind[u] == KindFixed)
          {
            for (int col = 0; col < columns; ++col)
            {
              t(k, col) -= coefficient * solution(u, col);
            }
          }
        }
        for (int col = 0; col < columns; ++col)
        {
          t(k, col) += constraints[k].Target[col];
        }
      }
      Eigen::MatrixXd rhsF(NumberFactor, NumberExtra + r);
      rhsF << AFG, CF;
      const Eigen::MatrixXd ZY = NumberFactor ? Factor.Solve(rhsF) : rhsF; // [Z Y]
      const Eigen::MatrixXd Z = ZY.leftCols(NumberExtra), Y = ZY.rightCols(r);
      const int m = NumberExtra + r;
      Eigen::MatrixXd K(m, m);
      Eigen::MatrixXd rhs(m, columns);
      K.topLeftCorner(NumberExtra, NumberExtra) = AGG - AGF * Z;
      K.topRightCorner(NumberExtra, r) = CG.transpose() - AGF * Y;
      K.bottomLeftCorner(r, NumberExtra) = CG - CF.transpose() * Z;
      K.bottomRightCorner(r, r) = -CF.transpose() * Y;
      rhs.topRows(NumberExtra) = BG - AGF * x0;
      rhs.bottomRows(r) = t - CF.transpose() * x0;
      Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
      if (lu.rank() < m)
      {
        error = "the point constraints are inconsistent or redundant (two constraints on the same "
                "point, or constraints on fixed boundary points that disagree with the boundary)";
        return false;
      }
      const Eigen::MatrixXd ge = lu.solve(rhs);
      g = ge.topRows(NumberExtra);
      eta = ge.bottomRows(r);
      x0 -= Z * g + Y * eta;
    }
    for (int u = 0; u < static_cast<int>(Kind.size()); ++u)
    {
      if (Kind[u] == KindFactor)
      {
        solution.row(u) = x0.row(Slot[u]);
      }
      else if (Kind[u] == KindExtra)
      {
        solution.row(u) = g.row(Slot[u]);
      }
    }
    return true;
  }

  /// Impulse responses of the fixed unknowns (section 5.4.2), for a system
  /// without extra unknowns: column j = response to fixed unknown `fixed[j]`.
  Eigen::MatrixXd ImpulseResponses(const RowMatrix& rows, const std::vector<int>& fixed) const
  {
    std::vector<int> column(Kind.size(), -1);
    for (std::size_t j = 0; j < fixed.size(); ++j)
    {
      column[fixed[j]] = static_cast<int>(j);
    }
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(NumberFactor, static_cast<int>(fixed.size()));
    for (int r = 0; r < static_cast<int>(Kind.size()); ++r)
    {
      if (Kind[r] != KindFactor)
      {
        continue;
      }
      for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
      {
        if (column[rows.Columns[k]] >= 0)
        {
          rhs(Slot[r], column[rows.Columns[k]]) -= rows.Values[k];
        }
      }
    }
    Eigen::MatrixXd basis(NumberFactor, rhs.cols());
    const int chunk = 64;
    for (int j = 0; j < rhs.cols(); j += chunk)
    {
      const int w = std::min<int>(chunk, static_cast<int>(rhs.cols()) - j);
      basis.middleCols(j, w) = Factor.Solve(rhs.middleCols(j, w));
    }
    return basis;
  }
};

} // namespace

BoundaryBasis::BoundaryBasis(Index numberOfVertices, std::vector<Index> boundary,
  std::vector<Index> free, std::vector<double> basis)
  : Vertices(numberOfVertices)
  , Boundary(std::move(boundary))
  , Free(std::move(free))
  , Basis(std::move(basis))
{
}

void BoundaryBasis::Apply(const double* boundaryUV, double* uv) const
{
  std::fill(uv, uv + 2 * static_cast<std::size_t>(Vertices), 0.0); // points in no triangle
  const Eigen::Index nb = static_cast<Eigen::Index>(Boundary.size());
  const Eigen::Index nf = static_cast<Eigen::Index>(Free.size());
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> p(boundaryUV, nb, 2);
  Eigen::Map<const Eigen::MatrixXd> b(Basis.data(), nf, nb);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> u = b * p;
  for (Eigen::Index k = 0; k < nf; ++k)
  {
    uv[2 * Free[k]] = u(k, 0);
    uv[2 * Free[k] + 1] = u(k, 1);
  }
  for (Eigen::Index k = 0; k < nb; ++k)
  {
    uv[2 * Boundary[k]] = p(k, 0);
    uv[2 * Boundary[k] + 1] = p(k, 1);
  }
}

void BoundaryBasis::PullBack(const double* gradient, double* boundaryGradient) const
{
  const Eigen::Index nb = static_cast<Eigen::Index>(Boundary.size());
  const Eigen::Index nf = static_cast<Eigen::Index>(Free.size());
  Eigen::Matrix<double, Eigen::Dynamic, 2> gf(nf, 2);
  for (Eigen::Index k = 0; k < nf; ++k)
  {
    gf(k, 0) = gradient[2 * Free[k]];
    gf(k, 1) = gradient[2 * Free[k] + 1];
  }
  Eigen::Map<const Eigen::MatrixXd> b(Basis.data(), nf, nb);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> gb = b.transpose() * gf;
  for (Eigen::Index k = 0; k < nb; ++k)
  {
    boundaryGradient[2 * k] = gb(k, 0) + gradient[2 * Boundary[k]];
    boundaryGradient[2 * k + 1] = gb(k, 1) + gradient[2 * Boundary[k] + 1];
  }
}

bool CheckDiskTopology(const MeshTopology& topo, std::string& error)
{
  const TopologySummary& s = topo.Summary();
  std::ostringstream os;
  if (topo.NumberOfTriangles() == 0)
  {
    error = "the input has no triangles";
    return false;
  }
  const Index components = topo.CountComponents();
  const std::int64_t twiceGenus = 2 - s.EulerCharacteristic - s.NumberOfBoundaryLoops;
  if (!s.IsManifold() || !s.IsOriented() || components != 1 || s.IsClosed() ||
    twiceGenus != 0)
  {
    os << "a parameterization needs one connected, manifold, consistently oriented surface of genus 0 "
          "with at least one boundary loop (a disk, possibly with holes); the input is: "
       << topo.Describe();
    if (s.IsClosed() && s.IsManifold())
    {
      os << ". Cut the closed surface open first (e.g. Clip, or remove a triangle)";
    }
    error = os.str();
    return false;
  }
  return true;
}

namespace
{

/// The per-vertex system rows lambda M^A + mu h^2 M^chi (unknown = vertex).
RowMatrix VertexSystem(const MeshTopology& topo, const double* points, double lambda, double mu,
  int threads, Index& degenerate)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index n = topo.NumberOfVertices();
  GraphLaplacian conformal, authalic;
  if (lambda != 0.0)
  {
    AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, conformal, threads);
    degenerate = conformal.DegenerateTriangles;
  }
  double h2 = 0.0;
  if (mu != 0.0)
  {
    AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Authalic, authalic, threads);
    degenerate = authalic.DegenerateTriangles;
    h2 = ParallelSum(edges.NumberOfEdges(), 1, threads, [&](std::int64_t b, std::int64_t e, double* sum) {
      for (std::int64_t k = b; k < e; ++k)
      {
        *sum += (Point(points, edges.Vertices[2 * k]) - Point(points, edges.Vertices[2 * k + 1])).squaredNorm();
      }
    })[0] / std::max<std::int64_t>(1, edges.NumberOfEdges());
  }
  RowMatrix m;
  m.Offsets.resize(static_cast<std::size_t>(n) + 1);
  for (Index i = 0; i <= n; ++i)
  {
    m.Offsets[i] = edges.NeighborOffsets[i] + i; // the neighbours and the diagonal
  }
  m.Columns.resize(m.Offsets[n]);
  m.Values.resize(m.Offsets[n]);
  ParallelFor(n, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      std::int64_t out = m.Offsets[i];
      double diagonal = 0.0;
      const std::int64_t diagonalAt = out++;
      for (std::int64_t k = edges.NeighborOffsets[i]; k < edges.NeighborOffsets[i + 1]; ++k)
      {
        double w = 0.0;
        if (lambda != 0.0)
        {
          w += lambda * 4.0 * conformal.Weights[k]; // cot a + cot b
        }
        if (mu != 0.0)
        {
          w += mu * h2 * authalic.Weights[k];
        }
        m.Columns[out] = edges.Neighbors[k];
        m.Values[out++] = -w;
        diagonal += w;
      }
      m.Columns[diagonalAt] = i;
      m.Values[diagonalAt] = diagonal;
    }
  });
  return m;
}

/// The coupled rows of the natural conformal map (eq. 5.7, halved):
/// unknowns 2i (u) and 2i+1 (v):  S (x) I_2  -  (1/2) Hess(signed area).
RowMatrix NaturalSystem(const MeshTopology& topo, const double* points, int threads,
  const std::vector<Index>& boundaryPrev, Index& degenerate)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index n = topo.NumberOfVertices();
  GraphLaplacian s;
  AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, s, threads);
  degenerate = s.DegenerateTriangles;
  RowMatrix m;
  m.Offsets.resize(2 * static_cast<std::size_t>(n) + 1);
  m.Offsets[0] = 0;
  for (Index i = 0; i < n; ++i)
  {
    const std::int64_t count =
      edges.NeighborOffsets[i + 1] - edges.NeighborOffsets[i] + 1 + (topo.BoundaryNext(i) >= 0 ? 2 : 0);
    m.Offsets[2 * i + 1] = m.Offsets[2 * i] + count;
    m.Offsets[2 * i + 2] = m.Offsets[2 * i + 1] + count;
  }
  m.Columns.resize(m.Offsets[2 * n]);
  m.Values.resize(m.Offsets[2 * n]);
  ParallelFor(n, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      for (int d = 0; d < 2; ++d)
      {
        std::int64_t out = m.Offsets[2 * i + d];
        m.Columns[out] = 2 * i + d;
        m.Values[out++] = s.Diagonal[i];
        for (std::int64_t k = edges.NeighborOffsets[i]; k < edges.NeighborOffsets[i + 1]; ++k)
        {
          m.Columns[out] = 2 * edges.Neighbors[k] + d;
          m.Values[out++] = -s.Weights[k];
        }
        const Index next = topo.BoundaryNext(i);
        if (next >= 0)
        {
          // d/du_i of A = 1/2 R(u_prev - u_next), R(x, y) = (-y, x); halved.
          const Index prev = boundaryPrev[i];
          const double sign = d == 0 ? 1.0 : -1.0;
          m.Columns[out] = 2 * next + (1 - d);
          m.Values[out++] = -0.25 * sign;
          m.Columns[out] = 2 * prev + (1 - d);
          m.Values[out++] = 0.25 * sign;
        }
      }
    }
  });
  return m;
}

void AddConstraintRows(const ParameterizationOptions& options, bool coupled,
  std::vector<ConstraintRow>& rows)
{
  for (const PointConstraint& c : options.Constraints)
  {
    if (!coupled)
    {
      ConstraintRow row;
      for (int k = 0; k < 3; ++k)
      {
        if (c.Vertices[k] >= 0 && c.Weights[k] != 0.0)
        {
          row.Entries.emplace_back(c.Vertices[k], c.Weights[k]);
        }
      }
      row.Target = { c.Target[0], c.Target[1] };
      rows.push_back(std::move(row));
      continue;
    }
    for (int d = 0; d < 2; ++d)
    {
      ConstraintRow row;
      for (int k = 0; k < 3; ++k)
      {
        if (c.Vertices[k] >= 0 && c.Weights[k] != 0.0)
        {
          row.Entries.emplace_back(2 * c.Vertices[k] + d, c.Weights[k]);
        }
      }
      row.Target = { c.Target[d] };
      rows.push_back(std::move(row));
    }
  }
}

/// Finds the minimum over [a, b] of the polynomial with coefficients `p`
/// (p[k] multiplies x^k): the derivative's roots by sign changes on a fine
/// grid refined by bisection, and the ends.
double MinimizePolynomial(const std::vector<double>& p, double a, double b)
{
  const auto value = [&](double x) {
    double v = 0.0;
    for (std::size_t k = p.size(); k-- > 0;)
    {
      v = v * x + p[k];
    }
    return v;
  };
  const auto slope = [&](double x) {
    double v = 0.0;
    for (std::size_t k = p.size(); k-- > 1;)
    {
      v = v * x + static_cast<double>(k) * p[k];
    }
    return v;
  };
  double best = a, bestValue = value(a);
  if (value(b) < bestValue)
  {
    best = b;
    bestValue = value(b);
  }
  const int samples = 4096;
  double x0 = a, s0 = slope(a);
  for (int k = 1; k <= samples; ++k)
  {
    const double x1 = a + (b - a) * k / samples;
    const double s1 = slope(x1);
    if (s0 < 0.0 && s1 >= 0.0) // a minimum in [x0, x1]
    {
      double lo = x0, hi = x1;
      for (int it = 0; it < 100 && hi - lo > 1e-15 * std::max(1.0, std::abs(hi)); ++it)
      {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) < 0.0 ? lo : hi) = mid;
      }
      const double x = 0.5 * (lo + hi);
      if (value(x) < bestValue)
      {
        best = x;
        bestValue = value(x);
      }
    }
    x0 = x1;
    s0 = s1;
  }
  return best;
}

std::vector<double> Multiply(const std::vector<double>& a, const std::vector<double>& b)
{
  std::vector<double> c(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    for (std::size_t j = 0; j < b.size(); ++j)
    {
      c[i + j] += a[i] * b[j];
    }
  }
  return c;
}

/// Coefficients in l of the energy of U = U_chi + l (U_A - U_chi), u -> s u.
std::vector<double> MixEnergyPolynomial(const MeshTopology& topo, const double* points,
  const double* uvA, const double* uvX, double s, DistortionEnergy energy)
{
  std::vector<double> total(energy == DistortionEnergy::EdgeLength ? 5 : 9, 0.0);
  const double s2 = s * s;
  if (energy == DistortionEnergy::EdgeLength)
  {
    ForEachEdge(topo, points, [&](Index i, Index j, double xx) {
      const Vec2 dX = UV(uvX, i) - UV(uvX, j);
      const Vec2 delta = UV(uvA, i) - UV(uvA, j) - dX;
      const std::vector<double> q = { s2 * dX.squaredNorm() / xx - 1.0, 2.0 * s2 * dX.dot(delta) / xx,
        s2 * delta.squaredNorm() / xx };
      const std::vector<double> q2 = Multiply(q, q);
      for (std::size_t k = 0; k < q2.size(); ++k)
      {
        total[k] += q2[k];
      }
    });
    return total;
  }
  ForEachTriangle(topo, points, [&](Index t, double a3) {
    // The signed area is quadratic in l: evaluate at 0, 1/2, 1 and interpolate.
    double area[3];
    double mixed[6];
    for (int k = 0; k < 3; ++k)
    {
      const double l = 0.5 * k;
      for (int c = 0; c < 3; ++c)
      {
        const Index v = topo.CornerVertex(3 * t + c);
        for (int d = 0; d < 2; ++d)
        {
          mixed[2 * c + d] = uvX[2 * v + d] + l * (uvA[2 * v + d] - uvX[2 * v + d]);
        }
      }
      const Vec2 b = Vec2(mixed[2], mixed[3]) - Vec2(mixed[0], mixed[1]);
      const Vec2 c = Vec2(mixed[4], mixed[5]) - Vec2(mixed[0], mixed[1]);
      area[k] = 0.5 * (b.x() * c.y() - b.y() * c.x());
    }
    const double f0 = area[0], fh = area[1], f1 = area[2];
    const double c2 = 2.0 * (f1 - 2.0 * fh + f0), c1 = f1 - f0 - c2;
    const std::vector<double> r = { s2 * f0 / a3, s2 * c1 / a3, s2 * c2 / a3 };
    std::vector<double> r2 = Multiply(r, r);
    r2[0] -= 1.0;
    const std::vector<double> e = Multiply(r2, r2);
    for (std::size_t k = 0; k < e.size(); ++k)
    {
      total[k] += e[k];
    }
  });
  return total;
}

} // namespace

namespace
{

ParameterizationResult Fail(std::string error)
{
  ParameterizationResult r;
  r.Error = std::move(error);
  return r;
}

void AppendWarning(std::string& warning, const std::string& text)
{
  warning += (warning.empty() ? "" : "; ") + text;
}

/// Gradient descent on the boundary points (section 5.5.2).
void OptimizeBoundary(const MeshTopology& topo, const double* points, const BoundaryBasis& basis,
  const ParameterizationOptions& options, std::vector<double>& uv, ParameterizationResult& result)
{
  const std::size_t nb = basis.BoundaryVertices().size();
  std::vector<double> p(2 * nb), gradient(uv.size()), g(2 * nb), trial(2 * nb), uvTrial(uv.size());
  for (std::size_t k = 0; k < nb; ++k)
  {
    p[2 * k] = uv[2 * basis.BoundaryVertices()[k]];
    p[2 * k + 1] = uv[2 * basis.BoundaryVertices()[k] + 1];
  }
  const int threads = ResolveThreadCount(options.NumberOfThreads);
  const double a3 = TotalArea3D(topo, points, threads), a2 = TotalArea2D(topo, uv.data(), threads);
  const double s = a2 > 0.0 ? std::sqrt(a3 / a2) : 1.0; // kept fixed during the descent
  double energy = DistortionEnergyValue(topo, points, uv.data(), s, options.BoundaryEnergy, gradient.data());
  result.BoundaryEnergies.push_back(energy);
  // The first step moves the boundary by about a hundredth of the domain's size.
  double step = -1.0;
  for (int it = 0; it < options.BoundaryOptimizationSteps; ++it)
  {
    basis.PullBack(gradient.data(), g.data());
    double norm = 0.0;
    for (double v : g)
    {
      norm = std::max(norm, std::abs(v));
    }
    if (!(norm > 0.0))
    {
      break;
    }
    if (step < 0.0)
    {
      step = 0.01 * std::sqrt(std::abs(a2)) / norm;
    }
    double slope = 0.0;
    for (double v : g)
    {
      slope += v * v;
    }
    bool accepted = false;
    for (int tries = 0; tries < 40; ++tries, step *= 0.5)
    {
      for (std::size_t k = 0; k < 2 * nb; ++k)
      {
        trial[k] = p[k] - step * g[k];
      }
      basis.Apply(trial.data(), uvTrial.data());
      const double e = DistortionEnergyValue(topo, points, uvTrial.data(), s, options.BoundaryEnergy);
      if (e <= energy - 1e-4 * step * slope && CountFlipped(topo, points, uvTrial.data()) == 0)
      {
        p.swap(trial);
        uv.swap(uvTrial);
        energy = DistortionEnergyValue(topo, points, uv.data(), s, options.BoundaryEnergy, gradient.data());
        accepted = true;
        step *= 2.0;
        break;
      }
    }
    result.BoundaryEnergies.push_back(energy);
    if (!accepted)
    {
      break; // a local minimum, as far as the line search can tell
    }
  }
}

ParameterizationResult ParameterizeUnguarded(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& options);

} // namespace

ParameterizationResult Parameterize(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& options)
{
  try
  {
    return ParameterizeUnguarded(topo, points, options);
  }
  catch (const std::bad_alloc&)
  {
    return Fail("Cannot parameterize: out of memory (the sparse factorization of a mesh of n vertices "
                "needs about 2-3 kB per vertex).");
  }
}

namespace
{

/// Point constraints on used vertices, with weights that sum to 1 and finite targets.
std::string CheckConstraints(const std::vector<PointConstraint>& constraints, const std::vector<std::uint8_t>& used)
{
  const Index n = static_cast<Index>(used.size());
  for (std::size_t k = 0; k < constraints.size(); ++k)
  {
    const PointConstraint& c = constraints[k];
    double sum = 0.0;
    bool any = false;
    for (int j = 0; j < 3; ++j)
    {
      if (c.Vertices[j] < 0)
      {
        continue;
      }
      if (c.Vertices[j] >= n || !used[c.Vertices[j]] || !std::isfinite(c.Weights[j]))
      {
        return "Point constraint " + std::to_string(k) + " refers to a point that is not on the surface.";
      }
      sum += c.Weights[j];
      any = true;
    }
    if (!any || std::abs(sum - 1.0) > 1e-6 || !std::isfinite(c.Target[0]) || !std::isfinite(c.Target[1]))
    {
      return "Point constraint " + std::to_string(k) + " needs barycentric weights that sum to 1 and a finite target.";
    }
  }
  return {};
}

/// The checks of the input and the options: the message of the first
/// problem, empty if there is none; `used` marks the vertices in a triangle.
std::string CheckInput(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  std::vector<std::uint8_t>& used)
{
  std::string error;
  if (!CheckDiskTopology(topo, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  const Index n = topo.NumberOfVertices();
  used.assign(n, 0);
  for (Index v = 0; v < n; ++v)
  {
    used[v] = topo.Valence(v) > 0;
    if (used[v] && !Point(points, v).allFinite())
    {
      return "Cannot parameterize: point " + std::to_string(v) + " has non-finite coordinates.";
    }
  }
  const bool natural = options.Boundary == ParameterizationBoundary::Natural;
  const bool mixSearch = options.OptimizeMix;
  if (!std::isfinite(options.ConformalWeight) || !std::isfinite(options.AuthalicWeight) ||
    (!mixSearch && options.ConformalWeight == 0.0 && options.AuthalicWeight == 0.0))
  {
    return "The conformal and authalic weights must be finite and not both 0.";
  }
  if (natural && (options.AuthalicWeight != 0.0 || mixSearch))
  {
    return "Natural boundaries are defined for the conformal energy only (thesis section 5.4.2): "
           "set the authalic weight to 0 and do not optimise the mix, or fix the boundary.";
  }
  if (natural && options.BoundaryOptimizationSteps > 0)
  {
    return "Boundary optimisation needs a fixed boundary (it moves the fixed boundary points).";
  }
  if (mixSearch && !(options.OptimalRange[0] <= options.OptimalRange[1]))
  {
    return "The search range of the optimal mix is empty.";
  }
  if ((options.BoundaryOptimizationSteps > 0 || options.KeepBoundaryBasis) && !options.Constraints.empty())
  {
    return "Boundary optimisation and the boundary basis do not combine with point constraints.";
  }
  return CheckConstraints(options.Constraints, used);
}

/// The two boundary vertices farthest apart (all boundary loops) and their
/// squared distance: exact up to 20000 boundary vertices, else a double
/// sweep (farthest from any vertex, then farthest from that one).
double FarthestBoundaryPair(const std::vector<std::vector<Index>>& loops, const double* points, int threads,
  Index& pa, Index& pb)
{
  std::vector<Index> boundary;
  for (const auto& loop : loops)
  {
    boundary.insert(boundary.end(), loop.begin(), loop.end());
  }
  pa = pb = boundary[0];
  double far = -1.0;
  if (boundary.size() <= 20000)
  {
    std::vector<double> best(boundary.size(), -1.0);
    std::vector<Index> partner(boundary.size(), -1);
    ParallelFor(static_cast<std::int64_t>(boundary.size()), threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        for (std::size_t j = i + 1; j < boundary.size(); ++j)
        {
          const double d = (Point(points, boundary[i]) - Point(points, boundary[j])).squaredNorm();
          if (d > best[i])
          {
            best[i] = d;
            partner[i] = boundary[j];
          }
        }
      }
    });
    for (std::size_t i = 0; i < boundary.size(); ++i)
    {
      if (best[i] > far)
      {
        far = best[i];
        pa = boundary[i];
        pb = partner[i];
      }
    }
    return far;
  }
  for (int sweep = 0; sweep < 2; ++sweep)
  {
    const Index from = sweep == 0 ? boundary[0] : pa;
    far = -1.0;
    for (Index v : boundary)
    {
      const double d = (Point(points, v) - Point(points, from)).squaredNorm();
      if (d > far)
      {
        far = d;
        (sweep == 0 ? pa : pb) = v;
      }
    }
  }
  return far;
}

/// The natural map is defined up to a similarity: with one point constraint,
/// translate it onto its target; with none, fit the map into [0,1]^2 by a
/// uniform scale and a translation (the energy does not change).
void PlaceNaturalMap(const ParameterizationOptions& options, const std::vector<std::uint8_t>& used,
  std::vector<double>& uv)
{
  const Index n = static_cast<Index>(used.size());
  if (options.Constraints.size() == 1)
  {
    const PointConstraint& c = options.Constraints[0];
    Vec2 at(0, 0);
    for (int j = 0; j < 3; ++j)
    {
      if (c.Vertices[j] >= 0)
      {
        at += c.Weights[j] * UV(uv.data(), c.Vertices[j]);
      }
    }
    for (Index v = 0; v < n; ++v)
    {
      uv[2 * v] += used[v] ? c.Target[0] - at.x() : 0.0;
      uv[2 * v + 1] += used[v] ? c.Target[1] - at.y() : 0.0;
    }
  }
  else if (options.Constraints.empty())
  {
    Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (Index v = 0; v < n; ++v)
    {
      if (used[v])
      {
        lo = lo.cwiseMin(UV(uv.data(), v));
        hi = hi.cwiseMax(UV(uv.data(), v));
      }
    }
    const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    for (Index v = 0; v < n; ++v)
    {
      if (used[v] && extent > 0.0)
      {
        uv[2 * v] = (uv[2 * v] - lo.x()) / extent;
        uv[2 * v + 1] = (uv[2 * v + 1] - lo.y()) / extent;
      }
    }
  }
}

/// The natural conformal map (eq. 5.7): the two farthest boundary points
/// pinned at (0,0) and (d,0), d their 3D distance; with two or more point
/// constraints the pins' positions are unknowns too (the constraints then
/// fix the similarity that the pins fix otherwise).  An error message, or
/// empty with `uv` set.
std::string MapNatural(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  const std::vector<std::vector<Index>>& loops, const std::vector<std::uint8_t>& used, int threads,
  ParameterizationResult& result, std::vector<double>& uv)
{
  const Index n = topo.NumberOfVertices();
  std::vector<Index> prev(n, -1);
  for (Index v = 0; v < n; ++v)
  {
    if (topo.BoundaryNext(v) >= 0)
    {
      prev[topo.BoundaryNext(v)] = v;
    }
  }
  Index pa = -1, pb = -1;
  const double far = FarthestBoundaryPair(loops, points, threads, pa, pb);
  if (!(far > 0.0))
  {
    return "Cannot parameterize: the boundary points all coincide.";
  }
  result.PinnedVertices = { pa, pb };
  Index degenerate = 0;
  const RowMatrix rows = NaturalSystem(topo, points, threads, prev, degenerate);
  result.DegenerateTriangles = degenerate;
  const bool freePins = options.Constraints.size() >= 2;
  std::vector<std::uint8_t> kind(2 * static_cast<std::size_t>(n), KindFactor);
  Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(2 * n, 1);
  for (Index v = 0; v < n; ++v)
  {
    if (!used[v])
    {
      kind[2 * v] = kind[2 * v + 1] = KindFixed;
    }
  }
  for (int d = 0; d < 2; ++d)
  {
    kind[2 * pa + d] = kind[2 * pb + d] = freePins ? KindExtra : KindFixed;
  }
  fixed(2 * pb, 0) = std::sqrt(far);
  ParameterizationSolver solver;
  std::string error;
  // u and v share the cotangent matrix and are coupled on the boundary only.
  if (!solver.Setup(rows, kind, fixed, true, VertexOrder(topo, points, threads), true, threads, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  std::vector<ConstraintRow> constraints;
  if (freePins)
  {
    AddConstraintRows(options, true, constraints);
  }
  Eigen::MatrixXd solution = fixed;
  if (!solver.Solve(constraints, solution, error))
  {
    return "Cannot parameterize: " + error + ".";
  }
  for (Index v = 0; v < n; ++v)
  {
    uv[2 * v] = used[v] ? solution(2 * v, 0) : 0.0;
    uv[2 * v + 1] = used[v] ? solution(2 * v + 1, 0) : 0.0;
  }
  PlaceNaturalMap(options, used, uv);
  return {};
}

/// The unknowns of a fixed-boundary map (one per vertex, u and v as two
/// columns) and the solves over them.
struct FixedBoundarySystem
{
  const MeshTopology& Topology;
  const double* Points;
  int Threads;
  std::vector<std::uint8_t> Kind;
  Eigen::MatrixXd Fixed;
  std::vector<int> FixedList;
  std::vector<Index> FreeList;
  std::vector<Index> Order;
  std::vector<ConstraintRow> Constraints;

  FixedBoundarySystem(const MeshTopology& topo, const double* points, int threads, const std::vector<std::uint8_t>& used)
    : Topology(topo)
    , Points(points)
    , Threads(threads)
    , Kind(topo.NumberOfVertices(), KindFactor)
    , Fixed(Eigen::MatrixXd::Zero(topo.NumberOfVertices(), 2))
  {
    for (Index v = 0; v < topo.NumberOfVertices(); ++v)
    {
      if (!used[v])
      {
        Kind[v] = KindUnused;
      }
    }
  }

  void Fix(Index v, double u, double w)
  {
    Kind[v] = KindFixed;
    Fixed(v, 0) = u;
    Fixed(v, 1) = w;
    FixedList.push_back(v);
  }

  /// Fixes the boundary (given positions on every loop, or the outer loop on
  /// a circle or square); an error message, or empty.
  std::string FixBoundary(const ParameterizationOptions& options, const std::vector<std::vector<Index>>& loops,
    const std::vector<Index>& outer)
  {
    if (options.Boundary == ParameterizationBoundary::Given)
    {
      if (!options.GivenUV)
      {
        return "Given boundary positions were requested but none were supplied.";
      }
      for (const auto& loop : loops)
      {
        for (Index v : loop)
        {
          const double u = options.GivenUV[2 * v], w = options.GivenUV[2 * v + 1];
          if (!std::isfinite(u) || !std::isfinite(w))
          {
            return "The given boundary position of point " + std::to_string(v) + " is not finite.";
          }
          Fix(v, u, w);
        }
      }
    }
    else
    {
      if (options.Boundary == ParameterizationBoundary::Square && outer.size() < 4)
      {
        return "A square boundary needs at least 4 boundary points.";
      }
      std::vector<double> placed(2 * static_cast<std::size_t>(Topology.NumberOfVertices()), 0.0);
      PlaceBoundaryLoop(outer, Points, options.Boundary, options.Spacing, placed.data());
      for (Index v : outer)
      {
        Fix(v, placed[2 * v], placed[2 * v + 1]);
      }
    }
    for (Index v = 0; v < Topology.NumberOfVertices(); ++v)
    {
      if (Kind[v] == KindFactor)
      {
        FreeList.push_back(v);
      }
    }
    AddConstraintRows(options, false, Constraints);
    return {};
  }

  /// One solve of the energy lambda E_A + mu E_chi into `out` (2 per
  /// vertex); with `responses`, also its impulse responses (section 5.4.2).
  bool Solve(double lambda, double mu, std::vector<double>& out, Eigen::MatrixXd* responses,
    ParameterizationResult& result, std::string& error)
  {
    Index degenerate = 0;
    const RowMatrix rows = VertexSystem(Topology, Points, lambda, mu, Threads, degenerate);
    result.DegenerateTriangles = degenerate;
    ParameterizationSolver solver;
    Eigen::MatrixXd solution = Fixed;
    if (Order.empty())
    {
      Order = VertexOrder(Topology, Points, Threads);
    }
    if (!solver.Setup(rows, Kind, Fixed, mu == 0.0, Order, false, Threads, error) ||
      !solver.Solve(Constraints, solution, error))
    {
      return false;
    }
    const Index n = Topology.NumberOfVertices();
    out.assign(2 * static_cast<std::size_t>(n), 0.0);
    for (Index v = 0; v < n; ++v)
    {
      out[2 * v] = solution(v, 0);
      out[2 * v + 1] = solution(v, 1);
    }
    if (responses)
    {
      *responses = solver.ImpulseResponses(rows, FixedList);
    }
    return true;
  }

  /// Section 5.5.1: the conformal and authalic maps, blended by the l of
  /// the search range that minimises the chosen energy (and so are their
  /// impulse responses, eq. 5.8, if asked for).
  bool SolveOptimalMix(const ParameterizationOptions& options, std::vector<double>& uv, Eigen::MatrixXd* responses,
    ParameterizationResult& result, std::string& error)
  {
    std::vector<double> uvA, uvX;
    Eigen::MatrixXd responsesX;
    if (!Solve(1.0, 0.0, uvA, responses, result, error) ||
      !Solve(0.0, 1.0, uvX, responses ? &responsesX : nullptr, result, error))
    {
      return false;
    }
    const double a3 = TotalArea3D(Topology, Points, Threads), a2 = TotalArea2D(Topology, uvA.data(), Threads);
    const double s = a2 > 0.0 ? std::sqrt(a3 / a2) : 1.0;
    const std::vector<double> poly =
      MixEnergyPolynomial(Topology, Points, uvA.data(), uvX.data(), s, options.OptimalEnergy);
    const double l = MinimizePolynomial(poly, options.OptimalRange[0], options.OptimalRange[1]);
    result.OptimalMix = l;
    for (std::size_t k = 0; k < uv.size(); ++k)
    {
      uv[k] = l * uvA[k] + (1.0 - l) * uvX[k];
    }
    if (responses)
    {
      *responses = l * *responses + (1.0 - l) * responsesX;
    }
    return true;
  }
};

/// A map with a fixed boundary (section 5.3), optionally the optimal mix
/// (5.5.1), the boundary basis and boundary optimisation (5.5.2).  An error
/// message, or empty with `uv` set.
std::string MapFixedBoundary(const MeshTopology& topo, const double* points, const ParameterizationOptions& options,
  const std::vector<std::vector<Index>>& loops, const std::vector<std::uint8_t>& used, int threads,
  ParameterizationResult& result, std::vector<double>& uv)
{
  FixedBoundarySystem system(topo, points, threads, used);
  std::string error = system.FixBoundary(options, loops, result.OuterBoundary);
  if (!error.empty())
  {
    return error;
  }
  const bool wantBasis = options.KeepBoundaryBasis || options.BoundaryOptimizationSteps > 0;
  const double basisBytes = 8.0 * system.FreeList.size() * system.FixedList.size();
  if (wantBasis && basisBytes > options.MaximumBasisBytes)
  {
    std::ostringstream os;
    os << "The boundary basis would need " << basisBytes / (1 << 20) << " MiB (" << system.FreeList.size()
       << " free x " << system.FixedList.size() << " boundary points), more than the limit of "
       << options.MaximumBasisBytes / (1 << 20) << " MiB.";
    return os.str();
  }
  Eigen::MatrixXd responses;
  Eigen::MatrixXd* wanted = wantBasis ? &responses : nullptr;
  const bool solved = options.OptimizeMix
    ? system.SolveOptimalMix(options, uv, wanted, result, error)
    : system.Solve(options.ConformalWeight, options.AuthalicWeight, uv, wanted, result, error);
  if (!solved)
  {
    return "Cannot parameterize: " + error + ".";
  }
  const Index n = topo.NumberOfVertices();
  std::unique_ptr<BoundaryBasis> basis;
  if (wantBasis)
  {
    basis = std::make_unique<BoundaryBasis>(n,
      std::vector<Index>(system.FixedList.begin(), system.FixedList.end()), std::move(system.FreeList),
      std::vector<double>(responses.data(), responses.data() + responses.size()));
  }
  for (Index v = 0; v < n; ++v)
  {
    if (!used[v])
    {
      uv[2 * v] = uv[2 * v + 1] = 0.0;
    }
  }
  if (basis && options.BoundaryOptimizationSteps > 0)
  {
    OptimizeBoundary(topo, points, *basis, options, uv, result);
  }
  if (options.KeepBoundaryBasis)
  {
    result.Basis = std::move(basis);
  }
  return {};
}

ParameterizationResult ParameterizeUnguarded(
  const MeshTopology& topo, const double* points, const ParameterizationOptions& options)
{
  std::vector<std::uint8_t> used;
  std::string error = CheckInput(topo, points, options, used);
  if (!error.empty())
  {
    return Fail(error);
  }
  const int threads = ResolveThreadCount(options.NumberOfThreads);
  ParameterizationResult result;
  const std::vector<std::vector<Index>> loops = topo.BoundaryLoops();
  result.OuterBoundary = loops[LongestLoop(loops, points)];
  std::vector<double> uv(2 * static_cast<std::size_t>(topo.NumberOfVertices()), 0.0);
  error = options.Boundary == ParameterizationBoundary::Natural
    ? MapNatural(topo, points, options, loops, used, threads, result, uv)
    : MapFixedBoundary(topo, points, options, loops, used, threads, result, uv);
  if (!error.empty())
  {
    return Fail(error);
  }
  for (double value : uv)
  {
    if (!std::isfinite(value))
    {
      return Fail("Cannot parameterize: the solution is not finite (degenerate triangles?).");
    }
  }
  if (result.DegenerateTriangles)
  {
    AppendWarning(result.Warning, std::to_string(result.DegenerateTriangles) +
        " zero-area triangles were left out of the energy");
  }
  result.UV = std::move(uv);
  result.Success = true;
  return result;
}

} // namespace

} // namespace beltrami
