// The linear solvers of the core (Filters/Core/Solvers): conjugate
// gradients, the graph solvers, the sparse factorizations and their orders.
#include "TestMeshes.h"

#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Mesh/Laplacian.h"
#include "Solvers/NestedDissection.h"
#include "Solvers/SparseFactorization.h"
#include "Solvers/SupernodalLU.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <random>
#include <tuple>

using namespace beltrami;

namespace
{

/// The implicit curvature-flow system of a torus: (M + dt S) X' = M X, with
/// some fixed rows (a band of vertices).
struct FlowSystem
{
  test::Mesh Mesh;
  GraphLaplacian L;
  std::vector<double> Shift, B;
  std::vector<std::uint8_t> Fixed;
  double TimeStep = 0.0;

  explicit FlowSystem(int nu = 120, int nv = 80)
    : Mesh(test::Torus(2.0, 0.7, nu, nv, 0.2, 5))
  {
    const MeshTopology topo = Mesh.Topology();
    AssembleSurfaceLaplacian(topo, Mesh.Points.data(), LaplacianWeights::Cotangent, L, 2);
    test::KeepGraph(L, Offsets, Neighbors);
    const Index n = L.NumberOfVertices;
    TimeStep = 10.0 * 0.1 * 0.1;
    Shift.assign(L.Mass.begin(), L.Mass.end());
    Fixed.assign(n, 0);
    for (Index i = 0; i < n; i += 37)
    {
      Fixed[i] = 1;
    }
    B.resize(3 * static_cast<std::size_t>(n));
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        B[3 * i + c] = Shift[i] * Mesh.Points[3 * i + c];
      }
    }
  }

  ShiftedLaplacianProblem Problem(int columns, double tolerance, int threads) const
  {
    ShiftedLaplacianProblem pb = L.Problem(columns);
    pb.Shift = Shift.data();
    pb.Factor = TimeStep;
    pb.Fixed = Fixed.data();
    pb.Scale.assign(columns, 1.0);
    pb.Tolerance = tolerance;
    pb.MaximumIterations = 5000;
    pb.NumberOfThreads = threads;
    return pb;
  }

  /// ||b - A x|| over the free rows, per column, and the reference solve of
  /// the general solver.
  std::vector<double> Residual(const double* b, const double* x, int nc) const
  {
    std::vector<double> norms(nc, 0.0);
    for (Index i = 0; i < L.NumberOfVertices; ++i)
    {
      if (Fixed[i])
      {
        continue;
      }
      for (int c = 0; c < nc; ++c)
      {
        double y = (Shift[i] + TimeStep * L.Diagonal[i]) * x[i * nc + c];
        for (std::int64_t k = L.Offsets[i]; k < L.Offsets[i + 1]; ++k)
        {
          y -= TimeStep * L.Weights[k] * x[L.Neighbors[k] * static_cast<std::int64_t>(nc) + c];
        }
        norms[c] += (b[i * nc + c] - y) * (b[i * nc + c] - y);
      }
    }
    for (double& v : norms)
    {
      v = std::sqrt(v);
    }
    return norms;
  }

  std::vector<std::int64_t> Offsets;
  std::vector<Index> Neighbors;
};

/// Right-hand sides with nc columns (the positions, then random data).
std::vector<double> Columns(const FlowSystem& s, int nc, std::vector<double>* x0)
{
  const Index n = s.L.NumberOfVertices;
  std::vector<double> b(static_cast<std::size_t>(n) * nc);
  x0->resize(b.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < nc; ++c)
    {
      const double value = c < 3 ? s.Mesh.Points[3 * i + c] : u(rng);
      (*x0)[i * nc + c] = value;
      b[i * nc + c] = s.Shift[i] * value;
    }
  }
  return b;
}

/// A solve from x0 meets the tolerance (residuals res against r0 per
/// column), is near the exact solution (within `margin` times the
/// tolerance relative to the change: the residual bounds the error only
/// through the conditioning), and kept the fixed rows bit for bit.
void ExpectSolved(const FlowSystem& s, int nc, double tolerance, const std::vector<double>& x0,
  const std::vector<double>& exact, const std::vector<double>& x, const std::vector<double>& r0,
  const std::vector<double>& res, double margin = 100.0)
{
  for (int c = 0; c < nc; ++c)
  {
    EXPECT_LE(res[c], tolerance * r0[c] * 1.0000001) << "column " << c;
  }
  double change = 0.0, error = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    change = std::max(change, std::abs(exact[k] - x0[k]));
    error = std::max(error, std::abs(x[k] - exact[k]));
    if (s.Fixed[k / nc])
    {
      ASSERT_EQ(x[k], x0[k]) << "fixed rows keep their values bit for bit";
    }
  }
  EXPECT_LT(error, margin * tolerance * change) << nc << " columns, tolerance " << tolerance;
}

} // namespace

