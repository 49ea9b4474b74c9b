// The core's distributed solves (Solvers/Partition) over MPI processes,
// VTK-free: run by ctest under mpirun on 1, 2 and 3 processes.  A grid
// graph's rows are split in blocks (the last of 3 processes owns none); each
// process holds its block and the ghost copies of the block's neighbours.
// The distributed conjugate gradient (Jacobi, and multigrid with one
// BoomerAMG hierarchy over the processes) must give every process' rows of
// the serial solution, which each process also computes whole.
#include "Flows/NoiseEstimation.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Solvers/Partition.h"
#include "Solvers/SparseGraph.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
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
