#include "Mesh/MeshMeasures.h"

#include "Mesh/TriangleTree.h"
#include "Support/DisjointSets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <vector>

namespace beltrami
{

namespace
{
/// Sum over triangles of f(a, b, c) (deterministic, parallel), 4 values;
/// triangles with a NaN or infinite corner are left out (the measures of the
/// rest of the surface, where the flows keep such points fixed).
template <typename F>
std::vector<double> SumOverTriangles(const MeshTopology& topo, const double* points, int numThreads, F&& f)
{
  const IndexArray& tri = topo.TriangleList();
  return ParallelSum(topo.NumberOfTriangles(), 4, numThreads,
    [&](std::int64_t begin, std::int64_t end, double* acc) {
      for (std::int64_t t = begin; t < end; ++t)
      {
        const Index a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
        if (Point(points, a).allFinite() && Point(points, b).allFinite() && Point(points, c).allFinite())
        {
          f(a, b, c, acc);
        }
      }
    });
}

} // namespace

template <typename T>
Eigen::AlignedBox3d UsedPointsBox(const MeshTopology& topo, const T* points)
{
  Eigen::AlignedBox3d box;
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    const T* p = points + 3 * static_cast<std::size_t>(v);
    const Vec3 x(p[0], p[1], p[2]);
    if (topo.Valence(v) > 0 && x.allFinite())
    {
      box.extend(x);
    }
  }
  return box;
}
template Eigen::AlignedBox3d UsedPointsBox<float>(const MeshTopology&, const float*);
template Eigen::AlignedBox3d UsedPointsBox<double>(const MeshTopology&, const double*);

int FarScaleExponent(const Eigen::AlignedBox3d& box)
{
  if (box.isEmpty())
  {
    return 0;
  }
  const double extent = std::max(box.sizes().maxCoeff(), std::max(box.min().cwiseAbs().maxCoeff(),
    box.max().cwiseAbs().maxCoeff()));
  if (!(extent > 0.0) || !std::isfinite(extent))
  {
    return 0;
  }
  const int e = std::ilogb(extent);
  return e > 60 || e < -60 ? e : 0;
}

template <typename T>
std::vector<double> PointsTimesPowerOfTwo(const T* points, Index numberOfVertices, int exponent)
{
  std::vector<double> out(3 * static_cast<std::size_t>(numberOfVertices));
  for (std::size_t k = 0; k < out.size(); ++k)
  {
    out[k] = std::ldexp(static_cast<double>(points[k]), exponent);
  }
  return out;
}
template std::vector<double> PointsTimesPowerOfTwo<float>(const float*, Index, int);
template std::vector<double> PointsTimesPowerOfTwo<double>(const double*, Index, int);

void TimesPowerOfTwo(double* values, std::size_t count, int exponent)
{
  for (std::size_t k = 0; values && k < count; ++k)
  {
    values[k] = std::ldexp(values[k], exponent);
  }
}

Vec3 VertexCentroid(const MeshTopology& topo, const double* points)
{
  Vec3 c = Vec3::Zero();
  Index used = 0;
  for (Index i = 0; i < topo.NumberOfVertices(); ++i)
  {
    const Vec3 p = Point(points, i);
    if (topo.Valence(i) > 0 && p.allFinite())
    {
      c += p;
      ++used;
    }
  }
  return used ? Vec3(c / used) : c;
}

double VolumeAndCentroid(const MeshTopology& topo, const double* points, int numThreads, Vec3* centroid,
  const Vec3* origin)
{
  const Vec3 o = origin ? *origin : VertexCentroid(topo, points);
  const std::vector<double> s = SumOverTriangles(topo, points, numThreads, [&](Index a, Index b, Index c, double* acc) {
    const Vec3 pa = Point(points, a) - o, pb = Point(points, b) - o, pc = Point(points, c) - o;
    const double v = pa.dot(pb.cross(pc)) / 6.0;
    acc[0] += v;
    const Vec3 g = v * (pa + pb + pc) / 4.0; // tetrahedron (o, a, b, c)
    acc[1] += g[0];
    acc[2] += g[1];
    acc[3] += g[2];
  });
  if (centroid)
  {
    *centroid = s[0] != 0.0 ? Vec3(o + Vec3(s[1], s[2], s[3]) / s[0]) : o;
  }
  return s[0];
}

