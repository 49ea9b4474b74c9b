// The 3-manifold operator of section 2.8.2 / appendix A.4 and the graph flow
// on tetrahedral meshes.
#include "Flows/GraphFlow.h"
#include "Mesh/Tetrahedra.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <vector>

using namespace beltrami;

namespace
{

/// An nx x ny x nz grid of points (spacing h, jittered) split into 6
/// tetrahedra per cube around its main diagonal (GridTetrahedra).
struct Grid
{
  int NX, NY, NZ;
  std::vector<double> Points;
  std::vector<Index> Tets;
  Grid(int nx, int ny, int nz, double h, double jitter, unsigned seed)
    : NX(nx)
    , NY(ny)
    , NZ(nz)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
        {
          Points.push_back(h * i + u(rng));
          Points.push_back(h * j + u(rng));
          Points.push_back(h * k + u(rng));
        }
    Tets = GridTetrahedra(nx, ny, nz);
  }
  Index Size() const { return static_cast<Index>(Points.size() / 3); }
};

double TotalVolume(const TetrahedralMesh& mesh, const double* x, int dim)
{
  double v = 0.0;
  const std::vector<Index>& t = mesh.TetrahedronList();
  for (std::size_t q = 0; q < t.size(); q += 4)
  {
    v += Tetrahedron(x + t[q] * dim, x + t[q + 1] * dim, x + t[q + 2] * dim, x + t[q + 3] * dim, dim).Volume;
  }
  return v;
}

} // namespace

TEST(Tetrahedra, RegularTetrahedronHasTheDihedralCotangentWeights)
{
  const double s = 1.0 / std::sqrt(2.0);
  const double p[4][3] = { { 1, 0, -s }, { -1, 0, -s }, { 0, 1, s }, { 0, -1, s } }; // edge length 2
  const TetrahedronTerms t = Tetrahedron(p[0], p[1], p[2], p[3], 3);
  ASSERT_FALSE(t.Degenerate);
  EXPECT_NEAR(t.Volume, 8.0 / (6.0 * std::sqrt(2.0)), 1e-14);
  // l cot(theta) / 6 with l = 2 and theta = acos(1/3): cot = 1 / (2 sqrt 2).
  for (double w : t.Weights)
  {
    EXPECT_NEAR(w, 2.0 / (2.0 * std::sqrt(2.0)) / 6.0, 1e-14);
  }
}

TEST(Tetrahedra, VolumeGradientMatchesFiniteDifferencesInR5)
{
  // A jittered grid with two data coordinates: a 3-manifold in R^5.
  Grid grid(4, 3, 3, 1.0, 0.2, 7);
  const int dim = 5;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<double> x;
  for (Index i = 0; i < grid.Size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      x.push_back(grid.Points[3 * i + c]);
    }
    x.push_back(noise(rng));
    x.push_back(noise(rng));
  }
  TetrahedralMesh mesh(grid.Size(), grid.Tets);
  ASSERT_EQ(mesh.NumberOfTetrahedra(), 6 * 3 * 2 * 2);
  GraphLaplacian l;
  AssembleTetrahedralLaplacian(mesh, x.data(), dim, l);
  EXPECT_EQ(l.DegenerateTriangles, 0);
  std::vector<double> grad(x.size());
  l.ApplyStiffness(x.data(), grad.data(), dim, 1);
  const double h = 1e-6;
  double worst = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    std::vector<double> plus = x, minus = x;
    plus[k] += h;
    minus[k] -= h;
    const double fd = (TotalVolume(mesh, plus.data(), dim) - TotalVolume(mesh, minus.data(), dim)) / (2 * h);
    worst = std::max(worst, std::abs(fd - grad[k]));
  }
  EXPECT_LT(worst, 1e-7);
  // The lumped masses add up to the volume.
  double mass = 0.0;
  for (double m : l.Mass)
  {
    mass += m;
  }
  EXPECT_NEAR(mass, TotalVolume(mesh, x.data(), dim), 1e-12);
}