TEST(Solvers, CoupledColumnsSolveAnOperatorThatMixesThem)
{
  // A = L (x) I + I (x) C: a shifted path Laplacian on each of 3 columns,
  // plus a coupling of a row's values (C symmetric positive definite), so
  // that one CG over all 3n values is the right method; rows 0 and n-1
  // fixed.  With CoupledColumns the solve meets the tolerance on the whole
  // vector and the fixed rows keep their values.
  const Index n = 200;
  const double C[3][3] = { { 1.0, 0.6, 0.3 }, { 0.6, 1.0, 0.6 }, { 0.3, 0.6, 1.0 } };
  const auto apply = [&](const double* x, double* y) {
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        double v = 2.1 * x[3 * i + c];
        v -= i > 0 ? x[3 * (i - 1) + c] : 0.0;
        v -= i + 1 < n ? x[3 * (i + 1) + c] : 0.0;
        for (int d = 0; d < 3; ++d)
        {
          v += C[c][d] * x[3 * i + d];
        }
        y[3 * i + c] = v;
      }
    }
  };
  std::vector<double> b(3 * n), x(3 * n, 0.0), diag(n, 3.1);
  std::vector<std::uint8_t> fixed(n, 0);
  fixed[0] = fixed[n - 1] = 1;
  for (Index i = 0; i < 3 * n; ++i)
  {
    b[i] = std::sin(0.37 * i) + 0.2 * std::cos(1.3 * i);
  }
  x[0] = 1.0, x[3 * n - 1] = -2.0;
  ConjugateGradientProblem pb;
  pb.Rows = n;
  pb.Columns = 3;
  pb.CoupledColumns = true;
  pb.Apply = apply;
  pb.Diagonal = diag.data();
  pb.Fixed = fixed.data();
  pb.Scale.assign(3, 1.0);
  pb.Tolerance = 1e-10;
  const ConjugateGradientResult r = SolveConjugateGradient(pb, b.data(), x.data());
  EXPECT_TRUE(r.Converged);
  std::vector<double> ax(3 * n);
  apply(x.data(), ax.data());
  double residual = 0.0, norm = 0.0;
  for (Index i = 3; i < 3 * (n - 1); ++i) // the free rows
  {
    residual += (ax[i] - b[i]) * (ax[i] - b[i]);
    norm += b[i] * b[i];
  }
  EXPECT_LT(std::sqrt(residual / norm), 1e-9) << r.Iterations << " iterations";
  EXPECT_EQ(x[0], 1.0);
  EXPECT_EQ(x[3 * n - 1], -2.0);
}

TEST(Solvers, LocalityOrderIsAPermutationOverComponents)
{
  // Two separate triangles, an isolated vertex, and a path.
  const std::vector<std::int64_t> offsets = { 0, 2, 4, 6, 6, 8, 10, 12, 13, 14 };
  const std::vector<Index> neighbors = { 1, 2, 0, 2, 0, 1, 5, 6, 4, 6, 4, 5, 8, 7 };
  // rows: 0-1-2 triangle, 3 isolated, 4-5-6 triangle, 7-8 edge
  const std::vector<Index> order = LocalityOrder(9, offsets.data(), neighbors.data());
  ASSERT_EQ(order.size(), 9u);
  std::vector<Index> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (Index i = 0; i < 9; ++i)
  {
    EXPECT_EQ(sorted[i], i);
  }
  // Breadth first: each component is contiguous.
  EXPECT_EQ(order[3], 3);
  EXPECT_EQ(std::max({ order[0], order[1], order[2] }), 2);
}

/// Nonzeros of the Cholesky factor of a matrix with the pattern of the graph
/// (diagonal included) eliminated in `order`: each column's pattern is its
/// later neighbours and its elimination-tree children's patterns.
std::int64_t CholeskyFill(const std::vector<std::int64_t>& offsets, const std::vector<Index>& neighbors,
  const std::vector<Index>& order)
{
  const std::size_t n = order.size();
  std::vector<Index> position(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    position[order[k]] = static_cast<Index>(k);
  }
  std::vector<std::vector<Index>> children(n), pattern(n);
  std::int64_t fill = 0;
  for (std::size_t k = 0; k < n; ++k)
  {
    std::vector<Index> column;
    const Index v = order[k];
    for (std::int64_t e = offsets[v]; e < offsets[v + 1]; ++e)
    {
      if (position[neighbors[e]] > static_cast<Index>(k))
      {
        column.push_back(position[neighbors[e]]);
      }
    }
    for (Index c : children[k])
    {
      for (Index r : pattern[c])
      {
        if (r != static_cast<Index>(k))
        {
          column.push_back(r);
        }
      }
      pattern[c].clear();
      pattern[c].shrink_to_fit();
    }
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    fill += 1 + static_cast<std::int64_t>(column.size());
    if (!column.empty())
    {
      children[column.front()].push_back(static_cast<Index>(k));
    }
    pattern[k] = std::move(column);
  }
  return fill;
}

