// Beltrami core: the small geometry vocabulary every core file shares:
// fixed-size Eigen vectors over the interleaved coordinate arrays of the
// core (3 doubles per point, 2 per parameter-plane point, N per point of a
// surface embedded in R^N).
#pragma once

#include "Support/Parallel.h"

#include <Eigen/Core>

#include <cstdint>

namespace beltrami
{

template <int N>
using VecN = Eigen::Matrix<double, N, 1>;

/// Point i of an interleaved coordinate array (N used components, stride >= N).
template <int N, typename T>
inline VecN<N> LoadPoint(const T* points, int stride, Index i)
{
  VecN<N> p;
  const T* src = points + static_cast<std::int64_t>(stride) * i;
  for (int d = 0; d < N; ++d)
  {
    p[d] = static_cast<double>(src[d]);
  }
  return p;
}

using Vec3 = VecN<3>;
using Vec2 = VecN<2>;

/// Point i of an array of 3 doubles per point.
inline Vec3 Point(const double* points, Index i)
{
  return LoadPoint<3>(points, 3, i);
}

/// An orthonormal tangent frame (u, v) of the unit normal n, with u x v = n.
inline void TangentFrame(const Vec3& n, Vec3& u, Vec3& v)
{
  Vec3 axis = Vec3::Zero();
  int k = 0;
  n.cwiseAbs().minCoeff(&k);
  axis[k] = 1.0;
  u = (axis - axis.dot(n) * n).normalized();
  v = n.cross(u);
}

/// Point i of an array of 2 doubles per point (parameter-plane coordinates).
inline Vec2 UV(const double* uv, Index i)
{
  return LoadPoint<2>(uv, 2, i);
}

} // namespace beltrami
