// Beltrami core: a matrix-free, preconditioned conjugate gradient for
// symmetric positive definite systems with several right-hand sides at once
// (x, y, z of the vertices; u, v of a parameterization), and with fixed rows
// (hard constraints) eliminated: rows marked fixed keep the value they have
// in x on entry, and the others solve A_ff x_f = b_f - A_fc x_c.
//
// Stopping criterion: ||A x - b|| <= tolerance * ||A x0 - b|| for every
// column (the residual of the initial guess: for a smoothing step, the size
// of the update, so a small step is solved as accurately as a large one), or
// below round-off relative to the caller's scale (e.g. the norm of
// M (X - centroid)), in which case nothing moves.  The thesis (appendix A.5)
// uses ||X^n|| as the reference, which depends on where the object is.  All
// reductions are deterministic (ParallelSum), so the result does not depend
// on the thread count.
#pragma once

#include "Support/Parallel.h"

#include <cstdint>

#include <functional>
#include <vector>

namespace beltrami
{

class Partition;

/// Residuals below ResidualRoundOff * Scale (the caller's size of the
/// solution) are round-off: nothing is solved.
constexpr double ResidualRoundOff = 1e-13;

struct ConjugateGradientResult
{
  int Iterations = 0;
  double RelativeResidual = 0.0; ///< ||r|| / ||r0||, the largest over the columns
  bool Converged = false;
};

struct ConjugateGradientProblem
{
  Index Rows = 0;
  int Columns = 1; ///< values per row, interleaved (at most 8)
  /// y = A x over all rows (x is zero at the fixed rows when called by the solver).
  std::function<void(const double* x, double* y)> Apply;
  const double* Diagonal = nullptr;       ///< diag(A), for the Jacobi preconditioner
  /// Optional: z = M^-1 r over all rows (columns interleaved; symmetric
  /// positive definite M, e.g. a multigrid cycle), used instead of Jacobi.
  std::function<void(const double* r, double* z)> Preconditioner;
  const std::uint8_t* Fixed = nullptr;    ///< optional: non-zero = fixed row
  std::vector<double> Scale;              ///< per column: the size of the solution
  double Tolerance = 1e-6;                ///< residual reduction
  int MaximumIterations = 1000;
  int NumberOfThreads = 0;
  /// Optional: the rows split over processes (collective solve).  Only the
  /// owned rows are unknowns (ghost rows count as fixed here); Apply gets
  /// its input with the ghost rows holding their owners' values, the inner
  /// products are summed over the processes, and on return the ghost rows
  /// of x hold their owners' results.
  const Partition* Split = nullptr;
  /// The columns as one vector (one step length and direction for all of
  /// them, from inner products summed over the columns): for an operator
  /// that couples a row's values, e.g. section 3.2.7's projections.  Then
  /// every column's Scale should be the whole solution's size.
  bool CoupledColumns = false;
};

/// Solves A x = b; x holds the initial guess (and the fixed values) on entry.
ConjugateGradientResult SolveConjugateGradient(
  const ConjugateGradientProblem& problem, const double* b, double* x);

} // namespace beltrami
