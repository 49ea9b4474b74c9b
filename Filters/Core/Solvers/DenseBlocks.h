// Beltrami core: the dense kernels of the supernodal factorizations
// (beltrami::detail, for Solvers/SupernodalLU) - products, LU and Cholesky
// of diagonal blocks, triangular solves - by the BLAS and LAPACK for large
// blocks (OpenBLAS's where installed) and by Eigen for small ones; and
// SingleThreadedBlas, a guard that runs the BLAS single-threaded while our
// own threads factor (subtrees, or many small systems such as an atlas's
// charts).
#pragma once

#include <Eigen/Dense>

namespace beltrami::detail
{

using Strided = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using ConstStrided = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

/// c (m x n, leading dimension m) = a (m x k) * b (n x k)^T.
void MultiplyTransposed(int m, int n, int k, const double* a, int lda, const double* b, int ldb, double* c);

/// LU with partial pivoting of the w x w block at a (leading dimension lda):
/// swaps[q] = the row exchanged with row q at step q.  False on a zero pivot.
bool FactorizeDense(int w, double* a, int lda, int* swaps);

/// Cholesky (lower) of the w x w block at a.  False when not positive definite.
bool FactorizeDenseSymmetric(int w, double* a, int lda);

/// The triangular matrices of a diagonal block.
enum class Triangle
{
  Upper,         // U of an LU
  UnitLowerT,    // Lᵀ of an LU (unit diagonal)
  LowerT         // Lᵀ of a Cholesky factorization
};

/// b (m x w) := b * T^-1 with T one of the triangles of d.
void SolveOnTheRight(Triangle triangle, int m, int w, const double* d, int ldd, double* b, int ldb);

} // namespace beltrami::detail

namespace beltrami
{

/// Runs the BLAS single-threaded while it lives (OpenBLAS: its threads
/// would otherwise be shared by our threads' concurrent calls, which made
/// the subtrees 4-7x slower); nothing for a BLAS without that setting.
class SingleThreadedBlas
{
public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

private:
  void (*Set)(int) = nullptr;
  int Saved = 1;
};

} // namespace beltrami
