#include "Mesh/CurvatureDerivatives.h"

#include "Mesh/Geometry.h"
#include "Mesh/RingGeometry.h"

#include <Eigen/Cholesky>
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

/// A face's tensor C in its frame (U, N x U).
struct FaceDerivative
{
  double C[4];
  Vec3 U, N;
};

/// Rusinkiewicz's per-face fit: false where a vertex tensor is undefined
/// or the face is degenerate.
template <typename T>
bool FitFace(const T* points, const CurvatureTensors& t, const Index* v, FaceDerivative& face)
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
  face.N = normal.normalized();
  face.U = (p[1] - p[0]).normalized();
  const Vec3 V = face.N.cross(face.U);
  double tensor[3][3]; // entries 11, 12, 22 of each vertex's tensor in the face frame
  for (int k = 0; k < 3; ++k)
  {
    const double k1 = t.Maximum[v[k]], k2 = t.Minimum[v[k]];
    const Vec3 e1 = RotateLike(Point(t.Direction1, v[k]), Point(t.Normals, v[k]), face.N);
    double c = e1.dot(face.U), s = e1.dot(V);
    const double length = std::sqrt(c * c + s * s); // (a unit vector's parts)
    if (!(length > 0.0) || !std::isfinite(k1) || !std::isfinite(k2))
    {
      return false;
    }
    c /= length;
    s /= length;
    tensor[k][0] = k1 * c * c + k2 * s * s;
    tensor[k][1] = (k1 - k2) * c * s;
    tensor[k][2] = k1 * s * s + k2 * c * c;
  }
  // Along edge a -> b with components (du, dv): the tensor's change is
  // [[C111 du + C112 dv, C112 du + C122 dv], [., C122 du + C222 dv]].
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  Eigen::Vector4d r = Eigen::Vector4d::Zero();
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3;
    const Vec3 d = p[b] - p[a];
    const double du = d.dot(face.U), dv = d.dot(V);
    for (int entry = 0; entry < 3; ++entry)
    {
      Eigen::Vector4d row = Eigen::Vector4d::Zero();
      row[entry] = du;
      row[entry + 1] = dv;
      m += row * row.transpose();
      r += row * (tensor[b][entry] - tensor[a][entry]);
    }
  }
  const Eigen::Vector4d c = m.ldlt().solve(r);
  for (int k = 0; k < 4; ++k)
  {
    face.C[k] = c[k];
  }
  return c.allFinite();
}

} // namespace

template <typename T>
Index ComputeCurvatureDerivatives(const MeshTopology& topo, const T* points, const CurvatureTensors& t,
  double* derivatives, int numThreads)
{
  const Index numFaces = topo.NumberOfTriangles();
  std::vector<FaceDerivative> faces(numFaces);
  std::vector<std::uint8_t> fitted(numFaces);
  const IndexArray& tri = topo.TriangleList();
  ParallelFor(numFaces, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      fitted[f] = FitFace(points, t, tri.data() + 3 * f, faces[f]);
    }
  });
  std::atomic<Index> undefined{ 0 };
  ParallelFor(topo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    Index missing = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      double* out = derivatives + 4 * static_cast<std::int64_t>(i);
      const Vec3 n = Point(t.Normals, i), e1 = Point(t.Direction1, i), e2 = Point(t.Direction2, i);
      double sum[4] = { 0, 0, 0, 0 }, weight = 0.0;
      if (e1.allFinite() && e2.allFinite() && n.allFinite())
      {
        ForEachRingCorner<3>(topo, points, 3, i, LoadPoint<3>(points, 3, i), [&](const CornerGeometry<3>& g) {
          const Index f = g.Corner / 3;
          if (!fitted[f] || g.Degenerate)
          {
            return;
          }
          // The face frame turned into the vertex's tangent plane.
          const Vec3 u = RotateLike(faces[f].U, faces[f].N, n), v = n.cross(u);
          const double a[2] = { e1.dot(u), e1.dot(v) }, b[2] = { e2.dot(u), e2.dot(v) };
          const double* c = faces[f].C;
          sum[0] += g.MixedArea * EvaluateCubicForm(c, a, a, a);
          sum[1] += g.MixedArea * EvaluateCubicForm(c, a, a, b);
          sum[2] += g.MixedArea * EvaluateCubicForm(c, a, b, b);
          sum[3] += g.MixedArea * EvaluateCubicForm(c, b, b, b);
          weight += g.MixedArea;
        });
      }
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
