// The core's distributed solves (Solvers/Partition) over MPI processes,
// VTK-free: run by ctest under mpirun on 1, 2 and 3 processes.  A grid
// graph's rows are split in blocks (the last of 3 processes owns none); each
// process holds its block and the ghost copies of the block's neighbours.
// The distributed conjugate gradient (Jacobi, and multigrid with one
// BoomerAMG hierarchy over the processes) must give every process' rows of
// the serial solution, which each process also computes whole.  The
// algorithms that run over the processes (flows, the parameterization, the
// line drawing) are checked the same way against their serial runs.
#include "Drawing/LineDrawing.h"
#include "Drawing/Visibility.h"
#include "Flows/GraphFlow.h"
#include "Flows/NoiseEstimation.h"
#include "Maps/Parameterization.h"
#include "Mesh/Tetrahedra.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/Partition.h"
#include "Solvers/SparseGraph.h"
#include "Solvers/TestMPI.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
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

/// The grid's system solved whole and as this process's piece over
/// `split`, both set up by `setUp(problem)` and solved by `solve`: the two
/// results, and the largest difference of the piece's rows (ghosts too:
/// their owners' results) from the serial solution, and of the serial
/// solution itself there.
struct BothWays
{
  ConjugateGradientResult Serial, Distributed;
  double Difference = 0.0, Largest = 0.0;
};

template <class SetUp, class Solve>
BothWays SolvedBothWays(const Grid& g, const Piece& piece, const Partition& split, SetUp setUp, Solve solve)
{
  ShiftedLaplacianProblem whole = ProblemOf(static_cast<Index>(g.Diagonal.size()), g.Offsets.data(),
    g.Neighbors.data(), g.Weights.data(), g.Diagonal.data(), g.Shift.data(), g.Fixed.data());
  ShiftedLaplacianProblem local = ProblemOf(piece.Rows(), piece.Offsets.data(), piece.Neighbors.data(),
    piece.Weights.data(), piece.Diagonal.data(), piece.Shift.data(), piece.Fixed.data());
  local.Split = &split;
  setUp(whole);
  setUp(local);
  std::vector<double> serial(g.B.size(), 0.25), ours(piece.Rows(), 0.25);
  BothWays r;
  r.Serial = solve(whole, g.B.data(), serial.data());
  r.Distributed = solve(local, piece.B.data(), ours.data());
  for (Index l = 0; l < piece.Rows(); ++l)
  {
    r.Difference = std::max(r.Difference, std::abs(ours[l] - serial[piece.Global[l]]));
    r.Largest = std::max(r.Largest, std::abs(serial[piece.Global[l]]));
  }
  return r;
}

} // namespace