TEST(Solvers, NestedDissectionOrderCutsTheFill)
{
  // A 64 x 64 jittered grid: eliminated row by row, the factor fills the band
  // (~n^1.5 = 262k nonzeros); nested dissection needs O(n log n).
  const int side = 64;
  const test::Mesh m = test::HeightField([](double x, double y) { return 0.3 * x * y; }, 1.0, side, 0.2, true, 3);
  const MeshTopology topo = m.Topology();
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index n = topo.NumberOfVertices();
  const std::vector<std::int64_t> offsets(edges.NeighborOffsets.begin(), edges.NeighborOffsets.end());
  const std::vector<Index> neighbors(edges.Neighbors.begin(), edges.Neighbors.end());
  std::vector<Index> rowByRow(n);
  std::iota(rowByRow.begin(), rowByRow.end(), 0);
  const std::int64_t banded = CholeskyFill(offsets, neighbors, rowByRow);
  for (int threads : { 1, 2 })
  {
    const std::vector<Index> order =
      NestedDissectionOrder(n, offsets.data(), neighbors.data(), m.Points.data(), threads);
    std::vector<Index> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    ASSERT_EQ(sorted, rowByRow); // a permutation
    const std::int64_t fill = CholeskyFill(offsets, neighbors, order);
    EXPECT_LT(fill, banded / 2) << "banded " << banded;
    EXPECT_EQ(order, NestedDissectionOrder(n, offsets.data(), neighbors.data(), m.Points.data(), 1));
  }
  // Coincident or NaN positions still give a permutation.
  std::vector<double> flat(m.Points.size(), 1.0);
  for (std::size_t i = 0; i < flat.size(); i += 7)
  {
    flat[i] = std::nan("");
  }
  std::vector<Index> order = NestedDissectionOrder(n, offsets.data(), neighbors.data(), flat.data(), 2);
  std::sort(order.begin(), order.end());
  EXPECT_EQ(order, rowByRow);
}

TEST(Solvers, NestedDissectionEliminatesAFansApexLast)
{
  // A double cone of two fans of 4,000 triangles: the apexes are joined to
  // every ring point. With an apex on one side of a split every point of
  // the other side touched it and became a separator point: a dense block
  // of half the ring (2,000^2 / 2 fill; 6 s for 20,000 points). Dense rows
  // come last: the fill stays linear.
  const Index ring = 4000, n = ring + 2;
  std::vector<double> points;
  for (Index i = 0; i < ring; ++i)
  {
    const double a = 2.0 * M_PI * i / ring;
    points.insert(points.end(), { std::cos(a), std::sin(a), 0.0 });
  }
  points.insert(points.end(), { 0.0, 0.0, 1.0, 0.0, 0.0, -1.0 });
  std::vector<std::vector<Index>> adjacent(n);
  for (Index i = 0; i < ring; ++i)
  {
    for (const Index j : { (i + 1) % ring, ring, ring + 1 })
    {
      adjacent[i].push_back(j);
      adjacent[j].push_back(i);
    }
  }
  std::vector<std::int64_t> offsets(1, 0);
  std::vector<Index> neighbors;
  for (std::vector<Index>& a : adjacent)
  {
    std::sort(a.begin(), a.end());
    neighbors.insert(neighbors.end(), a.begin(), a.end());
    offsets.push_back(static_cast<std::int64_t>(neighbors.size()));
  }
  const std::vector<Index> order = NestedDissectionOrder(n, offsets.data(), neighbors.data(), points.data(), 2);
  EXPECT_EQ(order[n - 2], ring);
  EXPECT_EQ(order[n - 1], ring + 1);
  const std::int64_t fill = CholeskyFill(offsets, neighbors, order);
  std::printf("double cone of %d points: factor fill %lld\n", static_cast<int>(n), static_cast<long long>(fill));
  EXPECT_LT(fill, 20 * static_cast<std::int64_t>(n));
}

TEST(Solvers, SparseFactorizationSolvesEveryKindOfSystem)
{
  // The Dirichlet Laplacian of a grid (+ a shift): symmetric positive
  // definite; then made indefinite, then non-symmetric, then singular.
  const int side = 30, n = side * side;
  const auto build = [&](double shift, double skew) {
    std::vector<Eigen::Triplet<double, int>> t;
    for (int i = 0; i < side; ++i)
    {
      for (int j = 0; j < side; ++j)
      {
        const int r = i * side + j;
        t.emplace_back(r, r, 4.0 + shift);
        const int next[4][2] = { { i - 1, j }, { i + 1, j }, { i, j - 1 }, { i, j + 1 } };
        for (const auto& q : next)
        {
          if (q[0] >= 0 && q[0] < side && q[1] >= 0 && q[1] < side)
          {
            const int c = q[0] * side + q[1];
            t.emplace_back(r, c, -1.0 + (c > r ? skew : -skew));
          }
        }
      }
    }
    SparseFactorization::Matrix a(n, n);
    a.setFromTriplets(t.begin(), t.end());
    return a;
  };
  std::vector<int> order(n);
  std::iota(order.rbegin(), order.rend(), 0); // any permutation
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, 2);
  struct Case
  {
    double Shift, Skew;
    bool Symmetric;
  };
  for (const Case c : { Case{ 0.0, 0.0, true }, Case{ -3.0, 0.0, true }, Case{ 0.1, 0.3, false } })
  {
    const SparseFactorization::Matrix a = build(c.Shift, c.Skew);
    for (bool ordered : { false, true })
    {
      SparseFactorization f;
      ASSERT_TRUE(f.Compute(a, c.Symmetric, ordered ? order : std::vector<int>{}));
      const Eigen::MatrixXd x = f.Solve(b);
      EXPECT_LT((a * x - b).norm(), 1e-9 * b.norm()) << c.Shift << " " << c.Skew;
    }
  }
  // Singular: the Neumann Laplacian (rows summing to zero).
  SparseFactorization::Matrix singular = build(0.0, 0.0);
  for (int k = 0; k < singular.outerSize(); ++k)
  {
    double sum = 0.0;
    for (SparseFactorization::Matrix::InnerIterator it(singular, k); it; ++it)
    {
      sum += it.row() != k ? it.value() : 0.0;
    }
    singular.coeffRef(k, k) = -sum;
  }
  SparseFactorization f;
  EXPECT_FALSE(f.Compute(singular, true));
}

