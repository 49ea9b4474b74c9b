// The core's distributed solves (Solvers/Partition) over MPI processes,
// VTK-free: run by ctest under mpirun on 1, 2 and 3 processes.  A grid
// graph's rows are split in blocks (the last of 3 processes owns none); each
// process holds its block and the ghost copies of the block's neighbours.
// The distributed conjugate gradient (Jacobi, and multigrid with one
// BoomerAMG hierarchy over the processes) must give every process' rows of
// the serial solution, which each process also computes whole.
#include "Flows/GraphFlow.h"
#include "Flows/NoiseEstimation.h"
#include "Mesh/Tetrahedra.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/Partition.h"
#include "Solvers/SparseGraph.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

using namespace beltrami;

namespace
{

/// D + t K on an n x n grid graph (4 neighbours, weights varying over the
/// grid), row-major, and a right-hand side; rows of the first column fixed.
struct Grid
{
  int N = 0;
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<Index> Neighbors;
  std::vector<double> Weights, Diagonal, Shift, B;
  std::vector<std::uint8_t> Fixed;

  explicit Grid(int n)
    : N(n)
  {
    for (int i = 0; i < n * n; ++i)
    {
      const int r = i / n, c = i % n;
      double sum = 0.0;
      for (const auto& [dr, dc] : { std::pair{ -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 } })
      {
        if (r + dr >= 0 && r + dr < n && c + dc >= 0 && c + dc < n)
        {
          const int j = (r + dr) * n + c + dc;
          Neighbors.push_back(j);
          Weights.push_back(1.0 + 0.5 * std::sin(0.1 * (i + j)));
          sum += Weights.back();
        }
      }
      Offsets.push_back(static_cast<std::int64_t>(Neighbors.size()));
      Diagonal.push_back(sum);
      Shift.push_back(1.0 + 0.3 * std::cos(0.05 * i));
      B.push_back(std::sin(0.2 * r) * std::cos(0.3 * c));
      Fixed.push_back(c == 0);
    }
  }
};

/// One process' share: rows [first, last) owned, then the ghosts.
struct Piece
{
  std::vector<Index> Global; ///< local row -> grid row
  std::vector<int> OwnerRank;
  std::vector<Index> OwnerRow;
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<Index> Neighbors;
  std::vector<double> Weights, Diagonal, Shift, B;
  std::vector<std::uint8_t> Fixed;

  Piece(const Grid& g, int rank, int size)
  {
    const int rows = g.N * g.N;
    const int owners = size >= 3 ? size - 1 : size; // with 3 processes the last holds nothing
    const auto firstOf = [&](int p) { return p >= owners ? rows : static_cast<int>(std::int64_t(rows) * p / owners); };
    const int first = firstOf(rank), last = firstOf(rank + 1);
    std::map<int, Index> local;
    for (int i = first; i < last; ++i)
    {
      local[i] = static_cast<Index>(Global.size());
      Global.push_back(i);
    }
    for (int i = first; i < last; ++i)
    {
      for (std::int64_t k = g.Offsets[i]; k < g.Offsets[i + 1]; ++k)
      {
        if (!local.count(g.Neighbors[k]))
        {
          local[g.Neighbors[k]] = static_cast<Index>(Global.size());
          Global.push_back(g.Neighbors[k]);
        }
      }
    }
    for (std::size_t l = 0; l < Global.size(); ++l)
    {
      const int i = Global[l];
      int owner = 0;
      while (firstOf(owner + 1) <= i)
      {
        ++owner;
      }
      OwnerRank.push_back(owner);
      OwnerRow.push_back(i - firstOf(owner)); // the owner's rows are its block, in order
      const bool mine = i >= first && i < last;
      for (std::int64_t k = g.Offsets[i]; mine && k < g.Offsets[i + 1]; ++k)
      {
        Neighbors.push_back(local.at(g.Neighbors[k]));
        Weights.push_back(g.Weights[k]);
      }
      Offsets.push_back(static_cast<std::int64_t>(Neighbors.size()));
      Diagonal.push_back(g.Diagonal[i]);
      Shift.push_back(g.Shift[i]);
      B.push_back(g.B[i]);
      Fixed.push_back(g.Fixed[i]);
    }
  }
  Index Rows() const { return static_cast<Index>(Global.size()); }
};

ShiftedLaplacianProblem ProblemOf(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const double* weights, const double* diagonal, const double* shift, const std::uint8_t* fixed)
{
  ShiftedLaplacianProblem pb;
  pb.Rows = rows;
  pb.Offsets = offsets;
  pb.Neighbors = neighbors;
  pb.Weights = weights;
  pb.Diagonal = diagonal;
  pb.Shift = shift;
  pb.Factor = 5.0;
  pb.Fixed = fixed;
  pb.Scale = { 1.0 };
  pb.Tolerance = 1e-12;
  pb.MaximumIterations = 5000;
  return pb;
}

/// The generic CG on D + t K (Jacobi), over `split` when given.
ConjugateGradientResult SolveGeneric(
  const ShiftedLaplacianProblem& pb, const Partition* split, const double* b, double* x)
{
  std::vector<double> diag(static_cast<std::size_t>(pb.Rows));
  for (Index i = 0; i < pb.Rows; ++i)
  {
    diag[i] = pb.Shift[i] + pb.Factor * pb.Diagonal[i];
  }
  ConjugateGradientProblem cg;
  cg.Rows = pb.Rows;
  cg.Diagonal = diag.data();
  cg.Fixed = pb.Fixed;
  cg.Scale = pb.Scale;
  cg.Tolerance = pb.Tolerance;
  cg.MaximumIterations = pb.MaximumIterations;
  cg.Split = split;
  cg.Apply = [&](const double* in, double* out) {
    ApplyGraphStiffness(pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, in, out, 1, 1);
    for (Index i = 0; i < pb.Rows; ++i)
    {
      out[i] = pb.Shift[i] * in[i] + pb.Factor * out[i];
    }
  };
  return SolveConjugateGradient(cg, b, x);
}

} // namespace