TEST(Partition, DistributedSolvesGiveTheSerialSolution)
{
  const auto [rank, size] = RankAndSize();
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
    const BothWays r = SolvedBothWays(
      g, piece, split, [&](ShiftedLaplacianProblem& pb) { pb.Preconditioner = m; },
      [&](const ShiftedLaplacianProblem& pb, const double* b, double* x) {
        return m == Preconditioning::Multigrid ? SolveShiftedLaplacian(pb, b, x) : SolveGeneric(pb, pb.Split, b, x);
      });
    const ConjugateGradientResult &rs = r.Serial, &rd = r.Distributed;
    EXPECT_TRUE(rs.Converged && rd.Converged);
    EXPECT_LT(r.Difference, 1e-9) << (m == Preconditioning::Multigrid ? "multigrid" : "Jacobi") << " on " << size
                                  << " processes, iterations " << rd.Iterations << " (serial " << rs.Iterations << ")";
    if (m == Preconditioning::Multigrid)
    {
      EXPECT_LE(std::abs(rd.Iterations - rs.Iterations), 2) << "the hierarchy spans the processes";
    }
  }

  // Each process cycles on its own rows' hierarchy, and a coarse level made
  // of every process's coarsest one joins them. Split over two processes,
  // the 40 x 40 grid's pieces (800 rows and their ghosts) are each a single
  // level, so the joining level is the whole operator and the balanced
  // cycle solves exactly: a wrong coupling between the processes would show
  // in the iterations as well as in the solution. One process: the serial
  // grid's two levels.
  const auto pointsOf = [&](const std::vector<Index>& rows) {
    std::vector<double> p;
    for (const Index i : rows)
    {
      p.insert(p.end(), { static_cast<double>(i % g.N), static_cast<double>(i / g.N), 0.0 });
    }
    return p;
  };
  std::vector<Index> all(g.Diagonal.size());
  std::iota(all.begin(), all.end(), 0);
  const std::vector<double> wholePoints = pointsOf(all), piecePoints = pointsOf(piece.Global);
  for (const bool squared : { false, true })
  {
    const BothWays r = SolvedBothWays(
      g, piece, split,
      [&](ShiftedLaplacianProblem& pb) {
        pb.Preconditioner = Preconditioning::GeometricMultigrid;
        pb.Factor = squared ? 400.0 : 50.0;
        pb.Tolerance = 1e-11;
        pb.Points = pb.Split ? piecePoints.data() : wholePoints.data();
      },
      squared ? SolveSquaredLaplacian : SolveShiftedLaplacian);
    const ConjugateGradientResult &rs = r.Serial, &rd = r.Distributed;
    EXPECT_TRUE(rs.Converged && rd.Converged);
    EXPECT_LT(r.Difference, 1e-9 * std::max(1.0, r.Largest)) << (squared ? "order 2" : "order 1") << " on " << size
                                                             << " processes";
    if (size > 1)
    {
      EXPECT_LE(rd.Iterations, 2) << (squared ? "order 2" : "order 1") << ": the joining level is the whole operator"
                                  << " (serial " << rs.Iterations << ")";
    }
    else
    {
      EXPECT_LE(rd.Iterations, rs.Iterations + 2) << (squared ? "order 2" : "order 1");
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
  const auto [rank, size] = RankAndSize();
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
  // data plus pseudo-random noise of 0.05; every process its block.  Also
  // with the columns x < 25 exactly 0 (flat data, where the estimate leaves
  // out the samples next to them).
  const auto [rank, size] = RankAndSize();
  const MPI_Comm world = MPI_COMM_WORLD;
  const Grid g(60);
  const Piece piece(g, rank, size);
  const Partition split(&world, piece.Rows(), piece.OwnerRank.data(), piece.OwnerRow.data());
  const auto pointOf = [&](int i, double* p) {
    p[0] = i % g.N;
    p[1] = i / g.N;
    p[2] = 0.0;
  };
  for (const bool masked : { false, true })
  {
    const auto valueOf = [&](int i, double* f) {
      const double x = i % g.N, y = i / g.N;
      const bool flat = masked && x < 25;
      f[0] = flat ? 0.0
                  : std::sin(0.1 * x) * std::cos(0.07 * y) +
          0.05 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.7548776662, 1.0) - 1.0);
      f[1] = flat ? 0.0 : 0.01 * x * y;
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
    EXPECT_EQ(distributed, serial) << (masked ? "masked" : "");
  }
}

namespace
{

/// A lattice of cells cut into slabs along its last axis, one per owning
/// process (with 3 processes the last holds nothing): the Kuhn tetrahedra
/// of a 9^3 grid of points moved off the grid (Dimension 3), or the
/// triangles of a 17^2 height field, a disk (Dimension 2).  A point belongs
/// to the lowest process whose slab holds it; a process holds its slab and
/// the cells around the points it owns (as vtkBeltramiPieces' Owned stars),
/// its points in ascending global order.
struct Lattice
{
  int Dimension = 3;
  Index N = 9;
  std::vector<Index> Cells;
  int Owners = 1;

