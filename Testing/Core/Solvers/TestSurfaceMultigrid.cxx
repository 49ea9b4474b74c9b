// The geometric multigrid on the surface's own hierarchy
// (Solvers/SurfaceMultigrid): the hierarchy's levels, the V-cycle's
// convergence at four resolutions, and its solves against Jacobi's on real
// and irregular meshes.
#include "TestMeshes.h"

#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/SurfaceMultigrid.h"
#include "Support/DisjointSets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>
#include <string>
#include <vector>

using namespace beltrami;

namespace
{

/// M + t K of a mesh's cotangent Laplacian (t in units of h^2), its
/// graph kept (the topology's arrays copied).
struct MeshSystem
{
  test::Mesh Mesh;
  GraphLaplacian L;
  std::vector<std::int64_t> Offsets;
  std::vector<Index> Neighbors;
  std::vector<double> Mass;
  std::vector<std::uint8_t> Fixed; ///< with holdBoundary, the boundary's rows (as the fairing holds them)
  double H = 0.0;

  explicit MeshSystem(test::Mesh mesh, bool holdBoundary = false)
    : Mesh(std::move(mesh))
  {
    const MeshTopology topo = Mesh.Topology();
    AssembleSurfaceLaplacian(topo, Mesh.Points.data(), LaplacianWeights::Cotangent, L, 2);
    test::KeepGraph(L, Offsets, Neighbors);
    Mass.assign(L.Mass.begin(), L.Mass.end());
    H = MeanEdgeLength(topo, Mesh.Points.data());
    Fixed.assign(L.NumberOfVertices, 0);
    for (const std::vector<Index>& loop : holdBoundary ? topo.BoundaryLoops() : std::vector<std::vector<Index>>())
    {
      for (const Index v : loop)
      {
        Fixed[v] = 1;
      }
    }
  }

  ShiftedLaplacianProblem Problem(double step, int columns, Preconditioning m) const
  {
    ShiftedLaplacianProblem pb = L.Problem(columns);
    pb.Shift = Mass.data();
    pb.Factor = step;
    pb.Scale.assign(columns, 1.0);
    pb.Tolerance = 1e-8;
    pb.MaximumIterations = 20000;
    pb.NumberOfThreads = 2;
    pb.Preconditioner = m;
    pb.Points = Mesh.Points.data();
    pb.Fixed = Fixed.data();
    return pb;
  }

  /// r = b - (M + t K) x.
  std::vector<double> Residual(double t, const std::vector<double>& b, const std::vector<double>& x) const
  {
    std::vector<double> r(b.size());
    L.ApplyStiffness(x.data(), r.data(), 1, 2);
    for (std::size_t i = 0; i < r.size(); ++i)
    {
      r[i] = b[i] - Mass[i] * x[i] - t * r[i];
    }
    return r;
  }
};

double Norm(const std::vector<double>& v)
{
  double s = 0.0;
  for (const double x : v)
  {
    s += x * x;
  }
  return std::sqrt(s);
}

/// Connected components of a level's operator graph.
int Components(const LevelMatrix& a)
{
  std::vector<Index> parent(a.Rows());
  std::iota(parent.begin(), parent.end(), 0);
  for (Index i = 0; i < a.Rows(); ++i)
  {
    for (std::int64_t k = a.Offsets[i]; k < a.Offsets[i + 1]; ++k)
    {
      parent[FindRoot(parent, i)] = FindRoot(parent, a.Columns[k]);
    }
  }
  int count = 0;
  for (Index i = 0; i < a.Rows(); ++i)
  {
    count += FindRoot(parent, i) == i;
  }
  return count;
}

test::Mesh ReadOrFail(const std::string& name)
{
  std::string error;
  test::Mesh m = test::ReadMesh(name, error);
  EXPECT_TRUE(error.empty()) << error;
  return m;
}

} // namespace

