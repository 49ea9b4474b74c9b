#include "Mesh/CurvatureDerivatives.h"

#pragma GCC diagnostic ignored "-Wpsabi" // (lanes::Real in RingGeometry.h's templates: see Support/LaneVectors.h)

#include "Mesh/Geometry.h"
#include "Mesh/RingGeometry.h"

#include "Support/LargeBuffer.h"
#include "Support/Vectorization.h"
#include "Support/LaneVectors.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

namespace beltrami
{

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

/// The per-face fit runs on Lanes faces at once (one lane a face; the fit
/// has no branches: a face whose fit is not defined is computed all the
/// same and masked at the end).
constexpr int Lanes = lanes::Width;
using lanes::Real;
using lanes::Mask;
using lanes::V3;
using lanes::Sqrt;
using lanes::Max;
using lanes::Finite;
using lanes::Dot;
using lanes::Cross;

/// x turned by the smallest rotation that takes the unit vector `from` to
/// the unit vector `to` (Rodrigues); reversed when they are opposite.
inline V3 RotateLike(const V3& x, const V3& from, const V3& to)
{
  const Real c = Dot(from, to);
  const V3 k = Cross(from, to);
  const V3 turned = c * x + Cross(k, x) + (Dot(k, x) / (1.0 + c)) * k;
  const Mask opposite = c <= -1.0 + 1e-12;
  return { opposite ? -x.X : turned.X, opposite ? -x.Y : turned.Y, opposite ? -x.Z : turned.Z };
}

/// Solves the symmetric positive definite tridiagonal system with the
/// given diagonal and constant off-diagonal (4 unknowns) by its LDL^T
/// factors; the mask of the lanes whose pivots are positive (and finite).
inline Mask SolveTridiagonal(const Real (&diagonal)[4], const Real& off, const Real (&r)[4], Real (&x)[4])
{
  Real inverse[4], factor[4], z[4];
  Mask positive = diagonal[0] > 0.0;
  inverse[0] = 1.0 / diagonal[0];
  z[0] = r[0];
  for (int k = 1; k < 4; ++k)
  {
    factor[k] = off * inverse[k - 1];
    const Real pivot = diagonal[k] - factor[k] * off;
    positive &= pivot > 0.0;
    inverse[k] = 1.0 / pivot;
    z[k] = r[k] - factor[k] * z[k - 1];
  }
  x[3] = z[3] * inverse[3];
  for (int k = 2; k >= 0; --k)
  {
    x[k] = z[k] * inverse[k] - factor[k + 1] * x[k + 1];
  }
  for (int k = 0; k < 4; ++k)
  {
    positive &= Finite(x[k]);
  }
  return positive;
}

/// What a face reads of each of its vertices, side by side: position,
/// normal, e1, kappa_1, kappa_2 (from five arrays read at random, the
/// cache misses were most of the faces' time).
constexpr int FrameSize = 11;
enum FramePart
{
  FramePoint = 0,
  FrameNormal = 3,
  FrameDirection = 6,
  FrameMaximum = 9,
  FrameMinimum = 10
};

/// The faces ahead whose vertex frames the face loop asks for: it waited
/// on those random reads for half of its time.
constexpr std::int64_t PrefetchDistance = 8;

/// A corner's part of its vertex's average: the face's tensor in the
/// vertex's principal frame times the corner's mixed area, and that area
/// (zeros where the area or the vertex's frame is not defined).  Kept in
/// single precision (relative 6e-8, summed in double): the array of all
/// corners is the largest of the line drawing's view-independent pass.
struct CornerTerm
{
  float Weighted[4];
  float Area;
};

/// Rusinkiewicz's per-face fit of Lanes faces (`frames`: [corner][value] of
/// FramePart, a lane a face), then each corner's term ([corner][value]:
/// CornerTerm's five).  Per face: the vertex tensors in the face frame (U,
/// N x U), e1 turned into the face's plane by the smallest rotation; along
/// edge a -> b with components (du, dv) the tensor's change is
/// [[C111 du + C112 dv, C112 du + C122 dv], [., C122 du + C222 dv]], and
/// the normal equations of these 9 equations in C are tridiagonal.  Per
/// corner k the face frame turned into the vertex's plane (the inverse of
/// the turn of e1) has e1 = (c, s) and e2 = (-s, c): the term is C(a,a,a),
/// C(a,a,b), C(a,b,b), C(b,b,b) of EvaluateCubicForm with a = (c, s),
/// b = (-s, c), expanded, times the corner's mixed area (figure 2.3).
/// Zero terms where a vertex tensor is undefined or the face is degenerate.
CLONES void FitFaces(const Real (&frames)[3][FrameSize], Real (&terms)[3][5])
{
  V3 p[3], n[3], e1[3];
  for (int k = 0; k < 3; ++k)
  {
    const Real* f = frames[k];
    p[k] = { f[FramePoint], f[FramePoint + 1], f[FramePoint + 2] };
    n[k] = { f[FrameNormal], f[FrameNormal + 1], f[FrameNormal + 2] };
    e1[k] = { f[FrameDirection], f[FrameDirection + 1], f[FrameDirection + 2] };
  }
  const V3 edge[3] = { p[1] - p[0], p[2] - p[1], p[0] - p[2] }; // edge k: from corner k to k + 1
  const Real squared[3] = { Dot(edge[0], edge[0]), Dot(edge[1], edge[1]), Dot(edge[2], edge[2]) };
  const V3 normal = Cross(edge[0], p[2] - p[0]);
  const Real twiceArea = Sqrt(Dot(normal, normal));
  Mask fitted = twiceArea > DegenerateTolerance * Max(squared[0], Max(squared[1], squared[2]));
  // The corners' mixed areas with one square root for the three (the
  // corner geometry of the 1-ring loops takes one each).
  const Real inverseTwiceArea = 1.0 / twiceArea;
  Real mixedArea[3];
  for (int k = 0; k < 3; ++k)
  {
    const Real aa = squared[k], bb = squared[(k + 2) % 3], ab = -Dot(edge[k], edge[(k + 2) % 3]);
    mixedArea[k] =
      CornerMixedArea(aa, bb, ab, twiceArea, (aa - ab) * inverseTwiceArea, (bb - ab) * inverseTwiceArea);
  }
  const V3 N = inverseTwiceArea * normal;
  const V3 U = (1.0 / Sqrt(squared[0])) * edge[0];
  const V3 V = Cross(N, U);
  Real cosine[3], sine[3], tensor[3][3]; // entries 11, 12, 22 of each vertex's tensor in the face frame
  for (int k = 0; k < 3; ++k)
  {
    const Real k1 = frames[k][FrameMaximum], k2 = frames[k][FrameMinimum];
    const V3 turned = RotateLike(e1[k], n[k], N); // (a unit vector, now in the face's plane)
    const Real c = cosine[k] = Dot(turned, U), s = sine[k] = Dot(turned, V);
    fitted &= (c * c + s * s > 0.5) & Finite(k1) & Finite(k2);
    tensor[k][0] = k1 * c * c + k2 * s * s;
    tensor[k][1] = (k1 - k2) * c * s;
    tensor[k][2] = k1 * s * s + k2 * c * c;
  }
  Real uu = {}, uv = {}, vv = {}, r[4] = {};
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3;
    const Real du = Dot(edge[a], U), dv = Dot(edge[a], V);
    const Real t0 = tensor[b][0] - tensor[a][0], t1 = tensor[b][1] - tensor[a][1], t2 = tensor[b][2] - tensor[a][2];
    uu += du * du;
    uv += du * dv;
    vv += dv * dv;
    r[0] += du * t0;
    r[1] += dv * t0 + du * t1;
    r[2] += dv * t1 + du * t2;
    r[3] += dv * t2;
  }
  const Real diagonal[4] = { uu, uu + vv, uu + vv, vv };
  Real C[4];
  fitted &= SolveTridiagonal(diagonal, uv, r, C);
  for (int k = 0; k < 3; ++k)
  {
    const Mask defined = fitted & (mixedArea[k] > 0.0);
    const Real zero = {};
    const Real area = defined ? mixedArea[k] : zero;
    const Real c = defined ? cosine[k] : zero, s = defined ? sine[k] : zero, cc = c * c, cs = c * s, ss = s * s;
    const Real w[4] = { defined ? C[0] : zero, defined ? C[1] : zero, defined ? C[2] : zero, defined ? C[3] : zero };
    terms[k][0] = area * (c * (w[0] * cc + 3.0 * w[2] * ss) + s * (3.0 * w[1] * cc + w[3] * ss));
    terms[k][1] = area * (c * (w[1] * (cc - 2.0 * ss) + w[3] * ss) + s * (w[2] * (2.0 * cc - ss) - w[0] * cc));
    terms[k][2] = area * (c * (w[2] * (cc - 2.0 * ss) + w[3] * cs) + s * (w[1] * (ss - 2.0 * cc) + w[0] * cs));
    terms[k][3] = area * (c * (w[3] * cc - 3.0 * w[2] * cs) + s * (3.0 * w[1] * cs - w[0] * ss));
    terms[k][4] = area;
  }
}

} // namespace