double AreaAndCentroid(const MeshTopology& topo, const double* points, int numThreads, Vec3* centroid)
{
  const std::vector<double> s = SumOverTriangles(topo, points, numThreads, [&](Index a, Index b, Index c, double* acc) {
    const Vec3 pa = Point(points, a), pb = Point(points, b), pc = Point(points, c);
    const double area = 0.5 * (pb - pa).cross(pc - pa).norm();
    acc[0] += area;
    const Vec3 g = area * (pa + pb + pc) / 3.0;
    acc[1] += g[0];
    acc[2] += g[1];
    acc[3] += g[2];
  });
  if (centroid)
  {
    *centroid = s[0] > 0.0 ? Vec3(Vec3(s[1], s[2], s[3]) / s[0]) : VertexCentroid(topo, points);
  }
  return s[0];
}

double HeightVolume(const MeshTopology& topo, const double* points, const Vec3& origin,
  const Vec3& normal, int numThreads)
{
  const std::vector<double> s = SumOverTriangles(topo, points, numThreads, [&](Index a, Index b, Index c, double* acc) {
    const Vec3 pa = Point(points, a) - origin, pb = Point(points, b) - origin,
               pc = Point(points, c) - origin;
    const double projectedArea = 0.5 * (pb - pa).cross(pc - pa).dot(normal);
    acc[0] += projectedArea * (pa + pb + pc).dot(normal) / 3.0;
  });
  return s[0];
}

double RevolutionVolume(const MeshTopology& topo, const double* points, const Vec3& origin, const Vec3& axis,
  int numThreads)
{
  const std::vector<double> s = SumOverTriangles(topo, points, numThreads, [&](Index a, Index b, Index c, double* acc) {
    const Vec3 pa = Point(points, a) - origin, pb = Point(points, b) - origin, pc = Point(points, c) - origin;
    // The field F = r / 2 (r the radial part of the position) is linear: its
    // flux through the triangle is the value at the centroid times the area vector.
    const Vec3 centre = (pa + pb + pc) / 3.0;
    const Vec3 radial = centre - centre.dot(axis) * axis;
    acc[0] += 0.25 * radial.dot((pb - pa).cross(pc - pa));
  });
  return s[0];
}

double MeanEdgeLength(const MeshTopology& topo, const double* x, const Partition* split)
{
  // Each edge once, at its lower vertex.
  const MeshTopology::VertexGraph& graph = topo.Graph();
  std::vector<double> sums = ParallelSum(topo.NumberOfVertices(), 2, topo.NumberOfThreads(),
    [&](std::int64_t begin, std::int64_t end, double* acc) { // lengths, edges
      for (Index a = static_cast<Index>(begin); a < end; ++a)
      {
        for (std::int64_t k = graph.NeighborOffsets[a]; k < graph.NeighborOffsets[a + 1]; ++k)
        {
          const Index b = graph.Neighbors[k];
          if (b <= a)
          {
            continue;
          }
          const double length = (Point(x, a) - Point(x, b)).norm();
          if (std::isfinite(length) && (!split || split->CountsEdge(a, b)))
          {
            acc[0] += length;
            acc[1] += 1.0;
          }
        }
      }
    });
  if (split)
  {
    split->Sum(sums.data(), 2);
  }
  return sums[1] > 0.0 ? sums[0] / sums[1] : 0.0;
}

TriangleQuality MeasureTriangleQuality(const MeshTopology& topo, const double* x)
{
  TriangleQuality q;
  const IndexArray& tri = topo.TriangleList();
  q.MinimumAngle = 180.0;
  Index measured = 0;
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    const Vec3 p[3] = { Point(x, tri[3 * t]), Point(x, tri[3 * t + 1]), Point(x, tri[3 * t + 2]) };
    double angles[3];
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      angles[k] = std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI;
    }
    const double smallest = std::min({ angles[0], angles[1], angles[2] });
    if (!(smallest > 0.0))
    {
      ++q.DegenerateTriangles;
      continue;
    }
    ++measured;
    q.MeanMinimumAngle += smallest;
    q.MinimumAngle = std::min(q.MinimumAngle, smallest);
    q.MaximumAngle = std::max({ q.MaximumAngle, angles[0], angles[1], angles[2] });
    q.FractionBelow30 += smallest < 30.0;
  }
  q.MeanMinimumAngle /= std::max<Index>(1, measured);
  q.FractionBelow30 /= std::max<Index>(1, topo.NumberOfTriangles());
  q.MinimumAngle = q.DegenerateTriangles > 0 || measured == 0 ? 0.0 : q.MinimumAngle;
  Index interior = 0, regular = 0;
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (topo.IsInterior(v) && topo.Valence(v) > 0)
    {
      ++interior;
      regular += topo.Valence(v) == 6;
    }
  }
  q.FractionValence6 = interior > 0 ? static_cast<double>(regular) / interior : 0.0;
  const MeshTopology::EdgeTable& e = topo.Edges();
  double sum = 0.0, sum2 = 0.0;
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const double length = (Point(x, e.Vertices[2 * k]) - Point(x, e.Vertices[2 * k + 1])).norm();
    sum += length;
    sum2 += length * length;
  }
  const double count = std::max<double>(1.0, static_cast<double>(e.NumberOfEdges()));
  const double mean = sum / count;
  q.EdgeLengthVariation = mean > 0.0 ? std::sqrt(std::max(0.0, sum2 / count - mean * mean)) / mean : 0.0;
  return q;
}