TEST(SurfaceMultigrid, HierarchyCoversEveryVertexAndKeepsComponents)
{
  // Two spheres far apart and a real mesh: every finer row interpolates
  // from its level's coarse rows with non-negative weights summing to 1,
  // every coarse row is used, each level takes about one row in six to
  // ten, and every level keeps the components of the finest.
  const test::Mesh two = test::Merged(test::OctahedronSphere(5), test::OctahedronSphere(4, 0.5), { 5.0, 0.0, 0.0 });
  for (const auto& [name, mesh, components] :
    { std::make_tuple(std::string("two spheres"), two, 2), std::make_tuple(std::string("bunny00"),
        ReadOrFail("bunny00.off"), 1) })
  {
    const MeshSystem s(mesh);
    const ShiftedLaplacianProblem pb = s.Problem(10.0 * s.H * s.H, 1, Preconditioning::GeometricMultigrid);
    auto h = std::make_shared<const SurfaceHierarchy>(pb.Rows, pb.Offsets, pb.Neighbors, pb.Points, 2);
    ASSERT_GE(h->Levels(), 2) << name;
    EXPECT_LE(h->Rows(h->Levels() - 1), 1000) << name;
    for (int l = 0; l + 1 < h->Levels(); ++l)
    {
      const LevelMatrix& p = h->Prolongation(l);
      const double ratio = static_cast<double>(h->Rows(l)) / h->Rows(l + 1);
      EXPECT_GE(ratio, 5.0) << name << " level " << l;
      EXPECT_LE(ratio, 12.0) << name << " level " << l;
      for (Index i = 0; i < h->Rows(l); ++i)
      {
        double sum = 0.0;
        for (std::int64_t k = p.Offsets[i]; k < p.Offsets[i + 1]; ++k)
        {
          ASSERT_GT(p.Values[k], 0.0);
          ASSERT_LT(p.Columns[k], h->Rows(l + 1));
          sum += p.Values[k];
        }
        ASSERT_NEAR(sum, 1.0, 1e-12) << name << " level " << l << " row " << i;
      }
      const LevelMatrix& r = h->Restriction(l);
      for (Index c = 0; c < h->Rows(l + 1); ++c)
      {
        ASSERT_GT(r.Offsets[c + 1], r.Offsets[c]) << name << " level " << l + 1 << " row " << c << " unused";
      }
    }
    const SurfaceMultigrid mg(h, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, pb.Shift, pb.Factor, nullptr, 2);
    for (int l = 0; l < mg.Levels(); ++l)
    {
      EXPECT_EQ(Components(mg.Operator(l)), components) << name << " level " << l;
    }
    EXPECT_LT(mg.OperatorComplexity(), 1.6) << name;
  }
}

TEST(SurfaceMultigrid, HierarchyOfPointsWithNaNs)
{
  // Points that are NaN (hostile input) still join a sample each: every
  // level's rows interpolate from coarse rows with weights summing to 1.
  test::Mesh m = test::OctahedronSphere(5);
  for (Index i = 0; i < m.NumberOfVertices(); i += 7)
  {
    m.Points[3 * i + i % 3] = std::numeric_limits<double>::quiet_NaN();
  }
  const MeshTopology topo = m.Topology();
  const MeshTopology::VertexGraph& graph = topo.Graph();
  const SurfaceHierarchy h(
    m.NumberOfVertices(), graph.NeighborOffsets.data(), graph.Neighbors.data(), m.Points.data(), 2);
  ASSERT_GE(h.Levels(), 2);
  for (int l = 0; l + 1 < h.Levels(); ++l)
  {
    const LevelMatrix& p = h.Prolongation(l);
    for (Index i = 0; i < h.Rows(l); ++i)
    {
      double sum = 0.0;
      for (std::int64_t k = p.Offsets[i]; k < p.Offsets[i + 1]; ++k)
      {
        ASSERT_GE(p.Columns[k], 0);
        ASSERT_LT(p.Columns[k], h.Rows(l + 1));
        sum += p.Values[k];
      }
      ASSERT_NEAR(sum, 1.0, 1e-12) << "level " << l << " row " << i;
    }
  }
}