  /// `n` points a side (0: 9 in 3D, 17 in 2D).
  explicit Lattice(int size, int dimension = 3, Index n = 0)
    : Dimension(dimension)
    , N(n > 0 ? n : dimension == 3 ? 9 : 17)
    , Owners(size >= 3 ? size - 1 : size)
  {
    if (dimension == 3)
    {
      Cells = GridTetrahedra(N, N, N);
      return;
    }
    for (Index j = 0; j + 1 < N; ++j)
    {
      for (Index i = 0; i + 1 < N; ++i)
      {
        const Index a = j * N + i;
        Cells.insert(Cells.end(), { a, a + 1, a + N + 1, a, a + N + 1, a + N });
      }
    }
  }
  int Corners() const { return Dimension + 1; }
  /// The whole lattice's points, 3 coordinates each (the serial runs').
  std::vector<double> AllPoints() const
  {
    std::vector<double> all(3 * static_cast<std::size_t>(NumberOfPoints()));
    for (Index i = 0; i < NumberOfPoints(); ++i)
    {
      Point(i, &all[3 * i]);
    }
    return all;
  }
  Index PointsPerLayer() const { return Dimension == 3 ? N * N : N; }
  Index NumberOfPoints() const { return PointsPerLayer() * N; }
  void Point(Index i, double* x) const
  {
    if (Dimension == 2)
    {
      x[0] = double(i % N) / (N - 1);
      x[1] = double(i / N) / (N - 1);
      x[2] = 0.1 * std::sin(6.0 * x[0]) * std::cos(5.0 * x[1]);
      return;
    }
    const double c[3] = { double(i % N), double(i / N % N), double(i / (N * N)) };
    for (int a = 0; a < 3; ++a)
    {
      x[a] = c[a] + 0.2 * std::sin(1.3 * c[(a + 1) % 3] + 0.7 * c[(a + 2) % 3] + a);
    }
  }
  int SlabOf(std::size_t cell) const
  {
    const std::size_t perLayer = Dimension == 3 ? 6 * (N - 1) * (N - 1) : 2 * (N - 1);
    return static_cast<int>(cell / perLayer * Owners / (N - 1));
  }
  int OwnerOf(Index point) const
  {
    const Index z = point / PointsPerLayer();
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
  /// Process p's cells (global point ids).
  std::vector<Index> CellsOf(int p) const
  {
    std::vector<Index> mine;
    const int k = Corners();
    for (std::size_t t = 0; t < Cells.size() / k; ++t)
    {
      const Index* c = &Cells[k * t];
      if (SlabOf(t) == p || std::any_of(c, c + k, [&](Index v) { return OwnerOf(v) == p; }))
      {
        mine.insert(mine.end(), c, c + k);
      }
    }
    return mine;
  }
  std::vector<Index> PointsOf(int p) const
  {
    const std::vector<Index> cells = CellsOf(p);
    const std::set<Index> points(cells.begin(), cells.end());
    return { points.begin(), points.end() };
  }
};

/// Process `rank`'s piece of a lattice: its points (global ids, coordinates),
/// its cells over local ids, and the owner and row there of each point.
struct LatticePiece
{
  std::vector<Index> Global, Cells, OwnerRow;
  std::vector<int> OwnerRank;
  std::vector<double> Points;