TEST(Tetrahedra, LinearAndConstantFieldsAreFixedPoints)
{
  // Linear precision of the operator: with the boundary values held, a
  // linear field (and a constant, second component) stays put at every
  // interior vertex, for every gamma and both integrations.
  Grid grid(5, 4, 4, 0.5, 0.1, 11);
  TetrahedralMesh mesh(grid.Size(), grid.Tets);
  std::vector<std::uint8_t> boundary(grid.Size(), 0);
  for (int k = 0; k < grid.NZ; ++k)
    for (int j = 0; j < grid.NY; ++j)
      for (int i = 0; i < grid.NX; ++i)
      {
        boundary[(k * grid.NY + j) * grid.NX + i] =
          i == 0 || j == 0 || k == 0 || i == grid.NX - 1 || j == grid.NY - 1 || k == grid.NZ - 1;
      }
  for (double gamma : { -1.0, 0.0, 1.0, 2.0 })
  {
    for (auto integration : { GraphFlowIntegration::Explicit, GraphFlowIntegration::SemiImplicit })
    {
      std::vector<double> f;
      for (Index i = 0; i < grid.Size(); ++i)
      {
        const double* p = &grid.Points[3 * i];
        f.push_back(0.7 * p[0] - 1.3 * p[1] + 0.4 * p[2] + 2.0);
        f.push_back(3.0);
      }
      const std::vector<double> f0 = f;
      GraphFlowOptions o;
      o.Units = LengthUnit::Physical; // settings in the mesh\'s own units
      o.ContrastScale = 2.0;
      o.EdgeContrast = gamma;
      o.Integration = integration;
      o.TimeStep = integration == GraphFlowIntegration::Explicit ? 0.002 : 0.5;
      o.NumberOfIterations = 10;
      o.Stop = GraphFlowStop::Iterations;
      o.SolverTolerance = 1e-12;
      const GraphFlowResult r =
        RunTetrahedralGraphFlow(mesh, grid.Points.data(), 2, f.data(), boundary.data(), o);
      ASSERT_TRUE(r.Error.empty()) << r.Error;
      double worst = 0.0;
      for (std::size_t k = 0; k < f.size(); ++k)
      {
        worst = std::max(worst, std::abs(f[k] - f0[k]));
      }
      EXPECT_LT(worst, 1e-9) << "gamma " << gamma;
    }
  }
  // A constant with a free boundary (the natural boundary condition).
  std::vector<double> c(grid.Size(), 0.25);
  GraphFlowOptions o;
  o.Units = LengthUnit::Physical; // settings in the mesh\'s own units
  o.ContrastScale = 5.0;
  o.TimeStep = 0.002;
  o.NumberOfIterations = 10;
  o.Stop = GraphFlowStop::Iterations;
  RunTetrahedralGraphFlow(mesh, grid.Points.data(), 1, c.data(), nullptr, o);
  for (double v : c)
  {
    EXPECT_EQ(v, 0.25);
  }
}

TEST(Tetrahedra, FlowKeepsAJumpAndRemovesNoise)
{
  // A field 0 | 1 across the plane x = 1.5 with noise: the Beltrami flow
  // (alpha = 1.5 / sigma) removes most of the noise and keeps the jump.
  Grid grid(10, 8, 8, 1.0 / 3.0, 0.0, 1);
  TetrahedralMesh mesh(grid.Size(), grid.Tets);
  const double sigma = 0.1;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> clean, f;
  for (Index i = 0; i < grid.Size(); ++i)
  {
    clean.push_back(grid.Points[3 * i] > 1.5 ? 1.0 : 0.0);
    f.push_back(clean.back() + noise(rng));
  }
  const auto rms = [&](const std::vector<double>& a) {
    double s = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k)
    {
      s += (a[k] - clean[k]) * (a[k] - clean[k]);
    }
    return std::sqrt(s / a.size());
  };
  const double before = rms(f);
  std::vector<double> points(grid.Points);
  const double h = mesh.MeanEdgeLength(points.data());
  for (double& p : points)
  {
    p /= h; // mean edge length units, as the filter
  }
  GraphFlowOptions o;
  o.Units = LengthUnit::Physical; // settings in the mesh\'s own units
  o.ContrastScale = 1.5 / sigma;
  o.Integration = GraphFlowIntegration::SemiImplicit;
  o.TimeStep = 0.1;
  o.Stop = GraphFlowStop::NoiseLevel;
  o.NoiseLevel = sigma;
  const GraphFlowResult r = RunTetrahedralGraphFlow(mesh, points.data(), 1, f.data(), nullptr, o);
  ASSERT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_LT(r.FinalArea, r.InitialArea);
  EXPECT_LT(rms(f), 0.5 * before) << before;
  // The jump: mean of the two sides next to the plane stays apart.
  double low = 0.0, high = 0.0;
  int nl = 0, nh = 0;
  for (Index i = 0; i < grid.Size(); ++i)
  {
    const double x = grid.Points[3 * i];
    if (std::abs(x - 4.0 / 3.0) < 1e-9)
    {
      low += f[i];
      ++nl;
    }
    if (std::abs(x - 5.0 / 3.0) < 1e-9)
    {
      high += f[i];
      ++nh;
    }
  }
  EXPECT_GT(high / nh - low / nl, 0.8);
}