TEST(SurfaceMultigrid, CycleReducesTheResidualBySizeIndependentFactors)
{
  // Spheres of 1k to 263k vertices, M + t K with t = 10 h^2 and 1000 h^2:
  // the V-cycle alone (x += B (b - A x)) reduces the residual by a factor
  // per cycle that does not grow with the mesh; the order-2 system
  // M + t K M^-1 K (t = 4 h^4, COCG with the complex V-cycle) takes at most
  // 10 iterations at every size (measured 7-8).
  std::vector<double> factors[2];
  std::vector<int> squared;
  for (int levels : { 4, 5, 6, 7, 8 })
  {
    const MeshSystem s(test::OctahedronSphere(levels));
    const Index n = s.L.NumberOfVertices;
    std::vector<double> b(n);
    for (Index i = 0; i < n; ++i)
    {
      b[i] = s.Mass[i] * (s.Mesh.Points[3 * i] + std::sin(40.0 * s.Mesh.Points[3 * i + 1]));
    }
    for (int big : { 0, 1 })
    {
      const double t = (big ? 1000.0 : 10.0) * s.H * s.H;
      const ShiftedLaplacianProblem pb = s.Problem(t, 1, Preconditioning::GeometricMultigrid);
      auto h = std::make_shared<const SurfaceHierarchy>(pb.Rows, pb.Offsets, pb.Neighbors, pb.Points, 2);
      const SurfaceMultigrid mg(h, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, pb.Shift, t, nullptr, 2);
      std::vector<double> x(n, 0.0), rIn(n), zIn(n);
      const std::vector<Index>& order = h->Order(); // the cycle's rows
      const double r0 = Norm(b);
      for (int cycle = 0; cycle < 5; ++cycle)
      {
        const std::vector<double> r = s.Residual(t, b, x);
        for (Index i = 0; i < n; ++i)
        {
          rIn[i] = r[order[i]];
        }
        mg.ApplyInOrder(rIn.data(), zIn.data(), 1);
        for (Index i = 0; i < n; ++i)
        {
          x[order[i]] += zIn[i];
        }
      }
      factors[big].push_back(std::pow(Norm(s.Residual(t, b, x)) / r0, 1.0 / 5.0));
    }
    ShiftedLaplacianProblem pb = s.Problem(4.0 * std::pow(s.H, 4), 1, Preconditioning::GeometricMultigrid);
    pb.Tolerance = 1e-6;
    std::vector<double> x(n, 0.0);
    const ConjugateGradientResult r = SolveSquaredLaplacian(pb, b.data(), x.data());
    EXPECT_TRUE(r.Converged) << n << " vertices";
    squared.push_back(r.Iterations);
    std::cout << n << " vertices: V-cycle factors " << factors[0].back() << " (10 h^2), " << factors[1].back()
              << " (1000 h^2); order 2, 4 h^4: " << r.Iterations << " iterations\n";
  }
  for (int big : { 0, 1 })
  {
    for (std::size_t k = 0; k < factors[big].size(); ++k)
    {
      EXPECT_LT(factors[big][k], 0.25) << "level " << k << (big ? ", 1000 h^2" : ", 10 h^2");
      EXPECT_LT(factors[big][k], factors[big][0] + 0.06) << "level " << k << (big ? ", 1000 h^2" : ", 10 h^2");
    }
  }
  for (std::size_t k = 0; k < squared.size(); ++k)
  {
    EXPECT_LE(squared[k], 10) << "level " << k;
  }
}

