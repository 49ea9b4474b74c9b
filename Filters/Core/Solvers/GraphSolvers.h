// Beltrami core: conjugate-gradient solvers for the systems D + t K and
// D + t K D^-1 K over a graph Laplacian stiffness K (the implicit steps of
// smoothing and of the graph flows, harmonic extensions): faster than the
// generic SolveConjugateGradient through a renumbering, mixed precision and
// (for the squared systems) one complex symmetric solve.
#pragma once

#include "Solvers/AlgebraicMultigrid.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/SurfaceMultigrid.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace beltrami
{

/// A = D + t K with D diagonal (Shift) and K a graph Laplacian stiffness
/// (K_ii = Diagonal[i], K_ij = -Weights[k] for the CSR entry k of row i, j =
/// Neighbors[k]): the systems of implicit smoothing steps, (M + dt S) X' = M X,
/// and of harmonic extensions (D = 0).  Same contract and stopping criterion
/// as ConjugateGradientProblem, solved faster than through Apply:
///  - the rows are renumbered in breadth-first order over the graph (Order,
///    or computed), so that neighbours are near in memory and each thread's
///    rows stay in its core's cache from loop to loop (ParallelForStatic);
///  - mixed precision: the residual b - A x is computed in double, the
///    correction in single precision (half the memory traffic), and repeated
///    (iterative refinement) until the double residual meets the tolerance,
///    so the result is as accurate as a double-precision solve.
struct ShiftedLaplacianProblem
{
  Index Rows = 0;
  int Columns = 1; ///< values per row, interleaved (at most 8)
  const std::int64_t* Offsets = nullptr; ///< CSR rows (size Rows + 1)
  const Index* Neighbors = nullptr;
  const double* Weights = nullptr;  ///< per CSR entry: K_ij = -Weights[k]
  const double* Diagonal = nullptr; ///< K_ii
  const double* Shift = nullptr;    ///< D_ii (nullptr: 0)
  double Factor = 1.0;              ///< t
  const std::uint8_t* Fixed = nullptr; ///< optional: non-zero = fixed row
  /// Optional renumbering (LocalityOrder of the same graph), e.g. kept
  /// across the steps of a flow; computed when null.
  const Index* Order = nullptr;
  std::vector<double> Scale; ///< per column: the size of the solution
  double Tolerance = 1e-6;
  int MaximumIterations = 1000;
  int NumberOfThreads = 0;
  Preconditioning Preconditioner = Preconditioning::Jacobi;
  /// The rows' points (3 per row), for GeometricMultigrid: its hierarchy is
  /// built from the graph and the points, or taken from Hierarchy (built
  /// for the same graph, kept across solves).  Without either,
  /// GeometricMultigrid takes BoomerAMG; with a Split, each process's
  /// hierarchy of its own rows (RankCoarseSpace joins them).
  const double* Points = nullptr;
  std::shared_ptr<const SurfaceHierarchy> Hierarchy;
  /// Optional, without Hierarchy: where a hierarchy this solve builds from
  /// Points is left, and the next solve of the same graph takes it from (a
  /// flow's steps when Automatic chooses the multigrid).
  std::shared_ptr<const SurfaceHierarchy>* KeptHierarchy = nullptr;
  /// Optional: the rows split over processes (a collective solve, see
  /// ConjugateGradientProblem::Split): the algebraic multigrid spanning the
  /// processes, the geometric one on each process's own rows joined by a
  /// coarse level, or for SolveSquaredLaplacian also the Jacobi COCG.
  /// SolveShiftedLaplacian's Jacobi solver renumbers its rows per process:
  /// there a Split needs multigrid (distributed order-1 Jacobi solves take
  /// SolveConjugateGradient, the same iteration in double precision).
  const Partition* Split = nullptr;
  /// Optional, SolveSquaredLaplacian's COCG (Jacobi or the geometric
  /// multigrid; the algebraic multigrid starts at x): where the solve starts on the free
  /// rows (Columns per row, the caller's numbering), for example the
  /// solution of a nearby step; the tolerance stays relative to the
  /// residual at x, so the result is as accurate as the solve from x, in
  /// fewer iterations the nearer the guess.
  const double* Guess = nullptr;
  /// SolveSquaredLaplacian's serial Jacobi COCG from this many rows, asked
  /// for a reduction of at most 1e-5: in mixed precision (double-precision
  /// residuals of this matrix, single-precision corrections on a renumbered
  /// copy), half the memory of the double-precision solve; where the
  /// corrections stop reducing the residual (rows whose D_ii is tiny against
  /// sqrt(t) K_ii: slivers, specks), on in double precision from there.
  Index MixedPrecisionRows = 1000000;
};

/// The preconditioner the graph solvers take for `problem` (for the order-2
/// system D + t K D^-1 K of SolveSquaredLaplacian when `squared`): the given
/// one, or for Automatic the geometric multigrid where it was measured
/// faster than Jacobi for one step, its set-up included (bunny00
/// Loop-subdivided to 300k and 1.2M triangles, clean and with noise of 0.3%
/// of the diagonal, 2 threads), else Jacobi. The multigrid is taken for a
/// serial solve of at least AutomaticMultigridRows rows with points or a
/// hierarchy, on a surface's graph (4 or more neighbours a row on average),
/// whose step is large: s / median(D_ii) at least
/// AutomaticMultigridStep, s = t (order 1) or sqrt(t) (order 2), D_ii a
/// point's area (on the bunny 135 per 100 h^2, h the mean edge length; 176
/// with the noise): order 1 from about 150 h^2, order 2 from about 100 h^4.
/// At 1.2M triangles one clean step of 300 h^2 took 1.80 s instead of
/// Jacobi's 2.11, one of 400 h^4 2.00 s instead of 5.86. D = 0 (harmonic
/// extensions) is an infinite step. Order-2 systems of
/// AutomaticMultigridRowsOrder2 rows take it for any step (the default step
/// of 4 h^4 on 4.8M triangles: 12.9 s against 14.5 s, with noise of 0.3%
/// 95 s where Jacobi stopped short of the tolerance after 161 s; on 1.2M
/// triangles Jacobi was the faster); larger ones keep Jacobi, whose time and
/// memory were measured there (the multigrid's levels hold more).
Preconditioning ChosenPreconditioner(const ShiftedLaplacianProblem& problem, bool squared = false);
constexpr Index AutomaticMultigridRows = 20000;
constexpr Index AutomaticMultigridRowsOrder2[2] = { 1500000, 4000000 }; ///< from, below
constexpr double AutomaticMultigridStep[2] = { 200.0, 15.0 }; ///< orders 1 and 2

/// Whether the graph solvers precondition `problem` by multigrid.
bool UsesMultigrid(const ShiftedLaplacianProblem& problem, bool squared = false);

/// A x = b for A = D + t K (ShiftedLaplacianProblem), preconditioned as
/// ChosenPreconditioner says.  With Automatic, where the preconditioner it
/// chose stops short of the tolerance when the iterations run out, the
/// solve goes on from the x reached with the multigrid it did not choose,
/// up to MaximumIterations more (GraphSolvers.cxx, GoOnWhereShort; so does
/// SolveSquaredLaplacian).
ConjugateGradientResult SolveShiftedLaplacian(
  const ShiftedLaplacianProblem& problem, const double* b, double* x);

/// A = D + t K N K, N = D^-1 on the free rows and 0 on the fixed ones, with
/// D > 0 and K as in ShiftedLaplacianProblem (Shift, Factor = t, no Order):
/// the implicit steps of order-2 (L^2) smoothing, (M + dt S M^-1 S) X' = M X.
/// Same contract and stopping criterion as SolveConjugateGradient (Columns at
/// most 4).  On the free rows A = D + t K_ff D^-1 K_ff, and for real
/// symmetric K and positive diagonal D
///     A^-1 = Re (D + i sqrt(t) K_ff)^-1
/// (both sides are D^-1/2 (I + t G^2)^-1 D^-1/2 with G = D^-1/2 K_ff D^-1/2),
/// so each correction is the real part of one complex symmetric system with
/// the sparsity of K, solved by COCG (the conjugate gradient with the
/// unconjugated inner product, Jacobi preconditioned), whose conditioning is
/// that of an order-1 step of sqrt(t): a few times fewer iterations than CG on
/// A, each with one product by K instead of two.  One COCG run on the
/// initial residual: whenever the complex residual reaches its target, the
/// real residual of x0 + Re z is checked; if it misses the tolerance, the
/// same run goes on with a tighter target.  Converged is false when a check
/// shows no progress or the iterations run out (the caller may go on with
/// another solver from x).
/// With GeometricMultigrid, the same COCG preconditioned by a V-cycle of
/// D + i sqrt(t) K in complex arithmetic on the surface's hierarchy.
/// With the algebraic Multigrid, CG on A itself, preconditioned by
/// B D B with B one V-cycle on D + sqrt(t) K_ff: (D + sqrt(t) K) D^-1
/// (D + sqrt(t) K) = A + 2 sqrt(t) K lies between A and 2 A, so with exact
/// inverses in place of B the preconditioned system has a condition number
/// of at most 2 (6 iterations measured with 30 cycles per B).
ConjugateGradientResult SolveSquaredLaplacian(
  const ShiftedLaplacianProblem& problem, const double* b, double* x);

} // namespace beltrami