TEST(Partition, DistributedSolvesGiveTheSerialSolution)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const MPI_Comm world = MPI_COMM_WORLD;
  const Grid g(40);
  const Piece piece(g, rank, size);
  const Partition split(&world, piece.Rows(), piece.OwnerRank.data(), piece.OwnerRow.data());
  EXPECT_EQ(split.TotalRows(), 1600);
  for (Index l = 0; l < piece.Rows(); ++l)
  {
    EXPECT_EQ(split.GlobalRow(l), piece.Global[l]); // blocks in order: global rows are the grid's
  }
  // Ghost updates bring the owners' values; sums are over the owned rows.
  std::vector<double> values(piece.Rows());
  for (Index l = 0; l < piece.Rows(); ++l)
  {
    values[l] = split.IsOwned(l) ? piece.Global[l] : -1.0;
  }
  split.UpdateGhosts(values.data(), 1);
  double owned = 0.0;
  for (Index l = 0; l < piece.Rows(); ++l)
  {
    EXPECT_EQ(values[l], piece.Global[l]);
    owned += split.IsOwned(l);
  }
  EXPECT_EQ(split.Sum(owned), 1600.0);

  for (Preconditioning m : { Preconditioning::Jacobi, Preconditioning::Multigrid })
  {
    ShiftedLaplacianProblem whole = ProblemOf(static_cast<Index>(g.Diagonal.size()), g.Offsets.data(),
      g.Neighbors.data(), g.Weights.data(), g.Diagonal.data(), g.Shift.data(), g.Fixed.data());
    ShiftedLaplacianProblem local = ProblemOf(piece.Rows(), piece.Offsets.data(), piece.Neighbors.data(),
      piece.Weights.data(), piece.Diagonal.data(), piece.Shift.data(), piece.Fixed.data());
    whole.Preconditioner = local.Preconditioner = m;
    local.Split = &split;
    std::vector<double> serial(g.B.size(), 0.25), ours(piece.Rows(), 0.25);
    const auto solve = [&](const ShiftedLaplacianProblem& pb, const double* b, double* x) {
      return m == Preconditioning::Multigrid ? SolveShiftedLaplacian(pb, b, x) : SolveGeneric(pb, pb.Split, b, x);
    };
    const ConjugateGradientResult rs = solve(whole, g.B.data(), serial.data());
    const ConjugateGradientResult rd = solve(local, piece.B.data(), ours.data());
    EXPECT_TRUE(rs.Converged && rd.Converged);
    double worst = 0.0;
    for (Index l = 0; l < piece.Rows(); ++l) // ghosts too: their owners' results
    {
      worst = std::max(worst, std::abs(ours[l] - serial[piece.Global[l]]));
    }
    EXPECT_LT(worst, 1e-9) << (m == Preconditioning::Multigrid ? "multigrid" : "Jacobi") << " on " << size
                           << " processes, iterations " << rd.Iterations << " (serial " << rs.Iterations << ")";
    if (m == Preconditioning::Multigrid)
    {
      EXPECT_LE(std::abs(rd.Iterations - rs.Iterations), 2) << "the hierarchy spans the processes";
    }
  }
}