namespace
{

/// A convection-diffusion operator on a side x side grid (non-symmetric, with
/// a symmetric pattern), `perNode` unknowns per node (unknown perNode * node
/// + d, the copies uncoupled), and the nested-dissection order of the grid's
/// nodes.
struct ConvectionDiffusion
{
  SparseFactorization::Matrix A;
  std::vector<int> NodeOrder;

  ConvectionDiffusion(int side, int perNode, double wind)
  {
    const int n = side * side;
    std::vector<Eigen::Triplet<double, int>> t;
    std::vector<std::int64_t> offsets(1, 0);
    std::vector<Index> neighbors;
    std::vector<double> points;
    for (int i = 0; i < side; ++i)
    {
      for (int j = 0; j < side; ++j)
      {
        const int r = i * side + j;
        points.insert(points.end(), { double(j), double(i), 0.0 });
        const int next[4][2] = { { i - 1, j }, { i + 1, j }, { i, j - 1 }, { i, j + 1 } };
        for (int d = 0; d < perNode; ++d)
        {
          t.emplace_back(perNode * r + d, perNode * r + d, 4.01);
        }
        for (const auto& q : next)
        {
          if (q[0] >= 0 && q[0] < side && q[1] >= 0 && q[1] < side)
          {
            const int c = q[0] * side + q[1];
            neighbors.push_back(c);
            for (int d = 0; d < perNode; ++d)
            {
              t.emplace_back(perNode * r + d, perNode * c + d, -1.0 + (c > r ? wind : -wind));
            }
          }
        }
        offsets.push_back(static_cast<std::int64_t>(neighbors.size()));
      }
    }
    A.resize(perNode * n, perNode * n);
    A.setFromTriplets(t.begin(), t.end());
    const std::vector<Index> order = NestedDissectionOrder(n, offsets.data(), neighbors.data(), points.data(), 2);
    NodeOrder.assign(order.begin(), order.end());
  }

  SupernodalLU::MatrixView View() const
  {
    return { A.rows(), A.cols(), A.nonZeros(), A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr() };
  }
};

} // namespace

TEST(Solvers, SupernodalLUSolvesNonSymmetricSystems)
{
  const ConvectionDiffusion system(90, 1, 0.4);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(system.A.rows(), 3);
  Eigen::MatrixXd serial;
  for (int threads : { 1, 2, 3 })
  {
    SupernodalLU lu;
    ASSERT_TRUE(lu.Compute(system.View(), system.NodeOrder, threads));
    EXPECT_GT(lu.PivotRatio(), 1e-3);
    EXPECT_LE(lu.PivotRatio(), 1.0);
    Eigen::MatrixXd x = b;
    lu.Solve(x);
    EXPECT_LT((system.A * x - b).norm(), 1e-12 * b.norm()) << threads;
    if (threads == 1)
    {
      serial = x;
    }
    EXPECT_LT((x - serial).norm(), 1e-12 * serial.norm()) << threads; // the same factors, summed in another order
  }
  {
    std::vector<int> reversed(system.A.rows());
    std::iota(reversed.rbegin(), reversed.rend(), 0);
    SupernodalLU lu2;
    EXPECT_TRUE(lu2.Compute(system.View(), reversed, 2));
  }
  // A wrong-sized order is refused.
  SupernodalLU lu;
  EXPECT_FALSE(lu.Compute(system.View(), std::vector<int>(5, 0)));
}

TEST(Solvers, SupernodalCholeskyKeepsTheOrderWhenAsked)
{
  // The grid's nested-dissection order (postordered by the analysis, or kept
  // as given), the same with the border nodes last (the twin pairs' order,
  // not a postorder), and a random order of a smaller grid.
  const int side = 90;
  const ConvectionDiffusion system(side, 1, 0.0), small(30, 1, 0.0);
  std::vector<int> borderLast = system.NodeOrder;
  std::stable_partition(borderLast.begin(), borderLast.end(), [&](int node) {
    const int i = node / side, j = node % side;
    return i > 0 && j > 0 && i < side - 1 && j < side - 1;
  });
  std::vector<int> shuffled = small.NodeOrder;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
  struct Case
  {
    const ConvectionDiffusion& System;
    std::vector<int> Order;
    bool Keep;
  };
  for (const Case& c : { Case{ system, system.NodeOrder, false }, Case{ system, system.NodeOrder, true },
         Case{ system, borderLast, true }, Case{ small, shuffled, true } })
  {
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(c.System.A.rows(), 3);
    for (int threads : { 1, 2 })
    {
      SupernodalLU f;
      ASSERT_TRUE(f.Compute(c.System.View(), c.Order, threads, true, c.Keep));
      Eigen::MatrixXd x = b;
      f.Solve(x);
      EXPECT_LT((c.System.A * x - b).norm(), 1e-12 * b.norm()) << c.Keep << " " << threads;
      if (c.Keep)
      {
        EXPECT_EQ(f.Order(), c.Order);
      }
      EXPECT_GT(f.PivotRatio(), 1e-6);
    }
  }
  // Not positive definite: refused.
  SparseFactorization::Matrix indefinite = system.A;
  indefinite.coeffRef(5, 5) = -1.0;
  const SupernodalLU::MatrixView view(indefinite.rows(), indefinite.cols(), indefinite.nonZeros(),
    indefinite.outerIndexPtr(), indefinite.innerIndexPtr(), indefinite.valuePtr());
  SupernodalLU f;
  EXPECT_FALSE(f.Compute(view, system.NodeOrder, 2, true));
}