template <typename T>
Index ComputeCurvatureDerivatives(const MeshTopology& topo, const T* points, const CurvatureTensors& t,
  double* derivatives, int numThreads)
{
  const Index numFaces = topo.NumberOfTriangles();
  UninitializedVector<double> frames(FrameSize * static_cast<std::size_t>(topo.NumberOfVertices())); // (written whole)
  ParallelFor(topo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      double* frame = frames.data() + FrameSize * i;
      for (int k = 0; k < 3; ++k)
      {
        frame[FramePoint + k] = static_cast<double>(points[3 * i + k]);
        frame[FrameNormal + k] = t.Normals[3 * i + k];
        frame[FrameDirection + k] = t.Direction1[3 * i + k];
      }
      frame[FrameMaximum] = t.Maximum[i];
      frame[FrameMinimum] = t.Minimum[i];
    }
  });
  // Each corner's term in corner order (written in sequence: writing them
  // into their vertices' order took a third more time), read by the
  // vertices through their corner lists.
  UninitializedVector<CornerTerm> terms(3 * static_cast<std::size_t>(numFaces)); // (each written once)
  const IndexArray& tri = topo.TriangleList();
  ParallelFor(numFaces, numThreads, [&](std::int64_t begin, std::int64_t end) {
    Real batch[3][FrameSize], fitted[3][5];
    for (std::int64_t first = begin; first < end; first += Lanes)
    {
      const int count = static_cast<int>(std::min<std::int64_t>(Lanes, end - first));
      for (int l = 0; l < Lanes && first + l + PrefetchDistance < end; ++l)
      {
        for (int k = 0; k < 3; ++k)
        {
          const Index vertex = tri[3 * (first + l + PrefetchDistance) + k];
          const double* ahead = frames.data() + FrameSize * static_cast<std::int64_t>(vertex);
          __builtin_prefetch(ahead);
          __builtin_prefetch(ahead + FrameSize - 1);
        }
      }
      for (int k = 0; k < 3; ++k)
      {
        const double* f[Lanes]; // (spare lanes repeat the last face)
        for (int l = 0; l < Lanes; ++l)
        {
          f[l] = frames.data() + FrameSize * static_cast<std::int64_t>(tri[3 * (first + std::min(l, count - 1)) + k]);
        }
        static_assert(Lanes == 4, "one value of each lane's face below");
        for (int j = 0; j < FrameSize; ++j)
        {
          batch[k][j] = Real{ f[0][j], f[1][j], f[2][j], f[3][j] }; // (built in registers: no lane-wise stores)
        }
      }
      FitFaces(batch, fitted);
      for (int l = 0; l < count; ++l)
      {
        for (int k = 0; k < 3; ++k)
        {
          CornerTerm& term = terms[3 * (first + l) + k];
          for (int j = 0; j < 4; ++j)
          {
            term.Weighted[j] = static_cast<float>(fitted[k][j][l]);
          }
          term.Area = static_cast<float>(fitted[k][4][l]);
        }
      }
    }
  });
  std::atomic<Index> undefined{ 0 };
  ParallelFor(topo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    Index missing = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      if (i + PrefetchDistance < end) // (the corners' terms are random reads)
      {
        for (const Index* c = topo.CornersBegin(i + PrefetchDistance); c != topo.CornersEnd(i + PrefetchDistance); ++c)
        {
          __builtin_prefetch(terms.data() + *c);
        }
      }
      double sum[4] = { 0, 0, 0, 0 }, weight = 0.0;
      for (const Index* c = topo.CornersBegin(i); c != topo.CornersEnd(i); ++c)
      {
        for (int k = 0; k < 4; ++k)
        {
          sum[k] += terms[*c].Weighted[k];
        }
        weight += terms[*c].Area;
      }
      double* out = derivatives + 4 * static_cast<std::int64_t>(i);
      for (int k = 0; k < 4; ++k)
      {
        out[k] = weight > 0.0 ? sum[k] / weight : NaN;
      }
      missing += !(weight > 0.0);
    }
    undefined += missing;
  });
  return undefined;
}

template Index ComputeCurvatureDerivatives<float>(
  const MeshTopology&, const float*, const CurvatureTensors&, double*, int);
template Index ComputeCurvatureDerivatives<double>(
  const MeshTopology&, const double*, const CurvatureTensors&, double*, int);

} // namespace beltrami