TEST(Partition, InconsistentOwnershipThrowsOnEveryProcess)
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const MPI_Comm world = MPI_COMM_WORLD;
  // Every process says its row 0 is its own row 1.
  const int owners[2] = { rank, rank };
  const Index rows[2] = { 1, 1 };
  EXPECT_THROW(Partition(&world, 2, owners, rows), std::runtime_error);
  // A ghost whose owner was not found (rank -1) on the last process only.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int unknown[2] = { rank, rank == size - 1 ? -1 : rank };
  const Index own[2] = { 0, 1 };
  EXPECT_THROW(Partition(&world, 2, unknown, own), std::runtime_error);
}

TEST(Partition, NthSmallestIsTheOrderStatisticOfAllProcesses)
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const MPI_Comm world = MPI_COMM_WORLD;
  // All values (ties, zeros of both signs, subnormals, huge ones), dealt
  // out unevenly: process p takes every value whose index is p mod (size + 1),
  // the last process also the rest.
  std::vector<double> all;
  for (int i = 0; i < 3001; ++i)
  {
    const double x = std::fmod(i * 0.6180339887, 1.0);
    all.push_back(i % 7 == 0 ? 0.25 : i % 11 == 0 ? (i % 2 ? 0.0 : -0.0) : i % 13 == 0 ? 1e-310 * x
        : i % 17 == 0 ? 1e300 * x : x);
  }
  std::vector<double> mine;
  for (std::size_t i = 0; i < all.size(); ++i)
  {
    const int p = static_cast<int>(i % (size + 1));
    if (p == rank || (p == size && rank == size - 1))
    {
      mine.push_back(all[i]);
    }
  }
  const int owner[1] = { rank };
  const Index row[1] = { 0 };
  const Partition split(&world, 1, owner, row);
  for (const std::int64_t k : { std::int64_t(0), std::int64_t(1), std::int64_t(500), std::int64_t(1500),
         std::int64_t(2999), std::int64_t(3000) })
  {
    std::vector<double> sorted = all;
    std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
    EXPECT_EQ(split.NthSmallest(mine, k), sorted[k] + 0.0) << "k " << k;
  }
}

TEST(Partition, DistributedNoiseEstimateIsTheSerialOne)
{
  // Point data on the grid graph (the grid's points at (c, r, 0)): smooth
  // data plus pseudo-random noise of 0.05; every process its block.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const MPI_Comm world = MPI_COMM_WORLD;
  const Grid g(60);
  const Piece piece(g, rank, size);
  const Partition split(&world, piece.Rows(), piece.OwnerRank.data(), piece.OwnerRow.data());
  const auto pointOf = [&](int i, double* p) {
    p[0] = i % g.N;
    p[1] = i / g.N;
    p[2] = 0.0;
  };
  const auto valueOf = [&](int i, double* f) {
    const double x = i % g.N, y = i / g.N;
    f[0] = std::sin(0.1 * x) * std::cos(0.07 * y) + 0.05 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.7548776662, 1.0) - 1.0);
    f[1] = 0.01 * x * y;
  };
  std::vector<double> points(3 * g.Diagonal.size()), values(2 * g.Diagonal.size());
  for (std::size_t i = 0; i < g.Diagonal.size(); ++i)
  {
    pointOf(static_cast<int>(i), &points[3 * i]);
    valueOf(static_cast<int>(i), &values[2 * i]);
  }
  const double serial = EstimateGraphNoise(static_cast<Index>(g.Diagonal.size()), g.Offsets.data(),
    g.Neighbors.data(), points.data(), 2, values.data());
  std::vector<double> localPoints(3 * piece.Global.size()), localValues(2 * piece.Global.size());
  for (std::size_t l = 0; l < piece.Global.size(); ++l)
  {
    pointOf(piece.Global[l], &localPoints[3 * l]);
    valueOf(piece.Global[l], &localValues[2 * l]);
  }
  const double distributed = EstimateGraphNoise(piece.Rows(), piece.Offsets.data(), piece.Neighbors.data(),
    localPoints.data(), 2, localValues.data(), nullptr, &split);
  EXPECT_GT(serial, 0.0);
  EXPECT_EQ(distributed, serial);
}

