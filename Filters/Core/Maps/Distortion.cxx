#include "Maps/Distortion.h"

#include "Mesh/RingGeometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace beltrami
{

double SignedArea2D(const MeshTopology& topo, const double* uv, Index t)
{
  const Vec2 a = UV(uv, topo.CornerVertex(3 * t));
  const Vec2 b = UV(uv, topo.CornerVertex(3 * t + 1)) - a;
  const Vec2 c = UV(uv, topo.CornerVertex(3 * t + 2)) - a;
  return 0.5 * (b.x() * c.y() - b.y() * c.x());
}

double Area3D(const MeshTopology& topo, const double* points, Index t)
{
  const Vec3 a = Point(points, topo.CornerVertex(3 * t));
  return 0.5 *
    (Point(points, topo.CornerVertex(3 * t + 1)) - a).cross(Point(points, topo.CornerVertex(3 * t + 2)) - a).norm();
}

bool Degenerate3D(const MeshTopology& topo, const double* points, Index t)
{
  const Vec3 a = Point(points, topo.CornerVertex(3 * t));
  const Vec3 b = Point(points, topo.CornerVertex(3 * t + 1));
  const Vec3 c = Point(points, topo.CornerVertex(3 * t + 2));
  const double longest = std::max({ (b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm() });
  return !((b - a).cross(c - a).norm() > DegenerateTolerance * longest);
}

double TotalArea3D(const MeshTopology& topo, const double* points, int threads)
{
  return ParallelSum(topo.NumberOfTriangles(), 1, threads, [&](std::int64_t b, std::int64_t e, double* s) {
    for (std::int64_t t = b; t < e; ++t)
    {
      *s += Area3D(topo, points, static_cast<Index>(t));
    }
  })[0];
}

double TotalArea2D(const MeshTopology& topo, const double* uv, int threads)
{
  return ParallelSum(topo.NumberOfTriangles(), 1, threads, [&](std::int64_t b, std::int64_t e, double* s) {
    for (std::int64_t t = b; t < e; ++t)
    {
      *s += SignedArea2D(topo, uv, static_cast<Index>(t));
    }
  })[0];
}

Index CountFlipped(const MeshTopology& topo, const double* points, const double* uv)
{
  Index flipped = 0;
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    flipped += !Degenerate3D(topo, points, t) && !(SignedArea2D(topo, uv, t) > 0.0);
  }
  return flipped;
}

double DistortionEnergyValue(const MeshTopology& topo, const double* points, const double* uv,
  double scale, DistortionEnergy energy, double* gradient)
{
  const double s2 = scale * scale;
  if (gradient)
  {
    std::fill(gradient, gradient + 2 * static_cast<std::size_t>(topo.NumberOfVertices()), 0.0);
  }
  double total = 0.0;
  if (energy == DistortionEnergy::EdgeLength)
  {
    ForEachEdge(topo, points, [&](Index i, Index j, double xx) {
      const Vec2 d = UV(uv, i) - UV(uv, j);
      const double q = s2 * d.squaredNorm() / xx - 1.0;
      total += q * q;
      if (gradient)
      {
        const Vec2 g = 4.0 * q * s2 / xx * d;
        gradient[2 * i] += g.x();
        gradient[2 * i + 1] += g.y();
        gradient[2 * j] -= g.x();
        gradient[2 * j + 1] -= g.y();
      }
    });
    return total;
  }
  ForEachTriangle(topo, points, [&](Index t, double a3) {
    const double r = s2 * SignedArea2D(topo, uv, t) / a3;
    total += (r * r - 1.0) * (r * r - 1.0);
    if (gradient)
    {
      // dE/dr = 4 r (r^2 - 1); dA/du_a = 1/2 R(u_c - u_b) for the corner a.
      const double f = 4.0 * r * (r * r - 1.0) * s2 / a3;
      for (int k = 0; k < 3; ++k)
      {
        const Index a = topo.CornerVertex(3 * t + k);
        const Vec2 b = UV(uv, topo.CornerVertex(3 * t + (k + 1) % 3));
        const Vec2 c = UV(uv, topo.CornerVertex(3 * t + (k + 2) % 3));
        gradient[2 * a] += f * 0.5 * (b.y() - c.y());
        gradient[2 * a + 1] += f * 0.5 * (c.x() - b.x());
      }
    }
  });
  return total;
}

DistortionReport MeasureDistortion(
  const MeshTopology& topo, const double* points, const double* uv, int numThreads, const Partition* split)
{
  const int threads = ResolveThreadCount(numThreads);
  const Index nt = topo.NumberOfTriangles();
  // Split: the sums over the triangles this process counts, over all processes.
  std::vector<std::uint8_t> counted(nt, 1);
  for (Index t = 0; split && t < nt; ++t)
  {
    counted[t] = split->CountsTriangle(topo.CornerVertex(3 * t), topo.CornerVertex(3 * t + 1), topo.CornerVertex(3 * t + 2));
  }
  DistortionReport r;
  r.AngleDistortion.assign(nt, 0.0);
  r.AreaDistortion.assign(nt, 0.0);
  r.EdgeDistortion.assign(nt, 0.0);
  double areas[2] = { 0.0, 0.0 }; // 3D, signed 2D
  for (Index t = 0; t < nt; ++t)
  {
    if (counted[t])
    {
      areas[0] += Area3D(topo, points, t);
      areas[1] += SignedArea2D(topo, uv, t);
    }
  }
  if (split)
  {
    split->Sum(areas, 2);
  }
  const double a3 = areas[0], a2 = areas[1];
  const double s = a2 != 0.0 && a3 > 0.0 ? std::sqrt(std::abs(a2) / a3) : 1.0;
  std::vector<std::uint8_t> degenerate(nt, 0), flipped(nt, 0);
  ParallelFor(nt, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index t = static_cast<Index>(begin); t < end; ++t)
    {
      if (Degenerate3D(topo, points, t))
      {
        degenerate[t] = 1;
        r.AngleDistortion[t] = r.AreaDistortion[t] = r.EdgeDistortion[t] = std::nan("");
        continue;
      }
      double angle = 0.0, edge = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const Index a = topo.CornerVertex(3 * t + k);
        const Index b = topo.CornerVertex(3 * t + (k + 1) % 3);
        const Index c = topo.CornerVertex(3 * t + (k + 2) % 3);
        const Vec3 e1 = Point(points, b) - Point(points, a), e2 = Point(points, c) - Point(points, a);
        const Vec2 f1 = UV(uv, b) - UV(uv, a), f2 = UV(uv, c) - UV(uv, a);
        const double angle3 = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
        const double angle2 = std::atan2(std::abs(f1.x() * f2.y() - f1.y() * f2.x()), f1.dot(f2));
        angle += std::abs(angle2 - angle3);
        const double ratio = f1.norm() / (s * e1.norm());
        edge += ratio > 0.0 ? std::abs(std::log(ratio)) : 50.0; // collapsed edge: large, finite
      }
      r.AngleDistortion[t] = angle / 3.0 * 180.0 / M_PI;
      r.EdgeDistortion[t] = edge / 3.0;
      const double area2 = SignedArea2D(topo, uv, t);
      flipped[t] = !(area2 > 0.0);
      const double ratio = std::abs(area2) / (s * s * Area3D(topo, points, t));
      r.AreaDistortion[t] = ratio > 0.0 ? std::log(ratio) : -50.0;
    }
  });
  // sums: used, degenerate, flipped, angle, area, edge; largest: angle, area, edge
  double sums[6] = { 0, 0, 0, 0, 0, 0 }, largest[3] = { 0, 0, 0 };
  for (Index t = 0; t < nt; ++t)
  {
    if (!counted[t] || degenerate[t])
    {
      sums[1] += counted[t];
      continue;
    }
    const double values[3] = { r.AngleDistortion[t], std::abs(r.AreaDistortion[t]), r.EdgeDistortion[t] };
    sums[0] += 1.0;
    sums[2] += flipped[t];
    for (int k = 0; k < 3; ++k)
    {
      sums[3 + k] += values[k];
      largest[k] = std::max(largest[k], values[k]);
    }
  }
  if (split)
  {
    split->Sum(sums, 6);
    split->Max(largest, 3);
  }
  const double used = std::max(sums[0], 1.0);
  r.DegenerateTriangles = static_cast<Index>(sums[1]);
  r.FlippedTriangles = static_cast<Index>(sums[2]);
  r.MeanAngle = sums[3] / used;
  r.MeanArea = sums[4] / used;
  r.MeanEdge = sums[5] / used;
  r.MaxAngle = largest[0];
  r.MaxArea = largest[1];
  r.MaxEdge = largest[2];
  return r;
}

} // namespace beltrami
