#include "Solvers/DenseBlocks.h"

#include <dlfcn.h>

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

// BLAS and LAPACK (OpenBLAS's where installed) for the large blocks.
extern "C"
{
  void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
    const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c, const int* ldc,
    std::size_t transaLength, std::size_t transbLength);
  void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
  void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uploLength);
  void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
    const double* alpha, const double* a, const int* lda, double* b, const int* ldb, std::size_t sideLength,
    std::size_t uploLength, std::size_t transaLength, std::size_t diagLength);
}

namespace beltrami::detail
{

namespace
{
// Blocks with at least this many multiply-adds go to the BLAS (its threads,
// its tuned kernels); smaller ones to Eigen, without a library call's overhead.
constexpr double BlasWork = 32.0 * 32.0 * 32.0;
} // namespace

/// c (m x n, leading dimension m) = a (m x k) * b (n x k)^T.
void MultiplyTransposed(int m, int n, int k, const double* a, int lda, const double* b, int ldb, double* c)
{
  if (double(m) * n * k >= BlasWork)
  {
    const double one = 1.0, zero = 0.0;
    dgemm_("N", "T", &m, &n, &k, &one, a, &lda, b, &ldb, &zero, c, &m, 1, 1);
  }
  else
  {
    Eigen::Map<Eigen::MatrixXd>(c, m, n).noalias() =
      ConstStrided(a, m, k, Eigen::OuterStride<>(lda)) * ConstStrided(b, n, k, Eigen::OuterStride<>(ldb)).transpose();
  }
}

/// LU with partial pivoting of the w x w block at a (leading dimension lda):
/// swaps[q] = the row exchanged with row q at step q.  False on a zero pivot.
bool FactorizeDense(int w, double* a, int lda, int* swaps)
{
  if (w >= 64)
  {
    std::vector<int> pivots(static_cast<std::size_t>(w));
    int info = 0;
    dgetrf_(&w, &w, a, &lda, pivots.data(), &info);
    for (int q = 0; q < w; ++q)
    {
      swaps[q] = pivots[q] - 1;
    }
    return info == 0;
  }
  for (int q = 0; q < w; ++q)
  {
    double* column = a + static_cast<std::ptrdiff_t>(q) * lda;
    int p = q;
    for (int r = q + 1; r < w; ++r)
    {
      p = std::abs(column[r]) > std::abs(column[p]) ? r : p;
    }
    swaps[q] = p;
    if (column[p] == 0.0)
    {
      return false;
    }
    if (p != q)
    {
      for (int c = 0; c < w; ++c)
      {
        std::swap(a[static_cast<std::ptrdiff_t>(c) * lda + q], a[static_cast<std::ptrdiff_t>(c) * lda + p]);
      }
    }
    const double inverse = 1.0 / column[q];
    for (int r = q + 1; r < w; ++r)
    {
      column[r] *= inverse;
    }
    for (int c = q + 1; c < w; ++c)
    {
      double* target = a + static_cast<std::ptrdiff_t>(c) * lda;
      const double f = target[q];
      if (f != 0.0)
      {
        for (int r = q + 1; r < w; ++r)
        {
          target[r] -= column[r] * f;
        }
      }
    }
  }
  return true;
}

/// Cholesky factorization (lower) of the w x w block at a.  False when the
/// block is not positive definite.
bool FactorizeDenseSymmetric(int w, double* a, int lda)
{
  if (w >= 64)
  {
    int info = 0;
    dpotrf_("L", &w, a, &lda, &info, 1);
    return info == 0;
  }
  for (int q = 0; q < w; ++q)
  {
    double* column = a + static_cast<std::ptrdiff_t>(q) * lda;
    if (!(column[q] > 0.0))
    {
      return false;
    }
    column[q] = std::sqrt(column[q]);
    const double inverse = 1.0 / column[q];
    for (int r = q + 1; r < w; ++r)
    {
      column[r] *= inverse;
    }
    for (int c = q + 1; c < w; ++c)
    {
      double* target = a + static_cast<std::ptrdiff_t>(c) * lda;
      const double f = column[c];
      for (int r = c; r < w; ++r)
      {
        target[r] -= column[r] * f;
      }
    }
  }
  return true;
}


/// b (m x w) := b * T^-1 with T one of the triangles of d.
void SolveOnTheRight(Triangle triangle, int m, int w, const double* d, int ldd, double* b, int ldb)
{
  if (m == 0)
  {
    return;
  }
  if (double(m) * w * w >= BlasWork)
  {
    const double one = 1.0;
    const bool upper = triangle == Triangle::Upper;
    dtrsm_("R", upper ? "U" : "L", upper ? "N" : "T", triangle == Triangle::UnitLowerT ? "U" : "N", &m, &w, &one, d,
      &ldd, b, &ldb, 1, 1, 1, 1);
    return;
  }
  const ConstStrided dd(d, w, w, Eigen::OuterStride<>(ldd));
  Strided bb(b, m, w, Eigen::OuterStride<>(ldb));
  switch (triangle)
  {
    case Triangle::Upper:
      dd.triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(bb);
      break;
    case Triangle::UnitLowerT:
      dd.triangularView<Eigen::UnitLower>().transpose().solveInPlace<Eigen::OnTheRight>(bb);
      break;
    case Triangle::LowerT:
      dd.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(bb);
      break;
  }
}

} // namespace beltrami::detail

namespace beltrami
{

SingleThreadedBlas::SingleThreadedBlas()
{
  static const auto functions = [] {
    return std::make_pair(reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")),
      reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")));
  }();
  if (functions.first && functions.second)
  {
    Set = functions.second;
    Saved = functions.first();
    Set(1);
  }
}

SingleThreadedBlas::~SingleThreadedBlas()
{
  if (Set)
  {
    Set(Saved);
  }
}

} // namespace beltrami
