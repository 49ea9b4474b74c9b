// Beltrami core: the small geometry vocabulary every core file shares:
// fixed-size Eigen vectors over the interleaved coordinate arrays of the
// core (3 doubles per point, 2 per parameter-plane point, N per point of a
// surface embedded in R^N).
#pragma once

#include "Support/Parallel.h"

#include <Eigen/Core>

#include <algorithm>
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

/// The distance of p from the segment a-b.
inline double SegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 d = b - a;
  const double t = d.squaredNorm() > 0.0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - a - t * d).norm();
}

/// The point of the triangle (a, b, c) nearest to p (Ericson, Real-Time
/// Collision Detection 5.1.5): its barycentric weights in w; the squared
/// distance is returned.
inline double ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double w[3])
{
  const auto result = [&](double wa, double wb, double wc) {
    w[0] = wa;
    w[1] = wb;
    w[2] = wc;
    return (wa * a + wb * b + wc * c - p).squaredNorm();
  };
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    return result(1.0, 0.0, 0.0);
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    return result(0.0, 1.0, 0.0);
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    const double t = d1 - d3 != 0.0 ? d1 / (d1 - d3) : 0.0;
    return result(1.0 - t, t, 0.0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    return result(0.0, 0.0, 1.0);
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    const double t = d2 - d6 != 0.0 ? d2 / (d2 - d6) : 0.0;
    return result(1.0 - t, 0.0, t);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
  {
    const double t = (d4 - d3) + (d5 - d6) != 0.0 ? (d4 - d3) / ((d4 - d3) + (d5 - d6)) : 0.0;
    return result(0.0, 1.0 - t, t);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) // degenerate triangle: its nearest vertex
  {
    const double da = ap.squaredNorm(), db = bp.squaredNorm(), dc = cp.squaredNorm();
    return da <= db && da <= dc ? result(1.0, 0.0, 0.0) : (db <= dc ? result(0.0, 1.0, 0.0) : result(0.0, 0.0, 1.0));
  }
  return result(va / sum, vb / sum, vc / sum);
}

} // namespace beltrami