namespace
{

/// A tetrahedral lattice (Kuhn split of an n^3 grid of points, moved off
/// the grid) cut into slabs of cells along z, one per owning process (with
/// 3 processes the last holds nothing).  A point belongs to the lowest
/// process whose slab holds it; a process holds its slab and the
/// tetrahedra around the points it owns (as vtkBeltramiPieces' Owned
/// stars), its points in ascending global order.
struct Lattice
{
  static constexpr Index N = 9;
  std::vector<Index> Tets = GridTetrahedra(N, N, N);
  int Owners = 1;

  explicit Lattice(int size)
    : Owners(size >= 3 ? size - 1 : size)
  {
  }
  static void Point(Index i, double* x)
  {
    const double c[3] = { double(i % N), double(i / N % N), double(i / (N * N)) };
    for (int a = 0; a < 3; ++a)
    {
      x[a] = c[a] + 0.2 * std::sin(1.3 * c[(a + 1) % 3] + 0.7 * c[(a + 2) % 3] + a);
    }
  }
  int SlabOf(std::size_t tet) const
  {
    const std::size_t layer = tet / (6 * (N - 1) * (N - 1));
    return static_cast<int>(layer * Owners / (N - 1));
  }
  int OwnerOf(Index point) const
  {
    const Index z = point / (N * N);
    for (int p = 0; p < Owners; ++p)
    {
      const Index first = static_cast<Index>((N - 1) * p / Owners), last = static_cast<Index>((N - 1) * (p + 1) / Owners);
      if (z >= first && z <= last)
      {
        return p;
      }
    }
    return -1;
  }
  /// Process p's tetrahedra (global point ids).
  std::vector<Index> TetsOf(int p) const
  {
    std::vector<Index> mine;
    for (std::size_t t = 0; t < Tets.size() / 4; ++t)
    {
      const Index* c = &Tets[4 * t];
      if (SlabOf(t) == p || std::any_of(c, c + 4, [&](Index v) { return OwnerOf(v) == p; }))
      {
        mine.insert(mine.end(), c, c + 4);
      }
    }
    return mine;
  }
  std::vector<Index> PointsOf(int p) const
  {
    const std::vector<Index> tets = TetsOf(p);
    const std::set<Index> points(tets.begin(), tets.end());
    return { points.begin(), points.end() };
  }
};

/// Data flowed as the cube roots of `count` values, their noise measured
/// on the values: the options' ToNoiseSpace and FromNoiseSpace.
void FlowAsCubeRoots(GraphFlowOptions& o, std::size_t count)
{
  o.ToNoiseSpace = [count](double* x) { std::transform(x, x + count, x, [](double v) { return v * v * v; }); };
  o.FromNoiseSpace = [count](double* x) { std::transform(x, x + count, x, [](double v) { return std::cbrt(v); }); };
}

} // namespace