TEST(SurfaceMultigrid, SolvesAsJacobiOnRealAndIrregularMeshes)
{
  // Order-1 and order-2 steps on real meshes, on a flat mesh with slivers
  // (a third of its triangles split at random interior points) and on a
  // sphere with a far speck of 1e-4 its size: the geometric multigrid's
  // solution equals Jacobi's to the tolerance, in fewer iterations.
  std::vector<std::pair<std::string, test::Mesh>> meshes;
  // (three_peaks is open: its boundary rows held, and coarse rows whose
  // finer rows are all held have no operator; they made NaN.)
  for (const char* name : { "bunny00.off", "fandisk.off", "eight.off", "three_peaks.off" })
  {
    meshes.emplace_back(name, ReadOrFail(name));
  }
  meshes.emplace_back("irregular with slivers", test::FlatIrregular(120, 7));
  meshes.emplace_back("sphere with a speck",
    test::Merged(test::OctahedronSphere(4), test::OctahedronSphere(1, 1e-4), { 5.0, 0.0, 0.0 }));
  const Index speck = test::OctahedronSphere(4).NumberOfVertices(); // the speck's first row
  for (const auto& [name, mesh] : meshes)
  {
    const MeshSystem s(mesh, name == "three_peaks.off");
    const Index n = s.L.NumberOfVertices;
    std::vector<double> b(3 * static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < b.size(); ++k)
    {
      b[k] = s.Mass[k / 3] * s.Mesh.Points[k];
    }
    for (int order : { 1, 2 })
    {
      const double t = order == 1 ? 10.0 * s.H * s.H : 4.0 * std::pow(s.H, 4);
      std::vector<double> solution[2];
      int iterations[2] = {};
      for (int m : { 0, 1 })
      {
        ShiftedLaplacianProblem pb =
          s.Problem(t, 3, m ? Preconditioning::GeometricMultigrid : Preconditioning::Jacobi);
        solution[m] = s.Mesh.Points;
        const ConjugateGradientResult r = order == 1 ? SolveShiftedLaplacian(pb, b.data(), solution[m].data())
                                                      : SolveSquaredLaplacian(pb, b.data(), solution[m].data());
        EXPECT_TRUE(r.Converged) << name << ", order " << order << ", preconditioner " << m;
        iterations[m] = r.Iterations;
      }
      // The speck's rows (masses 1e-8 of the sphere's) weigh nothing in
      // the residual that ends the solves: there the order-2 solutions
      // differ by 6e-5 of the change (5e-8, 5e-4 of the speck's size).
      const bool onSpeck = name == "sphere with a speck" && order == 2;
      const std::size_t first = onSpeck ? 3 * static_cast<std::size_t>(speck) : b.size();
      double change = 0.0, difference = 0.0, tiny = 0.0;
      for (std::size_t k = 0; k < b.size(); ++k)
      {
        change = std::max(change, std::abs(solution[0][k] - s.Mesh.Points[k]));
        (k < first ? difference : tiny) = std::max(k < first ? difference : tiny,
          std::abs(solution[1][k] - solution[0][k]));
      }
      EXPECT_LE(difference, 1e-5 * change) << name << ", order " << order;
      EXPECT_LE(tiny, 1e-3 * change) << name << ", order " << order;
      EXPECT_LT(iterations[1], iterations[0]) << name << ", order " << order;
      std::cout << name << ", order " << order << ": Jacobi " << iterations[0] << ", geometric multigrid "
                << iterations[1] << " iterations, difference " << difference / change << " of the change"
                << (onSpeck ? " (" + std::to_string(tiny / change) + " on the speck)" : std::string()) << "\n";
    }
  }
}