TEST(Solvers, SupernodalLUPivotsWithinSupernodesOnly)
{
  // Pairs (2r, 2r+1) whose first diagonal entry is zero, each coupled to a
  // last "hub" unknown: every pair is a supernode with the hub below it, and
  // the LU must exchange its two rows (in L, in U's columns and in the solve).
  const int pairs = 30, n = 2 * pairs + 1, hub = n - 1;
  std::vector<Eigen::Triplet<double, int>> t;
  for (int r = 0; r < pairs; ++r)
  {
    const int u = 2 * r, v = 2 * r + 1;
    for (const auto& [row, column, value] : { std::make_tuple(u, v, 2.0), std::make_tuple(v, u, 1.0 + 0.01 * r),
           std::make_tuple(v, v, 3.0), std::make_tuple(u, hub, 0.5), std::make_tuple(hub, v, 0.25),
           std::make_tuple(hub, u, -0.1), std::make_tuple(v, hub, 0.2) })
    {
      t.emplace_back(row, column, value);
    }
  }
  t.emplace_back(hub, hub, 10.0);
  SparseFactorization::Matrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  const SupernodalLU::MatrixView view(a.rows(), a.cols(), a.nonZeros(), a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, 2);
  SupernodalLU lu;
  ASSERT_TRUE(lu.Compute(view, order, 2));
  Eigen::MatrixXd x = b;
  lu.Solve(x);
  EXPECT_LT((a * x - b).norm(), 1e-13 * b.norm());

  // Two unknowns per grid node with their rows exchanged: every diagonal
  // entry is zero.  Eliminated evens first, no exchange inside a supernode
  // helps and the LU fails; SparseFactorization then takes UMFPACK's LU
  // (pivoting anywhere), in either order.
  ConvectionDiffusion system(40, 2, 0.3);
  SparseFactorization::Matrix exchange(system.A.rows(), system.A.cols());
  for (int k = 0; k < exchange.rows(); ++k)
  {
    exchange.insert(k ^ 1, k) = 1.0;
  }
  const SparseFactorization::Matrix swapped = exchange * system.A;
  for (int k = 0; k < swapped.rows(); ++k)
  {
    ASSERT_EQ(swapped.coeff(k, k), 0.0);
  }
  std::vector<int> pairsTogether, evensFirst;
  for (int node : system.NodeOrder)
  {
    pairsTogether.insert(pairsTogether.end(), { 2 * node, 2 * node + 1 });
  }
  for (int parity : { 0, 1 })
  {
    for (int node : system.NodeOrder)
    {
      evensFirst.push_back(2 * node + parity);
    }
  }
  const SupernodalLU::MatrixView swappedView(swapped.rows(), swapped.cols(), swapped.nonZeros(),
    swapped.outerIndexPtr(), swapped.innerIndexPtr(), swapped.valuePtr());
  EXPECT_FALSE(lu.Compute(swappedView, evensFirst, 2));
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(swapped.rows(), 2);
  for (const std::vector<int>& o : { pairsTogether, evensFirst })
  {
    SparseFactorization f;
    ASSERT_TRUE(f.Compute(swapped, false, o));
    EXPECT_LT((swapped * f.Solve(c) - c).norm(), 1e-10 * c.norm());
  }
}

TEST(Solvers, SparseFactorizationTwinPairs)
{
  // A = I_2 (x) L + C, L a shifted grid Laplacian, C coupling the u of each
  // border node with the v of the next one around the border (the shape of
  // the natural conformal map's system).
  const int side = 20, pairs = side * side;
  std::vector<int> border;
  for (int j = 0; j < side - 1; ++j) border.push_back(j);                          // bottom
  for (int i = 0; i < side - 1; ++i) border.push_back(i * side + side - 1);        // right
  for (int j = side - 1; j > 0; --j) border.push_back((side - 1) * side + j);      // top
  for (int i = side - 1; i > 0; --i) border.push_back(i * side);                   // left
  const auto build = [&](double coupling, double oddShift) {
    std::vector<Eigen::Triplet<double, int>> t;
    for (int i = 0; i < side; ++i)
    {
      for (int j = 0; j < side; ++j)
      {
        const int r = i * side + j;
        for (int d = 0; d < 2; ++d)
        {
          t.emplace_back(2 * r + d, 2 * r + d, 5.0 + (d == 1 && r == 7 ? oddShift : 0.0));
          const int next[4][2] = { { i - 1, j }, { i + 1, j }, { i, j - 1 }, { i, j + 1 } };
          for (const auto& q : next)
          {
            if (q[0] >= 0 && q[0] < side && q[1] >= 0 && q[1] < side)
            {
              t.emplace_back(2 * r + d, 2 * (q[0] * side + q[1]) + d, -1.0);
            }
          }
        }
      }
    }
    for (std::size_t k = 0; coupling != 0.0 && k < border.size(); ++k)
    {
      const int a = border[k], b = border[(k + 1) % border.size()];
      for (const auto& [row, column, value] : { std::make_tuple(2 * a, 2 * b + 1, -coupling),
             std::make_tuple(2 * a + 1, 2 * b, coupling) })
      {
        t.emplace_back(row, column, value);
        t.emplace_back(column, row, value);
      }
    }
    SparseFactorization::Matrix a(2 * pairs, 2 * pairs);
    a.setFromTriplets(t.begin(), t.end());
    return a;
  };
  std::vector<int> order(2 * pairs);
  std::iota(order.begin(), order.end(), 0);
  std::reverse(order.begin(), order.end());
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(2 * pairs, 3);
  struct Case
  {
    double Coupling, OddShift;
    int Coupled; // expected CoupledPairs()
  };
  for (const Case c : { Case{ 0.25, 0.0, static_cast<int>(border.size()) }, Case{ 0.0, 0.0, 0 },
         Case{ 0.25, 0.5, -1 } }) // the last is not twin (u and v blocks differ): general path
  {
    const SparseFactorization::Matrix a = build(c.Coupling, c.OddShift);
    for (bool ordered : { false, true })
    {
      SparseFactorization f;
      ASSERT_TRUE(f.Compute(a, true, ordered ? order : std::vector<int>{}, true));
      EXPECT_EQ(f.CoupledPairs(), c.Coupled);
      const Eigen::MatrixXd x = f.Solve(b);
      EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm()) << c.Coupling << " " << c.OddShift;
    }
  }
}

