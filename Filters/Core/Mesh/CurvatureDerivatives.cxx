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
  double pivot[4], factor[4], z[4];
  pivot[0] = diagonal[0];
  z[0] = r[0];
  for (int k = 1; k < 4; ++k)
  {
    factor[k] = off / pivot[k - 1];
    pivot[k] = diagonal[k] - factor[k] * off;
    z[k] = r[k] - factor[k] * z[k - 1];
  }
  x[3] = z[3] / pivot[3];
  for (int k = 2; k >= 0; --k)
  {
    x[k] = z[k] / pivot[k] - factor[k + 1] * x[k + 1];
  }
  bool positive = true;
  for (int k = 0; k < 4; ++k)
  {
    positive = positive && pivot[k] > 0.0 && std::isfinite(x[k]);
  }
  return positive;
}

/// A face's tensor C in its frame (U, N x U); per corner the mixed area
/// (figure 2.3; 0 where degenerate), the weight of its vertex's average,
/// and the vertex's e1 turned into the face's plane, in that frame.
struct FaceDerivative
{
  double C[4];
  Vec3 U, N;
  double MixedArea[3];
  double Cos[3], Sin[3];
};

/// Rusinkiewicz's per-face fit: false where a vertex tensor is undefined
/// or the face is degenerate.
template <typename T>
bool FitFace(const T* points, const CurvatureTensors& t, const Index* v, Index f, FaceDerivative& face)
{
  Vec3 p[3];
  for (int k = 0; k < 3; ++k)
  {
    p[k] = LoadPoint<3>(points, 3, v[k]);
  }
  const Vec3 normal = (p[1] - p[0]).cross(p[2] - p[0]);
  const double longest =
    std::max({ (p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm() });
  if (!(normal.norm() > DegenerateTolerance * longest))
  {
    return false;
  }
  for (int k = 0; k < 3; ++k)
  {
    // As ForEachRingCorner gives corner k: (x_k, its next, its previous).
    face.MixedArea[k] = MakeCornerGeometry<3>(points, 3, p[k], 3 * f + k, v[(k + 1) % 3], v[(k + 2) % 3]).MixedArea;
  }
  face.N = normal.normalized();
  face.U = (p[1] - p[0]).normalized();
  const Vec3 V = face.N.cross(face.U);
  double tensor[3][3]; // entries 11, 12, 22 of each vertex's tensor in the face frame
  for (int k = 0; k < 3; ++k)
  {
    const double k1 = t.Maximum[v[k]], k2 = t.Minimum[v[k]];
    const Vec3 e1 = RotateLike(Point(t.Direction1, v[k]), Point(t.Normals, v[k]), face.N);
    face.Cos[k] = e1.dot(face.U);
    face.Sin[k] = e1.dot(V);
    const double length = std::sqrt(face.Cos[k] * face.Cos[k] + face.Sin[k] * face.Sin[k]); // (about 1)
    if (!(length > 0.0) || !std::isfinite(k1) || !std::isfinite(k2))
    {
      return false;
    }
    const double c = face.Cos[k] / length, s = face.Sin[k] / length;
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
    const Vec3 d = p[b] - p[a];
    const double du = d.dot(face.U), dv = d.dot(V);
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
/// the parts -Sin[k], Cos[k].
CornerTerm TermOf(const FaceDerivative& face, int k)
{
  const double area = face.MixedArea[k];
  if (!(area > 0.0))
  {
    return CornerTerm{};
  }
  const double a[2] = { face.Cos[k], face.Sin[k] }, b[2] = { -face.Sin[k], face.Cos[k] };
  const double* c = face.C;
  return CornerTerm{ { area * EvaluateCubicForm(c, a, a, a), area * EvaluateCubicForm(c, a, a, b),
                       area * EvaluateCubicForm(c, a, b, b), area * EvaluateCubicForm(c, b, b, b) },
    area };
}

} // namespace

template <typename T>
Index ComputeCurvatureDerivatives(const MeshTopology& topo, const T* points, const CurvatureTensors& t,
  double* derivatives, int numThreads)
{
  const Index numFaces = topo.NumberOfTriangles();
  const Index* firstCorner = topo.CornersBegin(0);
  // Each corner's slot in its vertex's list of corners: the faces write
  // their corners' terms there, and the vertices read theirs in order.
  LargeVector<Index> slot(3 * static_cast<std::size_t>(numFaces));
  ParallelFor(topo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      for (const Index* c = topo.CornersBegin(i); c != topo.CornersEnd(i); ++c)
      {
        slot[*c] = static_cast<Index>(c - firstCorner);
      }
    }
  });
  LargeVector<CornerTerm> terms(slot.size());
  const IndexArray& tri = topo.TriangleList();
  ParallelFor(numFaces, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const Index* v = tri.data() + 3 * f;
      FaceDerivative face;
      const bool fitted = FitFace(points, t, v, static_cast<Index>(f), face);
      for (int k = 0; k < 3; ++k)
      {
        terms[slot[3 * f + k]] = fitted ? TermOf(face, k) : CornerTerm{};
      }
    }
  });
  std::atomic<Index> undefined{ 0 };
  ParallelFor(topo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    Index missing = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      double sum[4] = { 0, 0, 0, 0 }, weight = 0.0;
      for (std::int64_t s = topo.CornersBegin(i) - firstCorner; s < topo.CornersEnd(i) - firstCorner; ++s)
      {
        for (int k = 0; k < 4; ++k)
        {
          sum[k] += terms[s].Weighted[k];
        }
        weight += terms[s].Area;
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
