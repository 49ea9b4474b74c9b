#include "Drawing/ApparentRidges.h"

#include "Drawing/FaceZeroSets.h"
#include "Solvers/Partition.h"

#include <cmath>
#include <limits>

namespace beltrami
{

namespace
{

/// q1 and t1 at a point: normal n, principal curvatures k1, k2 along e1, e2,
/// v the unit vector towards the viewer.  False where n.v <= 0.
bool ViewCurvature(const Vec3& n, double k1, double k2, const Vec3& e1, const Vec3& e2, const Vec3& v, double& q1,
  Vec3& t1)
{
  const double c = n.dot(v);
  if (!(c > 1e-12) || !std::isfinite(k1) || !std::isfinite(k2))
  {
    return false;
  }
  // N = (I + w w^T / c^2) S^2 in the principal frame (w: v's tangent part).
  const double w1 = v.dot(e1) / c, w2 = v.dot(e2) / c, s1 = k1 * k1, s2 = k2 * k2;
  const double n11 = (1.0 + w1 * w1) * s1, n12 = w1 * w2 * s2, n21 = w1 * w2 * s1, n22 = (1.0 + w2 * w2) * s2;
  const double half = 0.5 * (n11 + n22), det = n11 * n22 - n12 * n21;
  const double lambda = half + std::sqrt(std::max(half * half - det, 0.0));
  // Its eigenvector: of the two forms, the longer one (both vanish where N
  // is lambda I: any direction).
  double x1 = n12, x2 = lambda - n11;
  const double y1 = lambda - n22, y2 = n21;
  if (y1 * y1 + y2 * y2 > x1 * x1 + x2 * x2)
  {
    x1 = y1;
    x2 = y2;
  }
  if (!(x1 * x1 + x2 * x2 > 0.0))
  {
    x1 = 1.0;
    x2 = 0.0;
  }
  q1 = std::sqrt(lambda);
  t1 = (x1 * e1 + x2 * e2).normalized();
  return std::isfinite(q1);
}

} // namespace

ApparentCurvature ComputeApparentCurvature(const LineDrawingGeometry& geo, const LineView& view, int numThreads)
{
  const Index n = geo.NumberOfVertices();
  ApparentCurvature out;
  out.Q1.assign(n, std::numeric_limits<double>::quiet_NaN());
  out.T1.assign(3 * static_cast<std::size_t>(n), 0.0);
  const Vec3 toward = -view.Direction.normalized();
  ParallelFor(n, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const Index v = static_cast<Index>(i);
      const Vec3 p = Point(geo.FieldPoints(), v);
      const Vec3 eye = view.Perspective ? Vec3((view.Position - p).normalized()) : toward;
      Vec3 t1;
      if (ViewCurvature(Point(geo.Normals.data(), v), geo.K1[i], geo.K2[i], Point(geo.E1.data(), v),
            Point(geo.E2.data(), v), eye, out.Q1[i], t1))
      {
        std::copy(t1.data(), t1.data() + 3, out.T1.begin() + 3 * i);
      }
      else
      {
        out.Q1[i] = std::numeric_limits<double>::quiet_NaN();
      }
    }
  });
  // D_t1 q1: the gradients of q1 on the triangles, averaged at each vertex
  // by area (one pass over the faces, in order: the same sums for any
  // thread count).
  std::vector<double> gradient(3 * static_cast<std::size_t>(n), 0.0), area(n, 0.0);
  for (Index f = 0; f < geo.NumberOfFaces(); ++f)
  {
    const Index* v = geo.Triangles.data() + 3 * static_cast<std::int64_t>(f);
    double q[3];
    Corners(geo.Triangles, f, out.Q1.data(), q);
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2]))
    {
      continue;
    }
    const Vec3 p[3] = { Point(geo.FieldPoints(), v[0]), Point(geo.FieldPoints(), v[1]), Point(geo.FieldPoints(), v[2]) };
    const double a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const Vec3 g = a * FaceGradient(p, q);
    for (int k = 0; k < 3; ++k)
    {
      for (int d = 0; d < 3; ++d)
      {
        gradient[3 * static_cast<std::size_t>(v[k]) + d] += g[d];
      }
      area[v[k]] += a;
    }
  }
  out.Derivative.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (Index v = 0; v < n; ++v)
  {
    if (area[v] > 0.0 && std::isfinite(out.Q1[v]))
    {
      out.Derivative[v] = Point(gradient.data(), v).dot(Point(out.T1.data(), v)) / area[v];
    }
  }
  if (geo.Split)
  {
    // A ghost point's star is cut at the edge of the ring: its owner's
    // derivative (collective; q1 and t1 there are the owner's already, from
    // its curvatures).
    geo.Split->UpdateGhosts(out.Derivative.data(), 1);
  }
  return out;
}

SegmentList ApparentRidgeSegments(const LineDrawingGeometry& geo, const ApparentCurvature& curvature,
  const LineDrawingOptions& options, double size)
{
  const float creaseCosine = LineDrawingGeometry::CreaseCosine(options.CreaseAngle);
  const double threshold = options.ApparentRidgeThreshold * HysteresisFactor(options);
  return std::move(CollectSegments(geo.NumberOfFaces(), options.NumberOfThreads, 1,
    [&](Index f, std::vector<LineSegment>* out) {
      const Index* v = geo.Triangles.data() + 3 * static_cast<std::int64_t>(f);
      if (!geo.Draws(f) || (options.AvoidCreases && geo.AtCrease(f, creaseCosine)))
      {
        return;
      }
      // t1 is a line, not a vector: turned like the first corner's, and
      // the derivative with it.
      Vec3 t[3];
      double g[3], test[3];
      for (int k = 0; k < 3; ++k)
      {
        t[k] = Point(curvature.T1.data(), v[k]);
        const double flip = k > 0 && t[k].dot(t[0]) < 0.0 ? -1.0 : 1.0;
        t[k] *= flip;
        g[k] = flip * curvature.Derivative[v[k]];
        test[k] = curvature.Q1[v[k]] * size - threshold;
      }
      LineSegment s;
      if (!ZeroCrossing(geo, f, v, g, s))
      {
        return; // (no crossing, or a corner without q1: not facing the viewer)
      }
      const Vec3 p[3] = { Point(geo.FieldPoints(), v[0]), Point(geo.FieldPoints(), v[1]), Point(geo.FieldPoints(), v[2]) };
      if (FaceGradient(p, g).dot(t[0] + t[1] + t[2]) < 0.0 && Clip(s, test))
      {
        out[0].push_back(s); // a maximum along t1, strong enough
      }
    })[0]);
}

} // namespace beltrami
