// Beltrami core: algebraic multigrid (hypre's BoomerAMG) as the
// preconditioner of the conjugate gradients on the shifted graph Laplacians
// D + t K (the implicit steps of fairing and of the graph flows, harmonic
// extensions).  The only file that sees hypre (with Partition.cxx, the
// only ones that see MPI).
//
// Where it pays: its iteration counts do not depend on the conditioning of
// a clean mesh's system (4 iterations for one implicit curvature-flow step
// of 1000 h^2 at 75k, 300k and 1.2M triangles, where Jacobi needs 355, 405
// and 499), but on this project's 2-core machines a V-cycle of Debian's
// hypre (single-threaded, no OpenMP) costs about 25 mixed-precision Jacobi
// iterations and its set-up about 7 us per row, so Jacobi stays the
// default: on the fairing benchmark's cases it is 1.2-6x faster up to 1.2M
// triangles (Testing/Benchmarks/benchmark_fairing.py prints both).  On
// noisy scans the V-cycle itself degrades (Chebyshev smoothing, below, is
// the most robust of the smoothers tried), and the default step's
// iteration counts grow with the noise relative to the edges rather than
// with the size: with noise of a fixed fraction of the edge length,
// Jacobi's grow 187 -> 241 -> 289 over two Loop levels.  Building the
// hierarchy from an M-matrix instead (the negative cotangent weights left
// out, the CG still on the true operator) made it worse: the default step
// on the 0.3%-noisy bunny took 155 iterations at 75k triangles (36 with the
// true weights) and 577 at 300k (144).
//
// hypre runs over MPI: on a process where MPI is not initialised (plain
// Python, the GUI's builtin server) the first multigrid set-up initialises it
// (as a singleton, about half a second) and finalises it at exit.  The
// hierarchy lives on MPI_COMM_SELF (each process solves its own systems),
// or on the processes of a Partition (a distributed solve: each process
// assembles its owned rows, and hypre's ParCSR matrices span them all).
#pragma once

#include "Support/Parallel.h"

#include <cstdint>
#include <memory>

namespace beltrami
{

class Partition;

/// The preconditioner of the graph solvers (ShiftedLaplacianProblem).
enum class Preconditioning
{
  Jacobi,            ///< mixed precision, renumbered rows
  Multigrid,         ///< one V-cycle of BoomerAMG per iteration
  GeometricMultigrid, ///< one V-cycle on the surface's own hierarchy (SurfaceMultigrid)
  Automatic           ///< GeometricMultigrid where it was measured the faster (ChosenPreconditioner), else Jacobi
};

class AlgebraicMultigrid
{
public:
  /// The hierarchy of A = D + t K, K a graph Laplacian stiffness in CSR form
  /// (K_ii = diagonal[i], K_ij = -weights[k]), D = shift (nullptr: 0),
  /// t = factor; rows marked in `fixed` (optional) are identity rows, and
  /// the couplings to them are left out (the system on the free rows).
  /// With `split` (collective over its processes): the rows this process
  /// owns, coupled to the other processes' through the ghost rows (whose
  /// `fixed` must be their owners'); Apply then sets the owned rows of z and
  /// zeroes the ghost rows.
  AlgebraicMultigrid(Index rows, const std::int64_t* offsets, const Index* neighbors,
    const double* weights, const double* diagonal, const double* shift, double factor,
    const std::uint8_t* fixed, const Partition* split = nullptr);
  ~AlgebraicMultigrid();
  AlgebraicMultigrid(const AlgebraicMultigrid&) = delete;
  AlgebraicMultigrid& operator=(const AlgebraicMultigrid&) = delete;

  /// z = B r with B ~ A^-1 one symmetric V-cycle from zero (a symmetric
  /// positive definite operator: a preconditioner for CG), for `columns`
  /// interleaved values per row.
  void Apply(const double* r, double* z, int columns) const;

  /// Levels of the hierarchy and its operator complexity (the non-zeros
  /// of all levels over those of A).
  int Levels() const;
  double OperatorComplexity() const;

private:
  struct Hierarchy;
  std::unique_ptr<Hierarchy> H;
};

} // namespace beltrami
