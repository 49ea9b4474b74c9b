#include "Mesh/CurvatureDerivatives.h"

#include "Mesh/Geometry.h"
#include "Mesh/RingGeometry.h"

#include "Support/LargeBuffer.h"

#include <Eigen/Geometry>

#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

namespace beltrami
{

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

/// x turned by the smallest rotation that takes the unit vector `from` to
/// the unit vector `to` (Rodrigues); reversed when they are opposite.
Vec3 RotateLike(const Vec3& x, const Vec3& from, const Vec3& to)
{
  const double c = from.dot(to);
  if (c <= -1.0 + 1e-12)
  {
    return -x;
  }
  const Vec3 k = from.cross(to);
  return c * x + k.cross(x) + (k.dot(x) / (1.0 + c)) * k;
}

/// Solves the symmetric positive definite tridiagonal system with the
/// given diagonal and constant off-diagonal (4 unknowns) by its LDL^T
/// factors; false where a pivot is not positive (or not finite).
inline bool SolveTridiagonal(const double (&diagonal)[4], double off, const double (&r)[4], double (&x)[4])
{
  double inverse[4], factor[4], z[4];
  bool positive = diagonal[0] > 0.0;
  inverse[0] = 1.0 / diagonal[0];
  z[0] = r[0];
  for (int k = 1; k < 4; ++k)
  {
    factor[k] = off * inverse[k - 1];
    const double pivot = diagonal[k] - factor[k] * off;
    positive = positive && pivot > 0.0;
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
    positive = positive && std::isfinite(x[k]);
  }
  return positive;
}

/// A face's tensor C in its frame (U, N x U); per corner the mixed area
/// (figure 2.3), the weight of its vertex's average, and the vertex's e1
/// turned into the face's plane, in that frame.
struct FaceDerivative
{
  double C[4];
  double MixedArea[3];
  double Cos[3], Sin[3];
};

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

/// Rusinkiewicz's per-face fit: false where a vertex tensor is undefined
/// or the face is degenerate.
bool FitFace(const double* frames, const Index* v, FaceDerivative& face)
{
  Vec3 p[3];
  for (int k = 0; k < 3; ++k)
  {
    p[k] = LoadPoint<3>(frames, FrameSize, v[k]);
  }
  const Vec3 edge[3] = { p[1] - p[0], p[2] - p[1], p[0] - p[2] }; // edge k: from corner k to k + 1
  const double squared[3] = { edge[0].squaredNorm(), edge[1].squaredNorm(), edge[2].squaredNorm() };
  const Vec3 normal = edge[0].cross(-edge[2]);
  const double twiceArea = normal.norm();
  if (!(twiceArea > DegenerateTolerance * std::max({ squared[0], squared[1], squared[2] })))
  {
    return false;
  }
  // The corners' mixed areas with one square root for the three (the
  // corner geometry of the 1-ring loops takes one each).
  const double inverseTwiceArea = 1.0 / twiceArea;
  for (int k = 0; k < 3; ++k)
  {
    const double aa = squared[k], bb = squared[(k + 2) % 3], ab = -edge[k].dot(edge[(k + 2) % 3]);
    face.MixedArea[k] =
      CornerMixedArea(aa, bb, ab, twiceArea, (aa - ab) * inverseTwiceArea, (bb - ab) * inverseTwiceArea);
  }
  const Vec3 N = normal * inverseTwiceArea;
  const Vec3 U = edge[0] / std::sqrt(squared[0]);
  const Vec3 V = N.cross(U);
  double tensor[3][3]; // entries 11, 12, 22 of each vertex's tensor in the face frame
  for (int k = 0; k < 3; ++k)
  {
    const double* frame = frames + FrameSize * static_cast<std::int64_t>(v[k]);
    const double k1 = frame[FrameMaximum], k2 = frame[FrameMinimum];
    // (A rotation keeps e1 a unit vector, now in the face's plane.)
    const Vec3 e1 = RotateLike(Vec3(frame + FrameDirection), Vec3(frame + FrameNormal), N);
    const double c = face.Cos[k] = e1.dot(U), s = face.Sin[k] = e1.dot(V);
    if (!(c * c + s * s > 0.5) || !std::isfinite(k1) || !std::isfinite(k2))
    {
      return false;
    }
    tensor[k][0] = k1 * c * c + k2 * s * s;
    tensor[k][1] = (k1 - k2) * c * s;
    tensor[k][2] = k1 * s * s + k2 * c * c;
  }
  // Along edge a -> b with components (du, dv): the tensor's change is
  // [[C111 du + C112 dv, C112 du + C122 dv], [., C122 du + C222 dv]]; the
  // normal equations of these 9 equations in C are tridiagonal.
  double uu = 0.0, uv = 0.0, vv = 0.0, r[4] = { 0.0, 0.0, 0.0, 0.0 };
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3;
    const double du = edge[a].dot(U), dv = edge[a].dot(V);
    const double t0 = tensor[b][0] - tensor[a][0], t1 = tensor[b][1] - tensor[a][1], t2 = tensor[b][2] - tensor[a][2];
    uu += du * du;
    uv += du * dv;
    vv += dv * dv;
    r[0] += du * t0;
    r[1] += dv * t0 + du * t1;
    r[2] += dv * t1 + du * t2;
    r[3] += dv * t2;
  }
  const double diagonal[4] = { uu, uu + vv, uu + vv, vv };
  return SolveTridiagonal(diagonal, uv, r, face.C);
}