  LatticePiece(const Lattice& lattice, int rank)
    : Global(lattice.PointsOf(rank))
    , Cells(lattice.CellsOf(rank))
    , Points(3 * Global.size())
  {
    std::map<Index, Index> local;
    for (std::size_t l = 0; l < Global.size(); ++l)
    {
      local[Global[l]] = static_cast<Index>(l);
    }
    for (Index& v : Cells)
    {
      v = local.at(v);
    }
    for (std::size_t l = 0; l < Global.size(); ++l)
    {
      OwnerRank.push_back(lattice.OwnerOf(Global[l]));
      const std::vector<Index> there = lattice.PointsOf(OwnerRank.back());
      OwnerRow.push_back(static_cast<Index>(std::lower_bound(there.begin(), there.end(), Global[l]) - there.begin()));
      lattice.Point(Global[l], &Points[3 * l]);
    }
  }
  Index Rows() const { return static_cast<Index>(Global.size()); }
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
  const auto [rank, size] = RankAndSize();
  const MPI_Comm world = MPI_COMM_WORLD;
  const Lattice lattice(size);
  const Index n = lattice.NumberOfPoints();
  const auto valueOf = [&lattice](Index i, double* f) {
    double x[3];
    lattice.Point(i, x);
    f[0] = (x[0] > 4.0 ? 1.0 : 0.0) + 0.1 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.7548776662, 1.0) - 1.0);
    f[1] = 0.1 * x[1] + 0.05 * std::sqrt(3.0) * (2.0 * std::fmod(i * 0.5698402910, 1.0) - 1.0);
  };
  // This process' piece, and the owner and row there of each of its points.
  const LatticePiece mine(lattice, rank);
  const std::vector<Index>& global = mine.Global;
  const std::vector<double>& points = mine.Points;
  std::vector<double> values(2 * global.size());
  for (std::size_t l = 0; l < global.size(); ++l)
  {
    valueOf(global[l], &values[2 * l]);
  }
  const Partition split(&world, mine.Rows(), mine.OwnerRank.data(), mine.OwnerRow.data());
  const TetrahedralMesh piece(mine.Rows(), mine.Cells, 1);
  std::vector<double> allPoints(3 * static_cast<std::size_t>(n)), allValues(2 * static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    lattice.Point(i, &allPoints[3 * i]);
    valueOf(i, &allValues[2 * i]);
  }
  const TetrahedralMesh whole(n, lattice.Cells, 1);
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
  const auto [rank, size] = RankAndSize();
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

TEST(Partition, DistributedParameterizationIsTheSerialOne)
{
  // The conformal map of a height-field disk split over the processes (the
  // last of 3 holding nothing) against the serial direct solve on the whole
  // disk: circle and square boundaries (the outer loop starting at the
  // lowest point id, as in serial), the distortion figures over the
  // processes; a NaN point in one piece: the same error on every process.
  const auto [rank, size] = RankAndSize();
  const MPI_Comm world = MPI_COMM_WORLD;
  const Lattice lattice(size, 2);
  const LatticePiece mine(lattice, rank);
  const Partition split(&world, mine.Rows(), mine.OwnerRank.data(), mine.OwnerRow.data());
  const MeshTopology piece(mine.Rows(), IndexArray(mine.Cells.begin(), mine.Cells.end()), 1);
  const std::vector<double> all = lattice.AllPoints();
  const MeshTopology whole(lattice.NumberOfPoints(), IndexArray(lattice.Cells.begin(), lattice.Cells.end()), 1);
  const std::vector<std::int64_t> ids(mine.Global.begin(), mine.Global.end());
  for (const ParameterizationBoundary boundary : { ParameterizationBoundary::Circle, ParameterizationBoundary::Square })
  {
    ParameterizationOptions o;
    o.Boundary = boundary;
    o.NumberOfThreads = 1;
    const ParameterizationResult a = Parameterize(whole, all.data(), o);
    const ParameterizationResult b = Parameterize(piece, mine.Points.data(), o, split, ids.data());
    ASSERT_TRUE(a.Error.empty() && b.Error.empty()) << a.Error << b.Error;
    double difference = 0.0;
    for (std::size_t l = 0; l < mine.Global.size(); ++l) // owned and ghost rows
    {
      for (int k = 0; k < 2; ++k)
      {
        difference = std::max(difference, std::abs(b.UV[2 * l + k] - a.UV[2 * mine.Global[l] + k]));
      }
    }
    EXPECT_LE(difference, 1e-9) << "in " << b.Iterations << " iterations";
    EXPECT_EQ(b.OuterRows.size(), a.OuterBoundary.size());
    const DistortionReport da = MeasureDistortion(whole, all.data(), a.UV.data(), 1);
    const DistortionReport db = MeasureDistortion(piece, mine.Points.data(), b.UV.data(), 1, &split);
    EXPECT_NEAR(da.MeanAngle, db.MeanAngle, 1e-8 * da.MeanAngle);
    EXPECT_NEAR(da.MaxEdge, db.MaxEdge, 1e-8 * da.MaxEdge);
    EXPECT_EQ(da.FlippedTriangles, db.FlippedTriangles);
  }
  std::vector<double> bad = mine.Points;
  if (rank == 0 && !bad.empty())
  {
    bad[0] = std::numeric_limits<double>::quiet_NaN();
  }
  const ParameterizationResult c = Parameterize(piece, bad.data(), ParameterizationOptions{}, split, ids.data());
  EXPECT_NE(c.Error.find("non-finite"), std::string::npos) << c.Error;
}

/// Per type: the lines' count, their points (each within 1e-9 of one of
/// the other's), strengths and Hidden flags.
void ExpectSameLines(const LineSet& ours, const LineSet& serial)
{
  for (int type = 0; type < NumberOfLineTypes; ++type)
  {
    std::vector<Index> mineLines, theirLines;
    const auto pointsOf = [type](const LineSet& lines, std::vector<Index>& count) {
      std::vector<std::array<double, 5>> out; // x, y, z, strength, hidden
      for (Index l = 0; l < lines.NumberOfLines(); ++l)
      {
        if (lines.Type[l] == type)
        {
          count.push_back(l);
          for (Index k = lines.Offsets[l]; k < lines.Offsets[l + 1]; ++k)
          {
            const Index p = lines.Connectivity[k];
            out.push_back({ lines.Points[3 * p], lines.Points[3 * p + 1], lines.Points[3 * p + 2],
              lines.PointStrength[p], lines.Hidden.empty() ? 0.0 : double(lines.Hidden[l]) });
          }
        }
      }
      std::sort(out.begin(), out.end());
      return out;
    };
    const auto x = pointsOf(ours, mineLines), y = pointsOf(serial, theirLines);
    std::printf("type %d: %zu lines, %zu points\n", type, theirLines.size(), y.size());
    EXPECT_EQ(mineLines.size(), theirLines.size()) << "type " << type;
    ASSERT_EQ(x.size(), y.size()) << "type " << type;
    for (std::size_t k = 0; k < x.size(); ++k)
    {
      for (int c = 0; c < 5; ++c)
      {
        EXPECT_NEAR(x[k][c], y[k][c], 1e-9) << "type " << type;
      }
    }
  }
}

TEST(Partition, DistributedLineDrawingIsTheSerialOne)
{
  // The line drawing of a height field split over the processes (the last
  // of 3 holding nothing) against the serial one of the whole field: the
  // curvature derivatives of every row (owned and ghost), and on process 0
  // (which chains the gathered segments) the same polylines of every type,
  // with the hysteresis and minimum length that need whole lines.
  const auto [rank, size] = RankAndSize();
  const MPI_Comm world = MPI_COMM_WORLD;
  const Lattice lattice(size, 2, 49);
  const LatticePiece mine(lattice, rank);
  const auto split = std::make_shared<Partition>(&world, mine.Rows(), mine.OwnerRank.data(), mine.OwnerRow.data());
  const MeshTopology piece(mine.Rows(), IndexArray(mine.Cells.begin(), mine.Cells.end()), 1);
  const std::vector<double> all = lattice.AllPoints();
  const MeshTopology whole(lattice.NumberOfPoints(), IndexArray(lattice.Cells.begin(), lattice.Cells.end()), 1);
  LineDrawingGeometry a, b;
  a.Build(whole, all.data(), 1);
  b.Build(piece, mine.Points.data(), 1, split);
  EXPECT_EQ(a.UndefinedVertices, b.UndefinedVertices); // (the boundary, over the processes)
  EXPECT_DOUBLE_EQ(a.AutomaticFeatureSize(), b.AutomaticFeatureSize());
  double difference = 0.0;
  for (std::size_t l = 0; l < mine.Global.size(); ++l)
  {
    for (int k = 0; k < 4; ++k)
    {
      const double x = a.Derivatives[4 * mine.Global[l] + k], y = b.Derivatives[4 * l + k];
      EXPECT_EQ(std::isfinite(x), std::isfinite(y));
      difference = std::isfinite(x) ? std::max(difference, std::abs(x - y)) : difference;
    }
  }
  EXPECT_LE(difference, 1e-10);
  LineDrawingOptions o;
  std::fill(o.Draw, o.Draw + NumberOfLineTypes, true);
  o.FeatureSize = 0.3; // (the field's curvatures reach about 4)
  o.HysteresisRatio = 0.5;
  o.MinimumLength = 0.5;
  o.NumberOfThreads = 1;
  LineView view;
  view.Position = Vec3(0.5, -1.5, 1.2);
  const LineSet serial = DrawLines(a, view, o), ours = DrawLines(b, view, o);
  // Visibility, seen from low over the field (its crests hide the troughs
  // behind them): each process casts the rays through its own triangles.
  LineView low;
  low.Position = Vec3(0.5, -1.0, 0.25);
  VisibilityOptions keep;
  keep.KeepHidden = true;
  keep.NumberOfThreads = 1;
  const LineSet serialSeen = SplitByVisibility(DrawLines(a, low, o), a, low, keep);
  const LineSet oursSeen = SplitByVisibility(DrawLines(b, low, o), b, low, keep); // (collective)
  if (rank != 0)
  {
    EXPECT_EQ(ours.NumberOfLines(), 0);
    EXPECT_EQ(oursSeen.NumberOfLines(), 0);
    return;
  }
  ExpectSameLines(ours, serial);
  ExpectSameLines(oursSeen, serialSeen);
  const auto hidden = std::count(serialSeen.Hidden.begin(), serialSeen.Hidden.end(), 1);
  std::printf("visibility: %zu lines, %d hidden\n", serialSeen.Hidden.size(), int(hidden));
  EXPECT_GT(hidden, 5);
  EXPECT_LT(hidden, serialSeen.NumberOfLines() - 5);
  EXPECT_GT(serial.NumberOfLines(), 10);
}