TEST(Tetrahedra, InvalidTetrahedraAreDropped)
{
  TetrahedralMesh mesh(4, { 0, 1, 2, 3, 0, 0, 1, 2, 0, 1, 2, 9 });
  EXPECT_EQ(mesh.NumberOfTetrahedra(), 1);
  EXPECT_EQ(mesh.NumberOfDroppedTetrahedra(), 2);
  const double flat[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 }; // all in z = 0
  EXPECT_TRUE(Tetrahedron(flat, flat + 3, flat + 6, flat + 9, 3).Degenerate);
}

namespace
{

/// Six steps of a flow for comparing two kernels: contrast 10, explicit
/// steps of 0.05 or semi-implicit ones of 0.2, tight solves.
GraphFlowOptions ComparisonOptions(GraphFlowIntegration integration)
{
  GraphFlowOptions o;
  o.ContrastScale = 10.0;
  o.Integration = integration;
  o.TimeStep = integration == GraphFlowIntegration::Explicit ? 0.05 : 0.2;
  o.Stop = GraphFlowStop::Iterations;
  o.NumberOfIterations = 6;
  o.SolverTolerance = 1e-12;
  return o;
}

/// One flow run on `values` with a number of threads.
using FlowRun = std::function<GraphFlowResult(std::vector<double>& values, int threads)>;

/// The double-precision flow on a tetrahedral mesh, as a FlowRun (o's
/// thread count set per run).
FlowRun TetrahedralRun(const TetrahedralMesh& mesh, const std::vector<double>& points, int nc,
  const std::vector<std::uint8_t>& fixed, GraphFlowOptions& o)
{
  return [&mesh, &points, nc, &fixed, &o](std::vector<double>& x, int threads) {
    o.NumberOfThreads = threads;
    return RunTetrahedralGraphFlow(mesh, points.data(), nc, x.data(), fixed.data(), o);
  };
}

/// Checks a single-precision kernel (`single`) against the double-precision
/// tetrahedral flow (`reference`) from the data f (nc per point): the graph
/// volumes within areaBound, the values within 1e-5 (scalars) or 3e-4
/// (vectors) of the largest change (which must be real), the same
/// unstable steps, and the same bits on 1 and 3 threads.  Returns the
/// kernel's result (1 thread) and sets the largest difference.
std::vector<double> ExpectSameFlow(const std::vector<double>& f, int nc, const FlowRun& reference,
  const FlowRun& single, double areaBound, double& difference)
{
  std::vector<double> a = f, b = f, c = f;
  const GraphFlowResult ra = reference(a, 1), rb = single(b, 1);
  single(c, 3);
  EXPECT_TRUE(ra.Error.empty() && rb.Error.empty()) << ra.Error << rb.Error;
  EXPECT_NEAR(ra.FinalArea, rb.FinalArea, areaBound * ra.FinalArea);
  EXPECT_EQ(ra.UnstableSteps, rb.UnstableSteps);
  double change = 0.0;
  difference = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    difference = std::max(difference, std::abs(a[k] - b[k]));
    change = std::max(change, std::abs(a[k] - f[k]));
  }
  // (Single-precision kernels: up to 3.2e-4 of the change for three
  // components at -O2, where the compiler vectorises their sums otherwise.)
  EXPECT_LT(difference, (nc == 1 ? 1e-5 : 4e-4) * change) << nc << " components";
  EXPECT_GT(change, 0.01);
  EXPECT_EQ(b, c) << "thread count changed the result";
  return b;
}

/// The points of an nx x ny x nz lattice of the given spacing from `origin`
/// (x fastest).
std::vector<double> LatticePoints(int nx, int ny, int nz, const double (&spacing)[3], const double (&origin)[3])
{
  std::vector<double> points;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        points.insert(points.end(), { origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2] });
  return points;
}

/// Appends the voxel cell (i, j, k) of an nx x ny lattice (8 point ids,
/// corner bit a = a step along axis a).
void AddVoxelCell(std::vector<Index>& cells, int nx, int ny, int i, int j, int k)
{
  for (int c = 0; c < 8; ++c)
    cells.push_back((i + (c & 1)) + nx * ((j + (c >> 1 & 1)) + ny * (k + (c >> 2))));
}

