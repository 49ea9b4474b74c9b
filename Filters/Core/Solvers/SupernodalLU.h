// Beltrami core: supernodal factorizations of the sparse systems of a
// surface mesh in a given elimination order: LU for matrices whose pattern
// is (nearly) symmetric, such as the authalic (DAP) systems of the
// parameterization, and its Cholesky form (U = Lᵀ) for symmetric positive
// definite ones (DCP, the natural conformal map).
//
// P A Pᵀ = L U in the caller's elimination order P (a nested dissection), on
// the supernodal structure of the Cholesky factor of pattern(A + Aᵀ) (CHOLMOD's
// symbolic analysis): U's rows have the pattern of L's columns, so L and Uᵀ
// share one index structure.  Pivoting stays inside each supernode's
// diagonal block (partial pivoting there, LAPACK-style row swaps), which keeps
// the structure static; a factorization that finds a zero pivot there or
// whose multipliers grow large fails, and the caller takes a general LU
// (UMFPACK) instead.
//
// Why not SuiteSparse alone: UMFPACK's symbolic analysis and frontal
// assembly cost over a quarter of a DAP factorization's time, and
// UMFPACK and CHOLMOD run one tree of fronts on one core (their BLAS calls
// barely use a second).  Here the elimination tree's independent subtrees are
// factorized on separate threads (the BLAS single-threaded meanwhile), then
// the top separators with the BLAS's threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace beltrami
{

class SupernodalLU
{
public:
  using MatrixView = Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>>;

  SupernodalLU();
  ~SupernodalLU();
  SupernodalLU(const SupernodalLU&) = delete;
  SupernodalLU& operator=(const SupernodalLU&) = delete;

  /// Factorizes `a` (square, compressed columns, sorted) in `order` (order[k]
  /// = the unknown eliminated k-th; CHOLMOD may postorder it) on numThreads
  /// threads (0: DefaultThreadCount()).  False when the analysis failed
  /// (memory, size), a pivot was zero, or the multipliers grew beyond 1e8
  /// (an unstable order: use a pivoting LU).
  ///
  /// `symmetric`: A is symmetric positive definite (its lower triangle is
  /// read): the Cholesky factorization P A Pᵀ = L Lᵀ instead, half the work
  /// and memory; false when A is not positive definite.  `keepOrder`: P is
  /// exactly `order` (no postordering), e.g. to keep some unknowns last.
  bool Compute(const MatrixView& a, const std::vector<int>& order, int numThreads = 0, bool symmetric = false,
    bool keepOrder = false);
  /// min |u_kk| / max |u_kk| of the last successful Compute (the square of
  /// L's diagonal's ratio for a Cholesky factorization).
  double PivotRatio() const;
  /// The elimination order of the factors (P: Order()[k] = the unknown
  /// eliminated k-th).
  const std::vector<int>& Order() const;
  /// Solves A X = B in place, column by column of B.
  void Solve(Eigen::MatrixXd& b) const;
  /// The two halves of Solve: B := L^-1 P B (rows in the factors' order;
  /// with the row exchanges of the LU), then B := Pᵀ U^-1 B (U = Lᵀ for a
  /// Cholesky factorization).
  void SolveLower(Eigen::MatrixXd& b) const;
  void SolveUpper(Eigen::MatrixXd& b) const;
  /// The lower triangle of the Cholesky factor's trailing m x m block (its
  /// last m rows and columns; the Schur complement of the other unknowns is
  /// its product with its transpose) into `block` (m x m; the entries above
  /// the diagonal are left as they are).
  void TrailingBlock(Eigen::Ref<Eigen::MatrixXd> block) const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace beltrami
