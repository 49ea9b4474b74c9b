#include "Flows/TensorSpace.h"

#include "Solvers/Partition.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace beltrami
{

namespace
{

const double Sqrt2 = std::sqrt(2.0);

/// The symmetric matrix of 6 values; `scale` multiplies the off-diagonal
/// ones (1 for tensors, 1/sqrt2 for log coordinates).
Eigen::Matrix3d Matrix(const double* v, double scale)
{
  Eigen::Matrix3d m;
  m << v[0], scale * v[3], scale * v[5], scale * v[3], v[1], scale * v[4], scale * v[5], scale * v[4], v[2];
  return m;
}

void Store(const Eigen::Matrix3d& m, double scale, double* v)
{
  v[0] = m(0, 0);
  v[1] = m(1, 1);
  v[2] = m(2, 2);
  v[3] = scale * m(0, 1);
  v[4] = scale * m(1, 2);
  v[5] = scale * m(0, 2);
}

/// V f(D) V^T of the symmetric matrix of v (off-diagonals times `in`),
/// stored with off-diagonals times `out`.
template <typename F>
void ApplyToEigenvalues(double* v, double in, double out, F&& f)
{
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.compute(Matrix(v, in)); // QR iterations: computeDirect loses 1e-9 at repeated eigenvalues
  const Eigen::Vector3d d = es.eigenvalues().unaryExpr(f);
  Store(es.eigenvectors() * d.asDiagonal() * es.eigenvectors().transpose(), out, v);
}

} // namespace

std::int64_t SymmetricTensorsToLog(
  double* values, std::int64_t count, int stride, double floor, int numThreads, const Partition* split)
{
  double largest = 0.0;
  for (std::int64_t i = 0; i < count; ++i)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.compute(Matrix(values + i * stride, 1.0), Eigen::EigenvaluesOnly);
    largest = std::max(largest, es.eigenvalues().maxCoeff());
  }
  largest = split ? split->Max(largest) : largest;
  const double lowest = largest > 0.0 ? floor * largest : 1.0;
  std::atomic<std::int64_t> raised{ 0 };
  ParallelFor(count, numThreads, [&](std::int64_t b, std::int64_t e) {
    std::int64_t local = 0;
    for (std::int64_t i = b; i < e; ++i)
    {
      bool low = false;
      ApplyToEigenvalues(values + i * stride, 1.0, Sqrt2, [&](double l) {
        low = low || !(l >= lowest);
        return std::log(l >= lowest ? l : lowest);
      });
      local += low && (!split || split->IsOwned(static_cast<Index>(i)));
    }
    raised += local;
  });
  return split ? static_cast<std::int64_t>(split->Sum(static_cast<double>(raised))) : raised.load();
}

void LogToSymmetricTensors(double* values, std::int64_t count, int stride, int numThreads)
{
  ParallelFor(count, numThreads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      ApplyToEigenvalues(values + i * stride, 1.0 / Sqrt2, 1.0, [](double l) { return std::exp(l); });
    }
  });
}

} // namespace beltrami