namespace
{

/// Per triangle, the corner of its angle above MostCapAngle (a cap), or -1.
std::vector<Index> CapCorners(const MeshTopology& topo, const double* x)
{
  const IndexArray& tri = topo.TriangleList();
  const double capCosine = std::cos(MostCapAngle * M_PI / 180.0);
  std::vector<Index> caps(tri.size() / 3, -1);
  for (std::size_t t = 0; t < caps.size(); ++t)
  {
    const Index* v = &tri[3 * t];
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 a = Point(x, v[(k + 1) % 3]) - Point(x, v[k]), b = Point(x, v[(k + 2) % 3]) - Point(x, v[k]);
      if (a.dot(b) < capCosine * a.norm() * b.norm())
      {
        caps[t] = static_cast<Index>(3 * t) + k;
      }
    }
  }
  return caps;
}

/// Per triangle, the unit normal of its side of the surface: its own, or
/// for a cap (whose normal turns with the slightest move of its middle
/// corner) that of the triangle across its long edge, the next across if
/// that is a cap too (CapHops at most; NaN where none is found or the
/// triangle has no area).
std::vector<Vec3> SideNormals(const MeshTopology& topo, const double* x)
{
  constexpr int CapHops = 4;
  const IndexArray& tri = topo.TriangleList();
  const MeshTopology::EdgeTable& e = topo.Edges();
  const std::vector<Index> caps = CapCorners(topo, x);
  std::vector<Vec3> normals(caps.size());
  for (std::size_t t = 0; t < caps.size(); ++t)
  {
    Index at = static_cast<Index>(t);
    for (int hop = 0; hop < CapHops && at >= 0 && caps[at] >= 0; ++hop)
    {
      const Index c = caps[at], first = c - c % 3;
      const std::int64_t k = e.Find(tri[first + (c + 1) % 3], tri[first + (c + 2) % 3]);
      const Index across = k < 0 || e.FaceCount[k] != 2 ? -1
        : (e.OppositeCorners[2 * k] == c ? e.OppositeCorners[2 * k + 1] : e.OppositeCorners[2 * k]);
      at = across >= 0 ? across / 3 : -1;
    }
    const Index* v = at >= 0 ? &tri[3 * static_cast<std::size_t>(at)] : nullptr;
    normals[t] = v && caps[at] < 0 ? (Point(x, v[1]) - Point(x, v[0])).cross(Point(x, v[2]) - Point(x, v[0])).normalized()
                                   : Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return normals;
}

/// The cosine of every edge's dihedral angle between the side normals of
/// its two triangles (SideNormals); NaN at a boundary or non-manifold edge,
/// an edge of a degenerate triangle, and the edges of a triangle turned over
/// against two of its neighbours or more (a fold of the input: normals
/// within MostFoldAngle of opposite), which has no normal to speak of
/// either: mech-holes-shark's two inverted triangles made a knot of short
/// sharp lines, and triangles of 0.6 degrees along them.
std::vector<double> DihedralCosines(const MeshTopology& topo, const double* x)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  const std::vector<Vec3> normals = SideNormals(topo, x);
  std::vector<double> dihedral(e.NumberOfEdges(), std::numeric_limits<double>::quiet_NaN());
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const Index c0 = e.OppositeCorners[2 * k], c1 = e.OppositeCorners[2 * k + 1];
    if (e.FaceCount[k] == 2 && c0 >= 0 && c1 >= 0)
    {
      dihedral[k] = normals[c0 / 3].dot(normals[c1 / 3]);
    }
  }
  const double foldCosine = std::cos(MostFoldAngle * M_PI / 180.0);
  std::vector<std::uint8_t> folds(topo.TriangleList().size() / 3, 0);
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    if (dihedral[k] < foldCosine)
    {
      ++folds[e.OppositeCorners[2 * k] / 3];
      ++folds[e.OppositeCorners[2 * k + 1] / 3];
    }
  }
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const bool folded = !std::isnan(dihedral[k]) &&
      (folds[e.OppositeCorners[2 * k] / 3] >= 2 || folds[e.OppositeCorners[2 * k + 1] / 3] >= 2);
    if (folded)
    {
      dihedral[k] = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return dihedral;
}

} // namespace