TEST(SurfaceMultigrid, AutomaticTakesItForLargeStepsOnLargeSurfaces)
{
  // Automatic: the geometric multigrid for steps from about 150 h^2 (order
  // 1) or 100 h^4 (order 2) on surfaces of at least AutomaticMultigridRows
  // rows with points, and for D = 0; Jacobi for the default steps, small
  // surfaces, curves and without points. Its solution is the chosen
  // solver's.
  const MeshSystem s(ReadOrFail("bunny00.off")); // 37,706 vertices
  const double h2 = s.H * s.H;
  const auto chosen = [&](double t, bool squared) {
    return ChosenPreconditioner(s.Problem(t, 3, Preconditioning::Automatic), squared);
  };
  EXPECT_EQ(chosen(10.0 * h2, false), Preconditioning::Jacobi);
  EXPECT_EQ(chosen(30.0 * h2, false), Preconditioning::Jacobi);
  EXPECT_EQ(chosen(300.0 * h2, false), Preconditioning::GeometricMultigrid);
  EXPECT_EQ(chosen(4.0 * h2 * h2, true), Preconditioning::Jacobi);
  EXPECT_EQ(chosen(400.0 * h2 * h2, true), Preconditioning::GeometricMultigrid);
  ShiftedLaplacianProblem harmonic = s.Problem(1.0, 1, Preconditioning::Automatic);
  harmonic.Shift = nullptr;
  EXPECT_EQ(ChosenPreconditioner(harmonic), Preconditioning::GeometricMultigrid);
  ShiftedLaplacianProblem unplaced = s.Problem(300.0 * h2, 3, Preconditioning::Automatic);
  unplaced.Points = nullptr;
  EXPECT_EQ(ChosenPreconditioner(unplaced), Preconditioning::Jacobi);
  const MeshSystem small(test::OctahedronSphere(5)); // 4,098 vertices
  EXPECT_EQ(ChosenPreconditioner(small.Problem(300.0 * small.H * small.H, 3, Preconditioning::Automatic)),
    Preconditioning::Jacobi);
  EXPECT_EQ(ChosenPreconditioner(s.Problem(300.0 * h2, 3, Preconditioning::Jacobi)), Preconditioning::Jacobi);
  // A curve's graph (the fairing's boundary stage), however large the step:
  // a path of 30,000 points.
  const Index m = 30000;
  std::vector<std::int64_t> offsets(1, 0);
  std::vector<Index> neighbors;
  std::vector<double> weights, diagonal(m, 2.0), shift(m, 1e-6), line(3 * static_cast<std::size_t>(m), 0.0);
  for (Index i = 0; i < m; ++i)
  {
    for (const Index j : { i - 1, i + 1 })
    {
      if (j >= 0 && j < m)
      {
        neighbors.push_back(j);
        weights.push_back(1.0);
      }
    }
    offsets.push_back(static_cast<std::int64_t>(neighbors.size()));
    line[3 * static_cast<std::size_t>(i)] = i;
  }
  ShiftedLaplacianProblem path;
  path.Rows = m;
  path.Offsets = offsets.data();
  path.Neighbors = neighbors.data();
  path.Weights = weights.data();
  path.Diagonal = diagonal.data();
  path.Shift = shift.data();
  path.Points = line.data();
  path.Preconditioner = Preconditioning::Automatic;
  EXPECT_EQ(ChosenPreconditioner(path), Preconditioning::Jacobi);

  const Index n = s.L.NumberOfVertices;
  std::vector<double> b(3 * static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < b.size(); ++k)
  {
    b[k] = s.Mass[k / 3] * s.Mesh.Points[k];
  }
  std::shared_ptr<const SurfaceHierarchy> kept; // built by the first solve, taken by the next
  const SurfaceHierarchy* first = nullptr;
  for (const Preconditioning m : { Preconditioning::Automatic, Preconditioning::Automatic })
  {
    std::vector<double> x = s.Mesh.Points;
    ShiftedLaplacianProblem pb = s.Problem(300.0 * h2, 3, m);
    pb.KeptHierarchy = &kept;
    const ConjugateGradientResult r = SolveShiftedLaplacian(pb, b.data(), x.data());
    EXPECT_TRUE(r.Converged);
    EXPECT_LT(r.Iterations, 20); // Jacobi: about 250
    ASSERT_TRUE(kept);
    EXPECT_EQ(kept->Rows(0), s.L.NumberOfVertices);
    first = first ? first : kept.get();
    EXPECT_EQ(kept.get(), first);
  }
}