TEST(Partition, DistributedTetrahedralFlowIsTheSerialOne)
{
  // The 3-manifold flow of 2-component data on the lattice split over the
  // processes against the serial run on the whole lattice: the defaults
  // (semi-implicit, least-risk stop, noise estimated) to the solver
  // tolerance, explicit steps to round-off, and data flowed in another
  // space than their noise's (ToNoiseSpace, as log-Euclidean tensors).
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const MPI_Comm world = MPI_COMM_WORLD;
  const Lattice lattice(size);
  const Index n = Lattice::N * Lattice::N * Lattice::N;
  const auto valueOf = [](Index i, double* f) {
    double x[3];
    Lattice::Point(i, x);
    f[0] = (x[0] > 4.0 ? 1.0 : 0.0) + 0.1 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.7548776662, 1.0) - 1.0);
    f[1] = 0.1 * x[1] + 0.05 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.5698402910, 1.0) - 1.0);
  };
  // This process' piece, and the owner and row there of each of its points.
  const std::vector<Index> global = lattice.PointsOf(rank);
  std::map<Index, Index> local;
  for (std::size_t l = 0; l < global.size(); ++l)
  {
    local[global[l]] = static_cast<Index>(l);
  }
  std::vector<Index> tets = lattice.TetsOf(rank);
  for (Index& v : tets)
  {
    v = local.at(v);
  }
  std::vector<int> ownerRank;
  std::vector<Index> ownerRow;
  std::vector<double> points(3 * global.size()), values(2 * global.size());
  for (std::size_t l = 0; l < global.size(); ++l)
  {
    ownerRank.push_back(lattice.OwnerOf(global[l]));
    const std::vector<Index> there = lattice.PointsOf(ownerRank.back());
    ownerRow.push_back(static_cast<Index>(std::lower_bound(there.begin(), there.end(), global[l]) - there.begin()));
    Lattice::Point(global[l], &points[3 * l]);
    valueOf(global[l], &values[2 * l]);
  }
  const Partition split(&world, static_cast<Index>(global.size()), ownerRank.data(), ownerRow.data());
  const TetrahedralMesh piece(static_cast<Index>(global.size()), tets, 1);
  std::vector<double> allPoints(3 * static_cast<std::size_t>(n)), allValues(2 * static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    Lattice::Point(i, &allPoints[3 * i]);
    valueOf(i, &allValues[2 * i]);
  }
  const TetrahedralMesh whole(n, lattice.Tets, 1);
  EXPECT_NEAR(piece.MeanEdgeLength(points.data(), &split), whole.MeanEdgeLength(allPoints.data()), 1e-14);

  GraphFlowOptions defaults = GraphFlowOptions::ForMeshes();
  defaults.NumberOfThreads = 1;
  GraphFlowOptions explicitSteps = defaults;
  explicitSteps.Integration = GraphFlowIntegration::Explicit;
  explicitSteps.AdaptiveTimeStep = true;
  explicitSteps.Stop = GraphFlowStop::Iterations;
  explicitSteps.NumberOfIterations = 30;
  // (The third case flows the cube roots of the data, the noise measured
  // on the data: ToNoiseSpace, as log-Euclidean tensors.)
  for (const auto& [options, tolerance, cubeRoots] :
    { std::tuple{ defaults, 1e-6, false }, { explicitSteps, 1e-11, false }, { defaults, 1e-6, true } })
  {
    std::vector<double> serial = allValues, distributed = values;
    GraphFlowOptions wholeOptions = options, pieceOptions = options;
    if (cubeRoots)
    {
      for (std::vector<double>* data : { &serial, &distributed })
      {
        std::transform(data->begin(), data->end(), data->begin(), [](double v) { return std::cbrt(v); });
      }
      FlowAsCubeRoots(wholeOptions, serial.size());
      FlowAsCubeRoots(pieceOptions, distributed.size());
    }
    const GraphFlowResult a = RunTetrahedralGraphFlow(whole, allPoints.data(), 2, serial.data(), nullptr, wholeOptions);
    const GraphFlowResult b =
      RunTetrahedralGraphFlow(piece, points.data(), 2, distributed.data(), nullptr, pieceOptions, {}, nullptr, &split);
    ASSERT_TRUE(a.Error.empty() && b.Error.empty()) << a.Error << b.Error;
    EXPECT_GT(a.Iterations, 2);
    EXPECT_EQ(a.Iterations, b.Iterations);
    EXPECT_NEAR(a.EstimatedNoiseLevel, b.EstimatedNoiseLevel, 1e-15);
    EXPECT_NEAR(a.FinalRisk, b.FinalRisk, 1e-6 * a.InitialRisk + 1e-15);
    double moved = 0.0, difference = 0.0;
    for (Index i = 0; i < n; ++i)
    {
      for (int k = 0; k < 2; ++k)
      {
        double f[2];
        valueOf(i, f);
        moved = std::max(moved, std::abs(serial[2 * i + k] - (cubeRoots ? std::cbrt(f[k]) : f[k])));
      }
    }
    for (std::size_t l = 0; l < global.size(); ++l)
    {
      for (int k = 0; split.IsOwned(static_cast<Index>(l)) && k < 2; ++k)
      {
        difference = std::max(difference, std::abs(distributed[2 * l + k] - serial[2 * global[l] + k]));
      }
    }
    EXPECT_GT(moved, 0.01);
    EXPECT_LE(difference, tolerance * moved) << "a distributed run of " << a.Iterations << " steps";
  }
}

