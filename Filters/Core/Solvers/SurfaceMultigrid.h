// Beltrami core: geometric multigrid on a hierarchy of the surface's own
// vertices, the preconditioner of the conjugate gradients on D + t K (the
// implicit fairing steps, the graph flows' semi-implicit steps, harmonic
// extensions) where the rows are the vertices of a surface with positions.
//
// The hierarchy (SurfaceHierarchy) depends on the graph and the points only,
// so it is built once per mesh and kept across steps and time steps:
//  - each coarser level samples the vertices of the finer one: a maximal set
//    of vertices at least three edges apart, taken in the rows' locality
//    order (about one vertex in eight on a triangle mesh);
//  - every finer vertex joins the sample nearest along the edges (a
//    multi-source Dijkstra over the edge lengths); two samples are joined on
//    the coarser level where their regions touch;
//  - prolongation: a finer vertex takes the barycentric coordinates of its
//    projection onto the coarse triangle around its sample that holds it
//    best (clamped to the triangle, so the weights are a partition of unity
//    and non-negative), the nearest coarse edge where its sample has no
//    triangle, the sample itself where it has no neighbour.
// (The construction follows the published descriptions of surface
// multigrid by sampling, Wiersma et al. 2023, "Fast Geometric Multigrid";
// Liu et al. 2021: coarse levels from the fine vertices, prolongation from
// a few nearest coarse ones, Galerkin coarse operators.)
//
// SurfaceMultigrid holds one operator A = D + t K over a hierarchy: the
// Galerkin operators P^T A P of every level (computed as P^T D P and
// P^T K P, so that a change of t costs only the coarsest factorization),
// and applies one symmetric V-cycle: symmetric Gauss-Seidel sweeps on blocks
// of rows (Gauss-Seidel within a block of ParallelChunkSize rows, the other
// blocks' values from the sweep's start: parallel, and the same result for
// any thread count), an exact (Cholesky) solve on the coarsest level.  For
// the order-2 systems D + t K D^-1 K it also cycles on the complex
// symmetric D + i sqrt(t) K in complex arithmetic (the COCG of
// SolveSquaredLaplacian): on spheres of 1k to 263k vertices 7-8 COCG
// iterations where a real V-cycle of D + sqrt(t) K as preconditioner took
// 18-20 (its preconditioned spectrum lies on a half circle from 1 to i).
#pragma once

#include "Support/LargeBuffer.h"
#include "Support/Parallel.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace beltrami
{

/// A sparse matrix in CSR form with the diagonal apart (Values: the
/// off-diagonal entries).
struct LevelMatrix
{
  LargeVector<std::int64_t> Offsets{ 0 };
  LargeVector<Index> Columns;
  LargeVector<double> Values;
  LargeVector<double> Diagonal;

  Index Rows() const { return static_cast<Index>(Diagonal.size()); }
};

/// The transpose of a matrix with `columns` columns stored without
/// diagonal (a prolongation: its restriction).
LevelMatrix Transposed(const LevelMatrix& a, Index columns);

class SurfaceHierarchy
{
public:
  /// The hierarchy of a graph (CSR, symmetric, no self-loops) whose rows
  /// are points (3 coordinates per row).  Rows are renumbered in locality
  /// order internally.
  SurfaceHierarchy(Index rows, const std::int64_t* offsets, const Index* neighbors, const double* points,
    int numThreads = 0);

  /// Levels, the finest (the input's rows) first.
  int Levels() const { return static_cast<int>(Sizes.size()); }
  Index Rows(int level) const { return Sizes[level]; }

  /// The prolongation from level l + 1 to level l: row i of level l (in
  /// the renumbered order) is sum_k Weights[k] x[Columns[k]].
  const LevelMatrix& Prolongation(int level) const { return Prolongations[level]; }
  /// Its transpose.
  const LevelMatrix& Restriction(int level) const { return Restrictions[level]; }

  /// Row `Order[i]` of the input is row i of the finest level.
  const std::vector<Index>& Order() const { return FineOrder; }
  const std::vector<Index>& Position() const { return FinePosition; }

private:
  std::vector<Index> Sizes;
  std::vector<LevelMatrix> Prolongations, Restrictions; // Diagonal unused
  std::vector<Index> FineOrder, FinePosition;
};

class SurfaceMultigrid
{
public:
  /// The V-cycle of A = D + t K, K a graph Laplacian stiffness in CSR form
  /// (K_ii = diagonal[i], K_ij = -weights[k]; the graph of the hierarchy),
  /// D = shift (nullptr: 0), t = factor; rows marked in `held` (optional)
  /// are identity rows, and the couplings to them are left out.
  SurfaceMultigrid(std::shared_ptr<const SurfaceHierarchy> hierarchy, const std::int64_t* offsets,
    const Index* neighbors, const double* weights, const double* diagonal, const double* shift, double factor,
    const std::uint8_t* held, int numThreads = 0);
  ~SurfaceMultigrid();
  SurfaceMultigrid(const SurfaceMultigrid&) = delete;
  SurfaceMultigrid& operator=(const SurfaceMultigrid&) = delete;

  /// A = D + t K for another t (the same D and K): the coarse levels are
  /// combined anew, nothing is recomputed from the fine level.
  void SetFactor(double factor);

  /// z = B r with B ~ A^-1 one symmetric V-cycle from zero (symmetric
  /// positive definite: a preconditioner for CG), 1 to 8 interleaved values
  /// per row, r and z in the hierarchy's Order(); held rows of z are 0.
  void ApplyInOrder(const double* r, double* z, int columns) const;
  /// y = A x in the hierarchy's Order(), at most 8 columns: the held rows
  /// are identity rows and A has no couplings to them (x zero there: the
  /// product of the free rows).
  void MultiplyInOrder(const double* x, double* y, int columns) const;

  /// The complex symmetric A = D + i a K (the same D and K): prepares its
  /// levels for ApplyComplexInOrder.
  void SetImaginaryFactor(double a);
  /// z = B r with B ~ (D + i a K)^-1 one V-cycle in complex arithmetic
  /// (symmetric, B^T = B: a preconditioner for COCG), r and z in the
  /// hierarchy's Order() with, per row, `columns` real parts and then
  /// `columns` imaginary parts.
  void ApplyComplexInOrder(const double* r, double* z, int columns) const;

  /// rc = the restriction of r to level `level`, and z += the prolongation
  /// of yc from it (the products of the levels' restrictions or
  /// prolongations down to it), `reals` (1 to 8) real values per row, r and
  /// z in the hierarchy's Order(), the held rows taking no part: the coarse
  /// space a distributed solve joins over the processes (RankCoarseSpace).
  void RestrictToLevel(int level, const double* r, double* rc, int reals) const;
  void AddProlongedFromLevel(int level, const double* yc, double* z, int reals) const;

  int Levels() const;
  /// Level l's P^T D P in the pattern of Operator(l) (D: the shift).
  LevelMatrix ShiftOperator(int level) const;
  /// Level l's stiffness P^T K P (the finest: K renumbered in the
  /// hierarchy's order, without the held rows' couplings), whose pattern
  /// is the level's operator's.
  const LevelMatrix& Operator(int level) const;
  /// The non-zeros of all levels over those of A.
  double OperatorComplexity() const;

private:
  struct State;
  std::unique_ptr<State> S;
};

} // namespace beltrami