TEST(Solvers, ShiftedLaplacianMatchesTheGeneralSolver)
{
  const FlowSystem s;
  const Index n = s.L.NumberOfVertices;
  for (int nc : { 1, 3, 5 })
  {
    std::vector<double> x0;
    const std::vector<double> b = Columns(s, nc, &x0);
    // Reference: the double-precision matrix-free solver, to round-off.
    ConjugateGradientProblem ref;
    ref.Rows = n;
    ref.Columns = nc;
    std::vector<double> diag(n);
    for (Index i = 0; i < n; ++i)
    {
      diag[i] = s.Shift[i] + s.TimeStep * s.L.Diagonal[i];
    }
    ref.Diagonal = diag.data();
    ref.Fixed = s.Fixed.data();
    ref.Scale.assign(nc, 1.0);
    ref.Tolerance = 1e-13;
    ref.MaximumIterations = 10000;
    ref.Apply = [&](const double* in, double* out) {
      s.L.ApplyStiffness(in, out, nc, 2);
      for (std::int64_t k = 0; k < static_cast<std::int64_t>(n) * nc; ++k)
      {
        out[k] = s.Shift[k / nc] * in[k] + s.TimeStep * out[k];
      }
    };
    std::vector<double> exact = x0;
    ASSERT_TRUE(SolveConjugateGradient(ref, b.data(), exact.data()).Converged);

    const std::vector<double> r0 = s.Residual(b.data(), x0.data(), nc);
    for (double tolerance : { 1e-4, 1e-10 })
    {
      for (Preconditioning m :
        { Preconditioning::Jacobi, Preconditioning::Multigrid, Preconditioning::GeometricMultigrid })
      {
        std::vector<double> x = x0;
        ShiftedLaplacianProblem pb = s.Problem(nc, tolerance, 2);
        pb.Preconditioner = m;
        pb.Points = s.Mesh.Points.data();
        const ConjugateGradientResult r = SolveShiftedLaplacian(pb, b.data(), x.data());
        EXPECT_TRUE(r.Converged) << nc << " columns, tolerance " << tolerance;
        EXPECT_LE(r.RelativeResidual, tolerance);
        // The true (double) residual meets the tolerance, also far below
        // single precision (iterative refinement).
        const std::vector<double> res = s.Residual(b.data(), x.data(), nc);
        ExpectSolved(s, nc, tolerance, x0, exact, x, r0, res);
        // Thread counts do not change a bit.
        for (int threads : { 1, 3 })
        {
          std::vector<double> y = x0;
          pb.NumberOfThreads = threads;
          SolveShiftedLaplacian(pb, b.data(), y.data());
          ASSERT_EQ(y, x) << threads << " threads";
        }
      }
    }
  }
}