std::vector<std::uint8_t> SharpEdges(const MeshTopology& topo, const double* x, double angleDegrees)
{
  const double cosine = std::cos(angleDegrees * M_PI / 180.0);
  const std::vector<double> dihedral = DihedralCosines(topo, x);
  std::vector<std::uint8_t> sharp(dihedral.size(), 0);
  for (std::size_t k = 0; k < dihedral.size(); ++k)
  {
    sharp[k] = dihedral[k] < cosine; // (false for NaN)
  }
  return sharp;
}

namespace
{

/// The end of edge k of `e` other than v.
Index OtherEnd(const MeshTopology::EdgeTable& e, std::int64_t k, Index v)
{
  return e.Vertices[2 * k] == v ? e.Vertices[2 * k + 1] : e.Vertices[2 * k];
}

/// The number of feature edges (`features`, 1 per edge) at each vertex.
std::vector<int> FeatureDegrees(const MeshTopology& topo, const std::vector<std::uint8_t>& features)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  std::vector<int> degree(static_cast<std::size_t>(topo.NumberOfVertices()), 0);
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    degree[e.Vertices[2 * k]] += features[k];
    degree[e.Vertices[2 * k + 1]] += features[k];
  }
  return degree;
}

/// The path from `end` along the sharpest edge (dihedral cosine below
/// `weak`, not a feature) at each vertex, never back to a vertex of the path,
/// up to `longestGap` long, to the first vertex with a feature edge (the
/// path's edges and that vertex; none and -1 where none is reached).
std::pair<std::vector<std::int64_t>, Index> GapPath(const MeshTopology& topo, const double* x,
  const std::vector<double>& dihedral, double weak, double longestGap, const std::vector<std::uint8_t>& features,
  const std::vector<int>& degree, Index end)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  std::vector<std::int64_t> path;
  std::vector<Index> visited{ end };
  double length = 0.0;
  for (Index v = end; length <= longestGap;)
  {
    std::int64_t best = -1;
    for (std::int64_t i = e.NeighborOffsets[v]; i < e.NeighborOffsets[v + 1]; ++i)
    {
      const std::int64_t k = e.NeighborEdges[i];
      const Index w = OtherEnd(e, k, v);
      if (!features[k] && dihedral[k] < weak && (best < 0 || dihedral[k] < dihedral[best]) &&
        std::find(visited.begin(), visited.end(), w) == visited.end())
      {
        best = k;
      }
    }
    if (best < 0)
    {
      break;
    }
    const Index w = OtherEnd(e, best, v);
    length += (Point(x, w) - Point(x, v)).norm();
    path.push_back(best);
    visited.push_back(w);
    v = w;
    if (degree[v] > 0)
    {
      return length <= longestGap ? std::make_pair(path, v) : std::make_pair(std::vector<std::int64_t>(), Index(-1));
    }
  }
  return { {}, -1 };
}

} // namespace

std::int64_t BridgeFeatureGaps(const MeshTopology& topo, const double* x, double weakAngleDegrees, double longestGap,
  std::vector<std::uint8_t>& features)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  const Index n = topo.NumberOfVertices();
  const double weak = std::cos(weakAngleDegrees * M_PI / 180.0);
  const std::vector<double> dihedral = DihedralCosines(topo, x);
  std::vector<int> degree(n, 0);
  std::vector<Index> chain(n); // (union-find: the feature lines' vertices)
  std::iota(chain.begin(), chain.end(), Index(0));
  const auto add = [&](std::int64_t k) {
    features[k] = 1;
    ++degree[e.Vertices[2 * k]];
    ++degree[e.Vertices[2 * k + 1]];
    chain[FindRoot(chain, e.Vertices[2 * k])] = FindRoot(chain, e.Vertices[2 * k + 1]);
  };
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    if (features[k])
    {
      add(k);
    }
  }
  std::int64_t added = 0;
  for (Index end = 0; end < n && longestGap > 0.0; ++end)
  {
    if (degree[end] != 1)
    {
      continue;
    }
    const auto [path, reached] = GapPath(topo, x, dihedral, weak, longestGap, features, degree, end);
    // Only to the end of another line: a path to the middle of a line makes
    // a junction (a corner of the remesh's lines) of what are often two rows
    // of a crease's fragments side by side, and one back to its own line a
    // loop.
    if (reached >= 0 && degree[reached] == 1 && FindRoot(chain, reached) != FindRoot(chain, end))
    {
      std::for_each(path.begin(), path.end(), add);
      added += static_cast<std::int64_t>(path.size());
    }
  }
  return added;
}

