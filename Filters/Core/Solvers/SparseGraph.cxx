#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <stdexcept>

namespace beltrami
{

namespace
{
/// y = K x for C columns (a compile-time count: the per-vertex loops unroll,
/// with no memcpy calls for the accumulators).  Rows split statically: the
/// iterative solvers that call it in a loop find their rows in the same
/// core's cache each time.
template <int C, class T>
void ApplyStiffnessColumns(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const T* weights, const T* diagonal, const T* x, T* y, int numThreads)
{
  ParallelForStatic(rows, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      T acc[C];
      StiffnessRow<C>(i, offsets, neighbors, weights, diagonal, x, acc);
      for (int c = 0; c < C; ++c)
      {
        y[i * C + c] = acc[c];
      }
    }
  });
}

template <class T>
void ApplyStiffness(Index rows, const std::int64_t* offsets, const Index* neighbors, const T* weights,
  const T* diagonal, const T* x, T* y, int columns, int numThreads)
{
  if (columns < 1 || columns > 8)
  {
    throw std::invalid_argument("ApplyStiffness: 1 to 8 columns");
  }
  WithCount<8>(columns, [&](auto k) {
    ApplyStiffnessColumns<decltype(k)::value>(rows, offsets, neighbors, weights, diagonal, x, y, numThreads);
  });
}
} // namespace

void ApplyGraphStiffness(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const double* weights, const double* diagonal, const double* x, double* y, int columns, int numThreads)
{
  ApplyStiffness(rows, offsets, neighbors, weights, diagonal, x, y, columns, numThreads);
}

void ApplyGraphStiffness(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const float* weights, const float* diagonal, const float* x, float* y, int columns, int numThreads)
{
  ApplyStiffness(rows, offsets, neighbors, weights, diagonal, x, y, columns, numThreads);
}

std::vector<Index> LocalityOrder(Index rows, const std::int64_t* offsets, const Index* neighbors)
{
  std::vector<Index> order;
  order.reserve(static_cast<std::size_t>(std::max<Index>(rows, 0)));
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(std::max<Index>(rows, 0)), 0);
  for (Index start = 0; start < rows; ++start)
  {
    if (seen[start])
    {
      continue;
    }
    seen[start] = 1;
    order.push_back(start);
    for (std::size_t head = order.size() - 1; head < order.size(); ++head)
    {
      const Index v = order[head];
      for (std::int64_t k = offsets[v]; k < offsets[v + 1]; ++k)
      {
        const Index u = neighbors[k];
        if (u >= 0 && u < rows && !seen[u])
        {
          seen[u] = 1;
          order.push_back(u);
        }
      }
    }
  }
  return order;
}

} // namespace beltrami