/// The Kuhn tetrahedra (6 per cell, 4 ids each) of voxel cells.
std::vector<Index> KuhnTetrahedraOf(const std::vector<Index>& cells)
{
  std::vector<Index> tets;
  for (std::size_t c = 0; c < cells.size(); c += 8)
    for (const auto& path : KuhnPaths)
    {
      const int first = 1 << path[0], second = first | (1 << path[1]);
      for (const int corner : { 0, first, second, 7 })
        tets.push_back(cells[c + corner]);
    }
  return tets;
}

} // namespace

TEST(Tetrahedra, VoxelFlowEqualsTheFlowOnTheKuhnMesh)
{
  // RunVolumeGraphFlow evaluates the Kuhn tetrahedra of a voxel grid
  // without a mesh: it must give the flow of RunTetrahedralGraphFlow on
  // GridTetrahedra (up to its single-precision tetrahedra and weights:
  // within 3e-4 of the data's change and 5e-5 of the graph's volume, where
  // a wrong weight or mass changes them by percents; scalars, in closed
  // form without the Gram matrix's cancellations, within 1e-5 and 1e-7:
  // measured 4e-7 and 7e-9), for scalars and
  // vectors, explicit and semi-implicit, anisotropic spacing, with a fixed
  // mask, and the same bits on any number of threads.
  const int nx = 9, ny = 7, nz = 6;
  const double sx = 1.0, sy = 1.3, sz = 0.8;
  const std::vector<double> points = LatticePoints(nx, ny, nz, { sx, sy, sz }, { 0.0, 0.0, 0.0 });
  const TetrahedralMesh mesh(nx * ny * nz, GridTetrahedra(nx, ny, nz));
  const VoxelGrid voxels{ nx, ny, nz, sx, sy, sz };
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<std::uint8_t> fixed(nx * ny * nz, 0);
  fixed[17] = fixed[200] = 1;
  for (int nc : { 1, 3 })
  {
    std::vector<double> f;
    for (int v = 0; v < nx * ny * nz; ++v)
      for (int c = 0; c < nc; ++c)
        f.push_back((v % nx > 4 ? 1.0 : 0.0) + noise(rng));
    for (auto integration : { GraphFlowIntegration::Explicit, GraphFlowIntegration::SemiImplicit })
    {
      GraphFlowOptions o = ComparisonOptions(integration);
      o.Units = LengthUnit::Physical; // settings in the mesh\'s own units
      double difference = 0.0;
      const std::vector<double> b = ExpectSameFlow(f, nc,
        TetrahedralRun(mesh, points, nc, fixed, o),
        [&](std::vector<double>& x, int threads) {
          o.NumberOfThreads = threads;
          return RunVolumeGraphFlow(voxels, nc, x.data(), fixed.data(), o);
        },
        nc == 1 ? 1e-7 : 5e-5, difference);
      EXPECT_EQ(b[17 * nc], f[17 * nc]);
    }
  }
}

TEST(Tetrahedra, AWholeLatticeOfVoxelCellsRunsTheGridsFlow)
{
  // A whole lattice given as voxel cells, rows of 40 points: the
  // voxel-cell kernel takes the grid's row kernel for the runs of points
  // whose neighbours are runs too, and the flow is the dense grid's to the
  // rounding of its single-precision sums taken in another order (within
  // 2e-6 of the change; measured 2e-7 on a 64^3 lattice; the double-
  // precision flow is 1e-5 away), for scalars and vectors, with the same
  // bits on 1 and 3 threads.
  const int nx = 40, ny = 6, nz = 5;
  const double sx = 1.0, sy = 1.3, sz = 0.8;
  const std::vector<double> points = LatticePoints(nx, ny, nz, { sx, sy, sz }, { 0.0, 0.0, 0.0 });
  std::vector<Index> cells;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        AddVoxelCell(cells, nx, ny, i, j, k);
  const Index n = nx * ny * nz;
  const TetrahedralMesh mesh(n, KuhnTetrahedraOf(cells));
  const VoxelGrid grid{ nx, ny, nz, sx, sy, sz };
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (int nc : { 1, 3 })
  {
    std::vector<double> f;
    for (Index v = 0; v < n; ++v)
      for (int c = 0; c < nc; ++c)
        f.push_back((v % nx > 17 ? 1.0 : 0.0) + noise(rng));
    GraphFlowOptions o = ComparisonOptions(GraphFlowIntegration::Explicit);
    o.Units = LengthUnit::Physical;
    std::vector<double> dense = f, sparse = f, threaded = f;
    ASSERT_EQ(RunVolumeGraphFlow(grid, nc, dense.data(), nullptr, o).Error, "");
    ASSERT_EQ(RunTetrahedralGraphFlow(mesh, points.data(), nc, sparse.data(), nullptr, o, {}, &cells).Error, "");
    o.NumberOfThreads = 3;
    RunTetrahedralGraphFlow(mesh, points.data(), nc, threaded.data(), nullptr, o, {}, &cells);
    double difference = 0.0, change = 0.0;
    for (std::size_t k = 0; k < f.size(); ++k)
    {
      difference = std::max(difference, std::abs(dense[k] - sparse[k]));
      change = std::max(change, std::abs(dense[k] - f[k]));
    }
    EXPECT_GT(change, 0.01);
    EXPECT_LT(difference, 2e-6 * change) << nc << " components";
    EXPECT_EQ(sparse, threaded);
  }
}