std::int64_t ExtendFeatureEnds(const MeshTopology& topo, const double* x, double weakAngleDegrees,
  double mostTurnDegrees, std::vector<std::uint8_t>& features)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  const Index n = topo.NumberOfVertices();
  const double weak = std::cos(weakAngleDegrees * M_PI / 180.0);
  const double straight = std::cos(mostTurnDegrees * M_PI / 180.0);
  const std::vector<double> dihedral = DihedralCosines(topo, x);
  std::vector<int> degree = FeatureDegrees(topo, features);
  std::int64_t added = 0;
  std::vector<Index> ends;
  for (Index v = 0; v < n; ++v)
  {
    if (degree[v] == 1)
    {
      ends.push_back(v);
    }
  }
  for (Index v : ends)
  {
    std::int64_t last = -1; // the line's edge at v
    for (std::int64_t i = e.NeighborOffsets[v]; i < e.NeighborOffsets[v + 1]; ++i)
    {
      last = features[e.NeighborEdges[i]] ? e.NeighborEdges[i] : last;
    }
    while (degree[v] == 1 && last >= 0)
    {
      const Vec3 along = (Point(x, v) - Point(x, OtherEnd(e, last, v))).normalized();
      std::int64_t best = -1;
      for (std::int64_t i = e.NeighborOffsets[v]; i < e.NeighborOffsets[v + 1]; ++i)
      {
        const std::int64_t k = e.NeighborEdges[i];
        const Index w = OtherEnd(e, k, v);
        if (!features[k] && dihedral[k] < weak && degree[w] == 0 &&
          (Point(x, w) - Point(x, v)).normalized().dot(along) >= straight &&
          (best < 0 || dihedral[k] < dihedral[best]))
        {
          best = k;
        }
      }
      if (best < 0)
      {
        break;
      }
      features[best] = 1;
      ++degree[v];
      ++degree[OtherEnd(e, best, v)];
      ++added;
      v = OtherEnd(e, best, v);
      last = best;
    }
  }
  return added;
}

std::int64_t DropShortFeatureChains(
  const MeshTopology& topo, const double* x, double minimumLength, std::vector<std::uint8_t>& features)
{
  const MeshTopology::EdgeTable& e = topo.Edges();
  const Index n = topo.NumberOfVertices();
  std::vector<int> degree = FeatureDegrees(topo, features);
  // The feature edge at v other than `except` (-1: none).
  const auto nextEdge = [&](Index v, std::int64_t except) {
    for (std::int64_t k = e.NeighborOffsets[v]; k < e.NeighborOffsets[v + 1]; ++k)
    {
      if (features[e.NeighborEdges[k]] && e.NeighborEdges[k] != except)
      {
        return e.NeighborEdges[k];
      }
    }
    return std::int64_t(-1);
  };
  std::int64_t dropped = 0;
  std::vector<std::int64_t> chain, drop;
  for (bool again = minimumLength > 0.0; again;)
  {
    drop.clear();
    for (Index end = 0; end < n; ++end)
    {
      if (degree[end] != 1)
      {
        continue;
      }
      chain.clear();
      double length = 0.0;
      Index v = end;
      for (std::int64_t k = nextEdge(v, -1); k >= 0 && length < minimumLength; k = degree[v] == 2 ? nextEdge(v, k) : -1)
      {
        chain.push_back(k);
        const Index w = OtherEnd(e, k, v);
        length += (Point(x, w) - Point(x, v)).norm();
        v = w;
      }
      if (length < minimumLength)
      {
        drop.insert(drop.end(), chain.begin(), chain.end());
      }
    }
    std::sort(drop.begin(), drop.end());
    drop.erase(std::unique(drop.begin(), drop.end()), drop.end());
    for (const std::int64_t k : drop)
    {
      features[k] = 0;
      --degree[e.Vertices[2 * k]];
      --degree[e.Vertices[2 * k + 1]];
    }
    dropped += static_cast<std::int64_t>(drop.size());
    again = !drop.empty();
  }
  return dropped;
}

