// Beltrami core: sparse graphs in CSR form (row i's neighbours are
// neighbors[offsets[i] .. offsets[i+1]), with per-entry weights), the bottom
// of the solvers: the product with a graph Laplacian stiffness and the
// cache-friendly row order the iterative solvers use.
#pragma once

#include "Support/Parallel.h"

#include <cstdint>
#include <vector>

namespace beltrami
{

/// Row i of y = K x below (C values, into out).
template <int C, class T>
inline void StiffnessRow(std::int64_t i, const std::int64_t* offsets, const Index* neighbors, const T* weights,
  const T* diagonal, const T* x, T* out)
{
  for (int c = 0; c < C; ++c)
  {
    out[c] = diagonal[i] * x[i * C + c];
  }
  for (std::int64_t k = offsets[i]; k < offsets[i + 1]; ++k)
  {
    const T w = weights[k];
    const T* xj = x + static_cast<std::int64_t>(neighbors[k]) * C;
    for (int c = 0; c < C; ++c)
    {
      out[c] -= w * xj[c];
    }
  }
}

/// y = K x for a graph Laplacian stiffness in CSR form (K_ii = diagonal[i],
/// K_ij = -weights[k] for the entry k of row i, j = neighbors[k]) and
/// `columns` (1 to 8) interleaved values per row; each thread takes the same
/// rows every call (ParallelForStatic).
void ApplyGraphStiffness(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const double* weights, const double* diagonal, const double* x, double* y, int columns, int numThreads);
/// The same in single precision (the mixed-precision solvers' corrections).
void ApplyGraphStiffness(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const float* weights, const float* diagonal, const float* x, float* y, int columns, int numThreads);

/// Breadth-first order of the rows of a graph (one component after another):
/// Order[new] = old.
std::vector<Index> LocalityOrder(Index rows, const std::int64_t* offsets, const Index* neighbors);

} // namespace beltrami