namespace
{

/// A grid of whole[0] x whole[1] x whole[2] samples split along `axis` into
/// slabs of sample planes, one per owning process, neighbours sharing their
/// boundary plane (as VTK's piece extents; with 3 processes the last holds
/// nothing); a process's piece is its slab and a ring of one sample where
/// the grid goes on, and a sample belongs to the lowest process whose slab
/// holds it.
struct GridSplit
{
  std::int64_t Whole[3];
  int Axis = 0, Owners = 1;

  GridSplit(std::int64_t x, std::int64_t y, std::int64_t z, int axis, int size)
    : Whole{ x, y, z }
    , Axis(axis)
    , Owners(size >= 3 ? size - 1 : size)
  {
  }
  /// The slab of process p: planes [first, last] along Axis (empty: last < first).
  std::pair<std::int64_t, std::int64_t> Slab(int p) const
  {
    if (p >= Owners)
    {
      return { 0, -1 };
    }
    const std::int64_t cells = Whole[Axis] - 1;
    return { cells * p / Owners, cells * (p + 1) / Owners };
  }
  /// The box of process p's piece: first sample and size per axis.
  void Box(int p, std::int64_t* origin, std::int64_t* size) const
  {
    const auto [first, last] = Slab(p);
    for (int a = 0; a < 3; ++a)
    {
      origin[a] = a != Axis ? 0 : std::max<std::int64_t>(0, first - 1);
      size[a] = a != Axis ? Whole[a] : (last < first ? 0 : std::min(Whole[a] - 1, last + 1) - origin[a] + 1);
    }
    if (last < first)
    {
      size[0] = size[1] = size[2] = 0;
    }
  }
  int OwnerOf(std::int64_t plane) const
  {
    for (int p = 0; p < Owners; ++p)
    {
      if (plane >= Slab(p).first && plane <= Slab(p).second)
      {
        return p;
      }
    }
    return -1;
  }
  /// This process's piece (origin, size) and its owners and rows there.
  void Piece(int rank, std::int64_t* origin, std::int64_t* size, std::vector<int>& ownerRank,
    std::vector<Index>& ownerRow) const
  {
    Box(rank, origin, size);
    for (std::int64_t z = 0; z < size[2]; ++z)
    {
      for (std::int64_t y = 0; y < size[1]; ++y)
      {
        for (std::int64_t x = 0; x < size[0]; ++x)
        {
          const std::int64_t g[3] = { x + origin[0], y + origin[1], z + origin[2] };
          const int owner = OwnerOf(g[Axis]);
          std::int64_t o[3], n[3];
          Box(owner, o, n);
          ownerRank.push_back(owner);
          ownerRow.push_back(static_cast<Index>(((g[2] - o[2]) * n[1] + g[1] - o[1]) * n[0] + g[0] - o[0]));
        }
      }
    }
  }
};

/// Noisy data with a jump: 2 components per sample of the whole grid.
void GridValue(const std::int64_t* whole, std::int64_t x, std::int64_t y, std::int64_t z, double* f)
{
  const std::int64_t i = (z * whole[1] + y) * whole[0] + x;
  f[0] = (x + 0.5 * y > 0.6 * whole[0] ? 1.0 : 0.0) + 0.1 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.7548776662, 1.0) - 1.0);
  f[1] = 0.05 * z + 0.05 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.5698402910, 1.0) - 1.0);
}

} // namespace

