// Beltrami core: small fixed-width vectors of doubles (GCC vector types),
// for kernels that run several independent items at once, one a lane
// (triangles of the curvature derivatives' face fit, corners of a 1-ring),
// without branches: what differs between lanes is selected with masks.
// Left to the auto-vectorizer, those loops did not vectorize.
#pragma once

// The helpers are inlined into their callers' clones (Vectorization.h):
// GCC's note on passing 32-byte vectors without AVX does not apply.  (A
// file that instantiates an included template with Real before this
// header, say Mesh/RingGeometry.h's CornerMixedArea, says so itself.)
#pragma GCC diagnostic ignored "-Wpsabi"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace beltrami
{
namespace lanes
{

constexpr int Width = 4;
using Real = double __attribute__((vector_size(8 * Width)));
using Mask = std::int64_t __attribute__((vector_size(8 * Width))); ///< a comparison of Reals: 0 or -1

inline Real Load(const double* p)
{
  Real r;
  std::memcpy(&r, p, sizeof r);
  return r;
}
inline void Store(double* p, const Real& r) { std::memcpy(p, &r, sizeof r); }
inline Real Sqrt(const Real& x)
{
  Real r;
  for (int l = 0; l < Width; ++l)
  {
    r[l] = std::sqrt(x[l]);
  }
  return r;
}
inline Real Max(const Real& a, const Real& b) { return a > b ? a : b; }
/// Finite, as a comparison (NaN fails it).
inline Mask Finite(const Real& x) { return (x < 0.0 ? -x : x) <= std::numeric_limits<double>::max(); }

struct V3
{
  Real X, Y, Z;
};
inline V3 operator+(const V3& a, const V3& b) { return { a.X + b.X, a.Y + b.Y, a.Z + b.Z }; }
inline V3 operator-(const V3& a, const V3& b) { return { a.X - b.X, a.Y - b.Y, a.Z - b.Z }; }
inline V3 operator*(const Real& s, const V3& a) { return { s * a.X, s * a.Y, s * a.Z }; }
inline Real Dot(const V3& a, const V3& b) { return a.X * b.X + a.Y * b.Y + a.Z * b.Z; }
inline V3 Cross(const V3& a, const V3& b)
{
  return { a.Y * b.Z - a.Z * b.Y, a.Z * b.X - a.X * b.Z, a.X * b.Y - a.Y * b.X };
}

} // namespace lanes
} // namespace beltrami