TEST(Solvers, SquaredLaplacianMatchesTheGeneralSolver)
{
  // The order-2 step (D + t S N S) X' = D X, N = D^-1 off the fixed rows, on
  // a jittered torus (obtuse triangles: some weights negative), against the
  // matrix-free CG on the same operator.
  const FlowSystem s;
  const Index n = s.L.NumberOfVertices;
  const double t = s.TimeStep * s.TimeStep;
  std::vector<double> inner(n);
  std::vector<double> diag(n);
  for (Index i = 0; i < n; ++i)
  {
    inner[i] = s.Fixed[i] ? 0.0 : 1.0 / s.Shift[i];
  }
  for (Index i = 0; i < n; ++i)
  {
    double s2 = s.L.Diagonal[i] * s.L.Diagonal[i] * inner[i];
    for (std::int64_t k = s.L.Offsets[i]; k < s.L.Offsets[i + 1]; ++k)
    {
      s2 += s.L.Weights[k] * s.L.Weights[k] * inner[s.L.Neighbors[k]];
    }
    diag[i] = s.Shift[i] + t * s2;
  }
  for (int nc : { 1, 3, 4 })
  {
    std::vector<double> x0;
    const std::vector<double> b = Columns(s, nc, &x0);
    std::vector<double> tmp(b.size());
    const auto apply = [&](const double* in, double* out) {
      s.L.ApplyStiffness(in, tmp.data(), nc, 2);
      for (std::size_t k = 0; k < tmp.size(); ++k)
      {
        tmp[k] *= inner[k / nc];
      }
      s.L.ApplyStiffness(tmp.data(), out, nc, 2);
      for (std::size_t k = 0; k < tmp.size(); ++k)
      {
        out[k] = s.Shift[k / nc] * in[k] + t * out[k];
      }
    };
    const auto residual = [&](const std::vector<double>& x) {
      std::vector<double> ax(x.size()), norms(nc, 0.0);
      apply(x.data(), ax.data());
      for (std::size_t k = 0; k < x.size(); ++k)
      {
        norms[k % nc] += s.Fixed[k / nc] ? 0.0 : (b[k] - ax[k]) * (b[k] - ax[k]);
      }
      for (double& v : norms)
      {
        v = std::sqrt(v);
      }
      return norms;
    };
    ConjugateGradientProblem ref;
    ref.Rows = n;
    ref.Columns = nc;
    ref.Diagonal = diag.data();
    ref.Fixed = s.Fixed.data();
    ref.Scale.assign(nc, 1.0);
    ref.Tolerance = 1e-13;
    ref.MaximumIterations = 20000;
    ref.Apply = apply;
    std::vector<double> exact = x0;
    ASSERT_TRUE(SolveConjugateGradient(ref, b.data(), exact.data()).Converged);

    const std::vector<double> r0 = residual(x0);
    for (double tolerance : { 1e-4, 1e-10 })
    for (Preconditioning m :
      { Preconditioning::Jacobi, Preconditioning::Multigrid, Preconditioning::GeometricMultigrid })
    {
      ShiftedLaplacianProblem pb = s.Problem(nc, tolerance, 2);
      pb.Factor = t;
      pb.Preconditioner = m;
      pb.Points = s.Mesh.Points.data();
      std::vector<double> x = x0;
      const ConjugateGradientResult r = SolveSquaredLaplacian(pb, b.data(), x.data());
      EXPECT_TRUE(r.Converged) << nc << " columns, tolerance " << tolerance;
      EXPECT_LE(r.RelativeResidual, tolerance);
      const std::vector<double> res = residual(x);
      // COCG (Jacobi, geometric multigrid) asks its complex residual for
      // more than the real one needs; the algebraic multigrid's CG stops
      // right at the real tolerance, where the random fourth column's error
      // reaches 110 times it.
      const double margin = m == Preconditioning::Multigrid ? 300.0 : 100.0;
      ExpectSolved(s, nc, tolerance, x0, exact, x, r0, res, margin);
      for (int threads : { 1, 3 })
      {
        std::vector<double> y = x0;
        pb.NumberOfThreads = threads;
        SolveSquaredLaplacian(pb, b.data(), y.data());
        ASSERT_EQ(y, x) << threads << " threads";
      }
      if (m != Preconditioning::Multigrid) // (its CG starts at x0)
      {
        // A start near the solution, the same system's at a quarter of the
        // step: solved to the same tolerance (relative to the residual at
        // x0) in fewer iterations (at least as few to 1e-10); at the solution
        // itself in none.
        ShiftedLaplacianProblem started = pb;
        started.Factor = t / 4.0;
        std::vector<double> near = x0;
        ASSERT_TRUE(SolveSquaredLaplacian(started, b.data(), near.data()).Converged);
        started.Factor = t;
        started.Guess = near.data();
        std::vector<double> w = x0;
        const ConjugateGradientResult fromNear = SolveSquaredLaplacian(started, b.data(), w.data());
        EXPECT_TRUE(fromNear.Converged);
        EXPECT_LE(fromNear.Iterations, r.Iterations - (tolerance > 1e-6 ? 1 : 0)) << nc << " columns, tolerance "
                                                                                  << tolerance;
        ExpectSolved(s, nc, tolerance, x0, exact, w, r0, residual(w), margin);
        started.Guess = x.data();
        w = x0;
        EXPECT_EQ(SolveSquaredLaplacian(started, b.data(), w.data()).Iterations, 0);
        EXPECT_EQ(w, x);
      }
      // The rows renumbered in a given order (here the reverse one, not a
      // locality order) solve the same system, in the caller's numbering.
      std::vector<Index> reversed(n);
      std::iota(reversed.rbegin(), reversed.rend(), 0);
      pb.Order = reversed.data();
      std::vector<double> z = x0;
      EXPECT_TRUE(SolveSquaredLaplacian(pb, b.data(), z.data()).Converged);
      ExpectSolved(s, nc, tolerance, x0, exact, z, r0, residual(z), margin);
    }
  }
  // Columns beyond 4, no shift: refused.
  ShiftedLaplacianProblem bad = s.Problem(5, 1e-4, 1);
  std::vector<double> x(5 * static_cast<std::size_t>(n)), b5 = x;
  EXPECT_THROW(SolveSquaredLaplacian(bad, b5.data(), x.data()), std::invalid_argument);
  bad = s.Problem(3, 1e-4, 1);
  bad.Shift = nullptr;
  EXPECT_THROW(SolveSquaredLaplacian(bad, b5.data(), x.data()), std::invalid_argument);
}