/// A corner's part of its vertex's average: the face's tensor in the
/// vertex's principal frame times the corner's mixed area, and that area
/// (zeros where the area or the vertex's frame is not defined).
struct CornerTerm
{
  double Weighted[4];
  double Area;
};

/// The term of corner k of a fitted face.  The turn R from the face's
/// normal to the vertex's is the inverse of the one FitFace turned e1 by,
/// so in the face frame turned into the vertex's plane (R U, R V) e1 has
/// the parts e1 . R U = R^-1 e1 . U = Cos[k] and Sin[k], and e2 = n x e1
/// the parts -Sin[k], Cos[k]: the four values are C(a,a,a), C(a,a,b),
/// C(a,b,b), C(b,b,b) of EvaluateCubicForm with a = (c, s), b = (-s, c),
/// expanded.
CornerTerm TermOf(const FaceDerivative& face, int k)
{
  const double area = face.MixedArea[k];
  if (!(area > 0.0))
  {
    return CornerTerm{};
  }
  const double c = face.Cos[k], s = face.Sin[k], cc = c * c, cs = c * s, ss = s * s;
  const double* C = face.C;
  return CornerTerm{ { area * (c * (C[0] * cc + 3.0 * C[2] * ss) + s * (3.0 * C[1] * cc + C[3] * ss)),
                       area * (c * (C[1] * (cc - 2.0 * ss) + C[3] * ss) + s * (C[2] * (2.0 * cc - ss) - C[0] * cc)),
                       area * (c * (C[2] * (cc - 2.0 * ss) + C[3] * cs) + s * (C[1] * (ss - 2.0 * cc) + C[0] * cs)),
                       area * (c * (C[3] * cc - 3.0 * C[2] * cs) + s * (3.0 * C[1] * cs - C[0] * ss)) },
    area };
}

} // namespace

template <typename T>
Index ComputeCurvatureDerivatives(const MeshTopology& topo, const T* points, const CurvatureTensors& t,
  double* derivatives, int numThreads)
{
  const Index numFaces = topo.NumberOfTriangles();
  LargeVector<double> frames(FrameSize * static_cast<std::size_t>(topo.NumberOfVertices()));
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
  LargeVector<CornerTerm> terms(3 * static_cast<std::size_t>(numFaces));
  const IndexArray& tri = topo.TriangleList();
  ParallelFor(numFaces, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const Index* v = tri.data() + 3 * f;
      if (f + PrefetchDistance < end)
      {
        for (int k = 0; k < 3; ++k)
        {
          const double* frame = frames.data() + FrameSize * static_cast<std::int64_t>(v[3 * PrefetchDistance + k]);
          __builtin_prefetch(frame);
          __builtin_prefetch(frame + FrameSize - 1);
        }
      }
      FaceDerivative face;
      const bool fitted = FitFace(frames.data(), v, face);
      for (int k = 0; k < 3; ++k)
      {
        terms[3 * f + k] = fitted ? TermOf(face, k) : CornerTerm{};
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