TEST(Tetrahedra, SparseVoxelCellsRunTheDenseKernelsFlow)
{
  // Voxel cells of a lattice with holes (the active voxels of a sparse
  // grid), given to RunTetrahedralGraphFlow with their Kuhn tetrahedra:
  // the voxel-cell kernel must give the flow of the generic tetrahedral
  // path (to its single-precision tetrahedra: the bounds of the dense
  // grid's test above, the volume of vectors within 2e-4; and not bit for
  // bit, which shows that it ran), for scalars and vectors, explicit and
  // semi-implicit, with a fixed point, the same bits on any number of
  // threads; points of no cell keep their values; cells that are not one
  // lattice (a moved corner) fall back to the generic path, bit for bit.
  const int nx = 10, ny = 8, nz = 7;
  const std::vector<double> points = LatticePoints(nx, ny, nz, { 1.0, 1.3, 0.8 }, { 2.0, -1.0, 0.5 });
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Index> cells;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
      {
        if (uniform(rng) < 0.2 || (i > 5 && j > 4)) // holes, and a block of points in no cell
          continue;
        AddVoxelCell(cells, nx, ny, i, j, k);
      }
  // Shuffled cells: the kernel sorts them itself.
  std::vector<int> order(cells.size() / 8);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Index> shuffled;
  for (int c : order)
    shuffled.insert(shuffled.end(), cells.begin() + 8 * c, cells.begin() + 8 * c + 8);
  cells = shuffled;
  const Index n = nx * ny * nz;
  const TetrahedralMesh mesh(n, KuhnTetrahedraOf(cells));
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<std::uint8_t> fixed(n, 0);
  fixed[23] = 1;
  const Index lonely = (nx - 1) + nx * ((ny - 1) + ny * 3); // in no cell
  for (int nc : { 1, 3 })
  {
    std::vector<double> f;
    for (Index v = 0; v < n; ++v)
      for (int c = 0; c < nc; ++c)
        f.push_back((v % nx > 4 ? 1.0 : 0.0) + noise(rng));
    for (auto integration : { GraphFlowIntegration::Explicit, GraphFlowIntegration::SemiImplicit })
    {
      GraphFlowOptions o = ComparisonOptions(integration);
      // (The volume of vectors: 2e-5 to 1e-4 measured, as the rounding of
      // the single precision goes; the kernel in double precision: 4e-13.)
      double difference = 0.0;
      const std::vector<double> b = ExpectSameFlow(f, nc,
        TetrahedralRun(mesh, points, nc, fixed, o),
        [&](std::vector<double>& x, int threads) {
          o.NumberOfThreads = threads;
          return RunTetrahedralGraphFlow(mesh, points.data(), nc, x.data(), fixed.data(), o, {}, &cells);
        },
        nc == 1 ? 1e-7 : 2e-4, difference);
      EXPECT_GT(difference, 0.0) << "the voxel-cell kernel did not run";
      EXPECT_EQ(b[23 * nc], f[23 * nc]);
      EXPECT_EQ(b[lonely * nc], f[lonely * nc]);
    }
  }
  // Not one lattice: a corner moved off it.
  std::vector<double> moved = points;
  moved[3 * cells[0] + 1] += 0.01;
  std::vector<double> f(n);
  for (double& x : f)
    x = noise(rng);
  GraphFlowOptions o;
  o.Stop = GraphFlowStop::Iterations;
  o.NumberOfIterations = 4;
  std::vector<double> a = f, b = f;
  RunTetrahedralGraphFlow(mesh, moved.data(), 1, a.data(), nullptr, o);
  RunTetrahedralGraphFlow(mesh, moved.data(), 1, b.data(), nullptr, o, {}, &cells);
  EXPECT_EQ(a, b);
}