TEST(Solvers, MultigridIterationsDoNotGrowWithTheMesh)
{
  // A physical time step (t = 1 on a torus of radii 2 and 0.7): refining the
  // mesh 4x in each direction raises the conditioning of D + t K and of
  // D + t K D^-1 K 16-fold.  Jacobi's iteration counts grow with it,
  // multigrid's stay (nearly) flat; both solve to the tolerance.
  std::vector<int> counts[2][3]; // [squared][Jacobi, algebraic, geometric multigrid]
  for (int scale : { 1, 4 })
  {
    FlowSystem s(120 * scale, 80 * scale);
    const Index n = s.L.NumberOfVertices;
    s.Fixed.assign(n, 0);
    s.TimeStep = 1.0;
    std::vector<double> x0;
    const std::vector<double> b = Columns(s, 3, &x0);
    for (int squared : { 0, 1 })
    {
      for (int m : { 0, 1, 2 })
      {
        ShiftedLaplacianProblem pb = s.Problem(3, 1e-6, 2);
        pb.Preconditioner = static_cast<Preconditioning>(m);
        pb.Points = s.Mesh.Points.data();
        pb.Factor = squared ? 0.01 : 1.0;
        pb.MaximumIterations = 20000;
        std::vector<double> x = x0;
        const ConjugateGradientResult r =
          squared ? SolveSquaredLaplacian(pb, b.data(), x.data()) : SolveShiftedLaplacian(pb, b.data(), x.data());
        EXPECT_TRUE(r.Converged) << n << " rows, squared " << squared << ", multigrid " << m;
        counts[squared][m].push_back(r.Iterations);
      }
    }
  }
  for (int squared : { 0, 1 })
  {
    const std::vector<int>& jacobi = counts[squared][0];
    EXPECT_GE(jacobi[1], 2 * jacobi[0]) << "squared " << squared << ": " << jacobi[0] << " -> " << jacobi[1];
    std::cout << (squared ? "D + t K D^-1 K" : "D + t K") << ": Jacobi " << jacobi[0] << " -> " << jacobi[1];
    for (int m : { 1, 2 })
    {
      const std::vector<int>& multigrid = counts[squared][m];
      EXPECT_LE(multigrid[1], 1.5 * multigrid[0] + 1)
        << "squared " << squared << ", " << m << ": " << multigrid[0] << " -> " << multigrid[1];
      EXPECT_LE(multigrid[1], 30);
      std::cout << (m == 1 ? ", algebraic multigrid " : ", geometric multigrid ") << multigrid[0] << " -> "
                << multigrid[1];
    }
    std::cout << " iterations\n";
  }
}

TEST(Solvers, ShiftedLaplacianHarmonicExtension)
{
  // D = 0: the discrete harmonic function with fixed values on some rows;
  // the linear function x is harmonic only where the cotangent Laplacian is
  // exact, so compare with the general solver instead.
  const FlowSystem s(30, 20);
  const Index n = s.L.NumberOfVertices;
  std::vector<double> x(n, 0.0), b(n, 0.0), ref;
  for (Index i = 0; i < n; ++i)
  {
    x[i] = s.Fixed[i] ? s.Mesh.Points[3 * i + 2] : 0.0;
  }
  ref = x;
  ConjugateGradientProblem g;
  g.Rows = n;
  g.Diagonal = s.L.Diagonal.data();
  g.Fixed = s.Fixed.data();
  g.Scale = { 1.0 };
  g.Tolerance = 1e-12;
  g.MaximumIterations = 10000;
  g.Apply = [&](const double* in, double* out) { s.L.ApplyStiffness(in, out, 1, 1); };
  ASSERT_TRUE(SolveConjugateGradient(g, b.data(), ref.data()).Converged);
  ShiftedLaplacianProblem pb = s.Problem(1, 1e-12, 2);
  pb.Shift = nullptr;
  pb.Factor = 1.0;
  ASSERT_TRUE(SolveShiftedLaplacian(pb, b.data(), x.data()).Converged);
  double worst = 0.0;
  for (Index i = 0; i < n; ++i)
  {
    worst = std::max(worst, std::abs(x[i] - ref[i]));
  }
  EXPECT_LT(worst, 1e-8);
}

TEST(Solvers, ShiftedLaplacianEdgeCases)
{
  const FlowSystem s(12, 8);
  const Index n = s.L.NumberOfVertices;
  // Already solved: nothing moves, no iteration.
  std::vector<double> x(3 * static_cast<std::size_t>(n)), b(x.size());
  ShiftedLaplacianProblem pb = s.Problem(3, 1e-6, 2);
  ConjugateGradientResult r = SolveShiftedLaplacian(pb, b.data(), x.data());
  EXPECT_TRUE(r.Converged);
  EXPECT_EQ(r.Iterations, 0);
  // Every row fixed.
  std::vector<std::uint8_t> all(n, 1);
  pb.Fixed = all.data();
  std::vector<double> y = s.Mesh.Points;
  r = SolveShiftedLaplacian(pb, s.B.data(), y.data());
  EXPECT_TRUE(r.Converged);
  EXPECT_EQ(y, s.Mesh.Points);
  // An iteration limit is reported, not exceeded.
  pb = s.Problem(3, 1e-12, 2);
  pb.MaximumIterations = 3;
  y = s.Mesh.Points;
  r = SolveShiftedLaplacian(pb, s.B.data(), y.data());
  EXPECT_FALSE(r.Converged);
  EXPECT_LE(r.Iterations, 3);
  // Inconsistent problems are refused.
  pb.Scale.clear();
  EXPECT_THROW(SolveShiftedLaplacian(pb, s.B.data(), y.data()), std::invalid_argument);
}