TEST(SurfaceMultigrid, SquaredJacobiSolveInMixedPrecisionReachesTheTolerance)
{
  // The serial Jacobi order-2 solve asked for a reduction single precision
  // resolves works in mixed precision (double-precision residuals of the
  // caller's matrix, single-precision corrections), and where those stall
  // goes on in double precision: at every step, on a real mesh, on a mesh
  // with slivers, on a sphere with a far speck and on spheres whose values
  // single precision cannot hold, the independent
  // double-precision residual of every column is within the tolerance of
  // the one at the start, and the solution within it of the
  // double-precision solve to 1e-9.
  std::vector<std::pair<std::string, test::Mesh>> meshes;
  meshes.emplace_back("bunny00.off", ReadOrFail("bunny00.off"));
  meshes.emplace_back("irregular with slivers", test::FlatIrregular(120, 7));
  meshes.emplace_back("sphere with a speck",
    test::Merged(test::OctahedronSphere(4), test::OctahedronSphere(1, 1e-4), { 5.0, 0.0, 0.0 }));
  // (Beyond single precision's range: solved in double precision.)
  meshes.emplace_back("sphere of radius 1e-20", test::OctahedronSphere(4, 1e-20));
  meshes.emplace_back("sphere of radius 1e20", test::OctahedronSphere(4, 1e20));
  for (const auto& [name, mesh] : meshes)
  {
    const MeshSystem s(mesh);
    const std::size_t size = 3 * static_cast<std::size_t>(s.L.NumberOfVertices);
    std::vector<double> b(size);
    for (std::size_t k = 0; k < size; ++k)
    {
      b[k] = s.Mass[k / 3] * s.Mesh.Points[k];
    }
    const auto residualNorms = [&](double t, const std::vector<double>& x) {
      std::vector<double> y(size), z(size), norms(3, 0.0);
      s.L.ApplyStiffness(x.data(), y.data(), 3, 2);
      for (std::size_t k = 0; k < size; ++k)
      {
        y[k] /= s.Mass[k / 3];
      }
      s.L.ApplyStiffness(y.data(), z.data(), 3, 2);
      for (std::size_t k = 0; k < size; ++k)
      {
        const double r = b[k] - s.Mass[k / 3] * x[k] - t * z[k];
        norms[k % 3] += r * r;
      }
      return norms;
    };
    for (const double steps : { 4.0, 400.0 })
    {
      const double t = steps * std::pow(s.H, 4);
      ShiftedLaplacianProblem pb = s.Problem(t, 3, Preconditioning::Jacobi);
      pb.MixedPrecisionRows = 0; // (from the default's million rows)
      pb.Tolerance = 1e-9;
      for (int c = 0; c < 3; ++c) // (the round-off floor in the right-hand side's units, as the fairing's)
      {
        double squares = 0.0;
        for (std::size_t k = c; k < size; k += 3)
        {
          squares += b[k] * b[k];
        }
        pb.Scale[c] = std::sqrt(squares);
      }
      std::vector<double> exact = s.Mesh.Points;
      ASSERT_TRUE(SolveSquaredLaplacian(pb, b.data(), exact.data()).Converged);
      const std::vector<double> start = residualNorms(t, s.Mesh.Points);
      for (const double tolerance : { 1e-4, 1e-5 })
      {
        pb.Tolerance = tolerance;
        std::vector<double> x = s.Mesh.Points;
        const ConjugateGradientResult r = SolveSquaredLaplacian(pb, b.data(), x.data());
        EXPECT_TRUE(r.Converged) << name << ", " << steps << " h^4, tolerance " << tolerance;
        const std::vector<double> end = residualNorms(t, x);
        double change = 0.0, error = 0.0;
        for (std::size_t k = 0; k < size; ++k)
        {
          change = std::max(change, std::abs(exact[k] - s.Mesh.Points[k]));
          error = std::max(error, std::abs(x[k] - exact[k]));
        }
        for (int c = 0; c < 3; ++c)
        {
          EXPECT_LE(std::sqrt(end[c]), 1.0001 * tolerance * std::sqrt(start[c]))
            << name << ", " << steps << " h^4, tolerance " << tolerance << ", column " << c;
        }
        EXPECT_LE(error, 10.0 * tolerance * change) << name << ", " << steps << " h^4, tolerance " << tolerance;
        for (const int threads : { 1, 3 }) // (the same numbers on any number of threads; one case a mesh)
        {
          if (steps != 4.0 || tolerance != 1e-4)
          {
            break;
          }
          ShiftedLaplacianProblem other = pb;
          other.NumberOfThreads = threads;
          std::vector<double> y = s.Mesh.Points;
          SolveSquaredLaplacian(other, b.data(), y.data());
          EXPECT_EQ(y, x) << name << ", " << threads << " threads";
        }
        std::cout << name << ", " << steps << " h^4, tolerance " << tolerance << ": " << r.Iterations
                  << " iterations, error " << error / change << " of the change\n";
      }
    }
  }
}
