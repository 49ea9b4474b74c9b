#include "Mesh/SurfaceOperators.h"

#include "Mesh/RingGeometry.h"

#include <limits>
#include <stdexcept>

namespace beltrami
{

namespace
{

template <int N, typename T>
bool BeltramiN(const MeshTopology& topo, const T* points, int stride, double* beltrami,
  double* mixedArea, double* angleDefect, int numThreads, const ProgressCallback& progress)
{
  return ParallelFor(
    topo.NumberOfVertices(), numThreads,
    [&](std::int64_t begin, std::int64_t end) {
      for (Index i = static_cast<Index>(begin); i < end; ++i)
      {
        PrefetchRing(topo, points, stride, i);
        const VecN<N> xi = LoadPoint<N>(points, stride, i);
        RingSums<N> sums;
        ForEachRingCorner<N>(
          topo, points, stride, i, xi, [&](const CornerGeometry<N>& g) { sums.Add(g); });
        if (beltrami)
        {
          const VecN<N> k = sums.MixedArea > 0.0
            ? sums.MeanCurvatureNormal()
            : VecN<N>::Constant(std::numeric_limits<double>::quiet_NaN());
          Eigen::Map<VecN<N>>(beltrami + static_cast<std::int64_t>(N) * i) = k;
        }
        if (mixedArea)
        {
          mixedArea[i] = sums.MixedArea;
        }
        if (angleDefect)
        {
          angleDefect[i] = sums.AngleDefect();
        }
      }
    },
    progress);
}

} // namespace

template <typename T>
bool ComputeBeltramiOperator(const MeshTopology& topo, const T* points, int dimension, int stride,
  double* beltrami, double* mixedArea, double* angleDefect, int numThreads,
  const ProgressCallback& progress)
{
  if (stride < dimension)
  {
    throw std::invalid_argument("ComputeBeltramiOperator: stride smaller than dimension");
  }
  switch (dimension)
  {
#define BELTRAMI_DIMENSION_CASE(n)                                                                 \
  case n:                                                                                          \
    return BeltramiN<n>(topo, points, stride, beltrami, mixedArea, angleDefect, numThreads, progress);
    BELTRAMI_DIMENSION_CASE(2)
    BELTRAMI_DIMENSION_CASE(3)
    BELTRAMI_DIMENSION_CASE(4)
    BELTRAMI_DIMENSION_CASE(5)
    BELTRAMI_DIMENSION_CASE(6)
    BELTRAMI_DIMENSION_CASE(7)
    BELTRAMI_DIMENSION_CASE(8)
#undef BELTRAMI_DIMENSION_CASE
    default:
      throw std::invalid_argument("ComputeBeltramiOperator: dimension must be in [2, 8]");
  }
}

template bool ComputeBeltramiOperator<float>(const MeshTopology&, const float*, int, int, double*,
  double*, double*, int, const ProgressCallback&);
template bool ComputeBeltramiOperator<double>(const MeshTopology&, const double*, int, int,
  double*, double*, double*, int, const ProgressCallback&);

} // namespace beltrami