TEST(Partition, DistributedGridFlowsAreTheSerialOnes)
{
  // The image flow (split along y) and the volume flow (split along x, so
  // that rows are cut) on 2-component data, against serial runs on the
  // whole grid: the defaults (explicit steps, least-risk stop, noise
  // estimated), semi-implicit steps and the noise-level stop.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const MPI_Comm world = MPI_COMM_WORLD;
  GraphFlowOptions semi;
  semi.Integration = GraphFlowIntegration::SemiImplicit;
  GraphFlowOptions noiseLevel;
  noiseLevel.Stop = GraphFlowStop::NoiseLevel;
  for (const bool volume : { false, true })
  {
    const GridSplit grid = volume ? GridSplit(23, 17, 12, 0, size) : GridSplit(37, 41, 1, 1, size);
    GridPiece piece;
    std::int64_t n[3];
    std::vector<int> ownerRank;
    std::vector<Index> ownerRow;
    grid.Piece(rank, piece.Origin, n, ownerRank, ownerRow);
    std::copy(grid.Whole, grid.Whole + 3, piece.Whole);
    const Partition split(&world, static_cast<Index>(ownerRank.size()), ownerRank.data(), ownerRow.data());
    piece.Split = &split;
    const auto valuesOf = [&](const std::int64_t* origin, const std::int64_t* box) {
      std::vector<double> v;
      for (std::int64_t z = 0; z < box[2]; ++z)
      {
        for (std::int64_t y = 0; y < box[1]; ++y)
        {
          for (std::int64_t x = 0; x < box[0]; ++x)
          {
            double f[2];
            GridValue(grid.Whole, x + origin[0], y + origin[1], z + origin[2], f);
            v.insert(v.end(), f, f + 2);
          }
        }
      }
      return v;
    };
    const std::int64_t zero[3] = { 0, 0, 0 };
    const std::vector<double> input = valuesOf(zero, grid.Whole);
    for (const auto& [options, tolerance] :
      { std::pair{ GraphFlowOptions{}, 1e-9 }, { semi, 1e-6 }, { noiseLevel, 1e-9 } })
    {
      GraphFlowOptions o = options;
      o.NumberOfThreads = 1;
      std::vector<double> serial = input, distributed = valuesOf(piece.Origin, n);
      const auto run = [&](double* values, const std::int64_t* box, const GridPiece* p) {
        if (volume)
        {
          VoxelGrid g;
          g.Width = box[0], g.Height = box[1], g.Depth = box[2];
          return RunVolumeGraphFlow(g, 2, values, nullptr, o, {}, p);
        }
        PixelGrid g;
        g.Width = static_cast<Index>(box[0]), g.Height = static_cast<Index>(box[1]);
        return RunImageGraphFlow(g, 2, values, nullptr, o, {}, p);
      };
      const GraphFlowResult a = run(serial.data(), grid.Whole, nullptr);
      const GraphFlowResult b = run(distributed.data(), n, &piece);
      ASSERT_TRUE(a.Error.empty() && b.Error.empty()) << a.Error << b.Error;
      EXPECT_GT(a.Iterations, 2);
      EXPECT_EQ(a.Iterations, b.Iterations);
      EXPECT_EQ(a.EstimatedNoiseLevel, b.EstimatedNoiseLevel);
      EXPECT_NEAR(a.FinalArea, b.FinalArea, 1e-12 * a.FinalArea);
      EXPECT_NEAR(a.FinalRisk, b.FinalRisk, 1e-6 * a.InitialRisk + 1e-15);
      double moved = 0.0, difference = 0.0;
      for (std::size_t k = 0; k < serial.size(); ++k)
      {
        moved = std::max(moved, std::abs(serial[k] - input[k]));
      }
      for (std::int64_t l = 0; l < n[0] * n[1] * n[2]; ++l)
      {
        const std::int64_t x = l % n[0] + piece.Origin[0], y = l / n[0] % n[1] + piece.Origin[1],
                           z = l / (n[0] * n[1]) + piece.Origin[2];
        const std::int64_t g = (z * grid.Whole[1] + y) * grid.Whole[0] + x;
        for (int k = 0; k < 2; ++k)
        {
          difference = std::max(difference, std::abs(distributed[2 * l + k] - serial[2 * g + k]));
        }
      }
      EXPECT_GT(moved, 0.05);
      EXPECT_LE(difference, tolerance * moved)
        << (volume ? "volume" : "image") << ", " << a.Iterations << " steps, integration "
        << static_cast<int>(o.Integration);
    }
  }
}

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int failed = RUN_ALL_TESTS();
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