double EnclosedVolume(const MeshTopology& topo, const double* points, int numThreads)
{
  return VolumeAndCentroid(topo, points, numThreads, nullptr);
}

double SurfaceArea(const MeshTopology& topo, const double* points, int numThreads)
{
  return AreaAndCentroid(topo, points, numThreads, nullptr);
}

double VolumeAbovePlane(const MeshTopology& topo, const double* points, const double origin[3],
  const double normal[3], int numThreads)
{
  Vec3 nn(normal[0], normal[1], normal[2]);
  nn.normalize();
  return HeightVolume(topo, points, Vec3(origin[0], origin[1], origin[2]), nn, numThreads);
}

std::vector<Vec3> CavityPoints(const MeshTopology& topology, const double* points)
{
  struct Component
  {
    double Volume = 0.0, Largest = -1.0;
    Index Triangle = -1; // the largest
  };
  const std::vector<Index> roots = topology.ComponentRoots();
  const IndexArray& tri = topology.TriangleList();
  std::map<Index, Component> components;
  const Vec3 origin = VertexCentroid(topology, points); // (for accuracy)
  double total = 0.0;
  for (Index t = 0; t < topology.NumberOfTriangles(); ++t)
  {
    const Vec3 a = Point(points, tri[3 * t]) - origin, b = Point(points, tri[3 * t + 1]) - origin,
               c = Point(points, tri[3 * t + 2]) - origin;
    Component& component = components[roots[tri[3 * t]]];
    const double volume = a.dot(b.cross(c)) / 6.0, twice = (b - a).cross(c - a).norm();
    component.Volume += volume;
    total += volume;
    if (twice > component.Largest)
    {
      component.Largest = twice;
      component.Triangle = t;
    }
  }
  std::vector<Vec3> cavities;
  if (components.size() < 2 || !(std::abs(total) > 0.0) || !std::isfinite(total))
  {
    return cavities;
  }
  std::unique_ptr<TriangleTree> tree; // (built for the first cavity)
  for (const auto& [root, component] : components)
  {
    if (!(component.Volume * total < 0.0) || component.Triangle < 0)
    {
      continue;
    }
    if (!tree)
    {
      tree = std::make_unique<TriangleTree>(points, tri.data(), tri.size() / 3);
    }
    const Index t = component.Triangle;
    const Vec3 a = Point(points, tri[3 * t]), b = Point(points, tri[3 * t + 1]), c = Point(points, tri[3 * t + 2]);
    const Vec3 normal = (total > 0.0 ? 1.0 : -1.0) * (b - a).cross(c - a).normalized();
    const Vec3 middle = (a + b + c) / 3.0;
    double reach = std::max({ (b - a).norm(), (c - b).norm(), (a - c).norm() });
    for (int halving = 0; halving < 64 && tree->Blocks(middle, reach * normal, 0.0, [t](Index u) { return u == t; });
         ++halving)
    {
      reach *= 0.5;
    }
    cavities.push_back(middle + 0.5 * reach * normal);
  }
  return cavities;
}

std::string CoordinateRangeProblem(const MeshTopology& topology, const double* points)
{
  constexpr double largest = 1e75, smallest = 1e-75;
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    if (topology.Valence(v) == 0)
    {
      continue;
    }
    const Vec3 p = Point(points, v);
    if (!p.allFinite())
    {
      return "The surface has NaN or infinite point coordinates (point " + std::to_string(v) + ")";
    }
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (!(lo[0] <= hi[0]))
  {
    return {};
  }
  const double magnitude = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  const double extent = (hi - lo).maxCoeff();
  if (extent == 0.0)
  {
    return "The surface's points all coincide";
  }
  if (magnitude > largest || extent < smallest)
  {
    char text[200];
    std::snprintf(text, sizeof text,
      "The surface's coordinates reach %.3g with a bounding box of %.3g: beyond 1e%d (or a box below 1e-%d) the "
      "products of coordinates that areas and angles need overflow; scale the input (vtkTransformFilter)",
      magnitude, extent, 75, 75);
    return text;
  }
  return {};
}

} // namespace beltrami
