// Beltrami core (internal to Drawing/): the per-face tools of the line
// drawings' zero sets: segment end keys, the zero set of a linear function
// on a face, clipping by another, per-face passes in face order, gradients.
#pragma once

#include "Drawing/LineDrawing.h"
#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace beltrami
{

/// Faces per block of the per-face passes: blocks keep the segments in face
/// order whatever the thread count.
constexpr std::int64_t FacesPerBlock = 4096;

/// The keys of segment ends on edge a-b and on vertex v: the same on every
/// process of a split run (from the vertices' global rows).
inline std::int64_t EdgeKey(const LineDrawingGeometry& geo, Index a, Index b)
{
  const std::int64_t i = geo.KeyId(a), j = geo.KeyId(b);
  return std::min(i, j) * geo.NumberOfKeyIds() + std::max(i, j);
}

inline std::int64_t VertexKey(const LineDrawingGeometry& geo, Index v)
{
  return geo.NumberOfKeyIds() * geo.NumberOfKeyIds() + geo.KeyId(v);
}

/// The zero set of the linear function with values f at the corners of
/// face `face` (vertices v of `geo`): its two ends on the face's edges.  The
/// point on an edge is computed from the edge's lower vertex id (KeyId), so
/// that both faces of the edge find the same point.  False if f has no sign
/// change (f >= 0 counts as positive) or a value is not finite.
inline bool ZeroCrossing(const LineDrawingGeometry& geo, Index face, const Index* v, const double* f, LineSegment& s)
{
  if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
  {
    return false;
  }
  const bool positive[3] = { f[0] >= 0.0, f[1] >= 0.0, f[2] >= 0.0 };
  if (positive[0] == positive[1] && positive[1] == positive[2])
  {
    return false;
  }
  s.Face = face;
  int found = 0;
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3;
    if (positive[a] != positive[b])
    {
      const int lo = geo.KeyId(v[a]) < geo.KeyId(v[b]) ? a : b, hi = a + b - lo;
      const double t = f[lo] / (f[lo] - f[hi]);
      LineEnd& end = s.End[found++];
      end.Key = EdgeKey(geo, v[a], v[b]);
      end.W[0] = end.W[1] = end.W[2] = 0.0;
      end.W[lo] = 1.0 - t;
      end.W[hi] = t;
    }
  }
  return true;
}

inline double Interpolate(const LineEnd& end, const double* g)
{
  return end.W[0] * g[0] + end.W[1] * g[1] + end.W[2] * g[2];
}

/// Keeps the part of s where the linear function with corner values g is
/// >= 0 (the new end inside the face, Key -1); false if none is left.
inline bool Clip(LineSegment& s, const double* g)
{
  const double a = Interpolate(s.End[0], g), b = Interpolate(s.End[1], g);
  if (!std::isfinite(a) || !std::isfinite(b) || (a < 0.0 && b < 0.0))
  {
    return false;
  }
  if (a >= 0.0 && b >= 0.0)
  {
    return true;
  }
  const double t = a / (a - b);
  LineEnd cut;
  for (int k = 0; k < 3; ++k)
  {
    cut.W[k] = (1.0 - t) * s.End[0].W[k] + t * s.End[1].W[k];
  }
  s.End[a < 0.0 ? 0 : 1] = cut;
  return true;
}

/// The corner values of face f of a per-vertex field.
inline void Corners(const IndexArray& tri, Index f, const double* field, double* out)
{
  for (int k = 0; k < 3; ++k)
  {
    out[k] = field[tri[3 * static_cast<std::int64_t>(f) + k]];
  }
}

/// Runs body(face, lists) over all faces (or other items: ridge
/// candidates, vertices), in blocks that each fill their own `count` lists
/// (of segments by default; at most three lists; `expected`: the room each
/// block's lists are given, per list); returns the `count` lists with the
/// blocks' items in face order (the same for any thread count).
template <typename Item = LineSegment, typename Body>
std::vector<LargeVector<Item>> CollectSegments(
  Index numFaces, int numThreads, int count, Body&& body, std::array<std::size_t, 3> expected = {})
{
  const std::int64_t blocks = (numFaces + FacesPerBlock - 1) / FacesPerBlock;
  std::vector<std::vector<std::vector<Item>>> perBlock(blocks, std::vector<std::vector<Item>>(count));
  ParallelFor(
    blocks, numThreads,
    [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t b = begin; b < end; ++b)
      {
        for (int l = 0; l < count; ++l)
        {
          perBlock[b][l].reserve(expected[l]);
        }
        const Index last = static_cast<Index>(std::min<std::int64_t>(numFaces, (b + 1) * FacesPerBlock));
        for (Index f = static_cast<Index>(b * FacesPerBlock); f < last; ++f)
        {
          body(f, perBlock[b].data());
        }
      }
    },
    {}, 0, 1);
  std::vector<LargeVector<Item>> lists(count);
  for (int l = 0; l < count; ++l)
  {
    std::size_t total = 0;
    for (const auto& block : perBlock)
    {
      total += block[l].size();
    }
    lists[l].reserve(total);
    for (const auto& block : perBlock)
    {
      lists[l].insert(lists[l].end(), block[l].begin(), block[l].end());
    }
  }
  return lists;
}

/// The gradient of the linear function with corner values g on the
/// triangle p (zero for a degenerate one).
inline Vec3 FaceGradient(const Vec3* p, const double* g)
{
  const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
  const double nn = n.squaredNorm();
  if (!(nn > 0.0))
  {
    return Vec3::Zero();
  }
  Vec3 gradient = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    // grad(phi_k) = n x (p_{k+2} - p_{k+1}) / |n|^2
    gradient += g[k] * n.cross(p[(k + 2) % 3] - p[(k + 1) % 3]);
  }
  return gradient / nn;
}


/// The lower threshold's fraction of the full one (HysteresisRatio in
/// (0, 1]; anything else: 1).
inline double HysteresisFactor(const LineDrawingOptions& options)
{
  const double r = options.HysteresisRatio;
  return r > 0.0 && r < 1.0 ? r : 1.0;
}

} // namespace beltrami
