#include "Remeshing/Remesh.h"

#include "Maps/GeometryImages.h"
#include "Remeshing/ConstrainedDelaunay.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace beltrami
{

namespace
{

/// One chart's share of the triangulation: its triangles in sample ids, and
/// interior samples it had to move inside (sample, new triangle, weights).
struct ChartTriangles
{
  std::string Error;
  std::vector<Index> Triangles;
  std::vector<double> UV; ///< 2 per triangle corner
  struct Moved
  {
    Index Sample, Triangle;
    double Weights[3];
  };
  std::vector<Moved> Moves;
};

/// The chart's points (its boundary paths' samples, then its interior
/// samples) with their positions in the chart and the path segments.
struct ChartPoints
{
  std::vector<Index> Sample;
  std::vector<double> UV;
  std::vector<Index> Segments;
};

ChartPoints GatherChart(const MeshTopology& topology, const AtlasChart& chart, const SurfaceSamples& samples,
  const std::vector<int>& paths, const std::vector<Index>& interior, std::string& error)
{
  ChartPoints out;
  std::unordered_map<Index, Index> local;
  const auto add = [&](Index s) {
    const auto [at, added] = local.emplace(s, static_cast<Index>(out.Sample.size()));
    if (added)
    {
      double uv[2] = { 0.0, 0.0 };
      if (!ChartPosition(topology, chart, samples.Triangle[s], &samples.Barycentric[3 * s], uv))
      {
        error = "a sample of a chart's boundary is not in the chart";
      }
      out.Sample.push_back(s);
      out.UV.insert(out.UV.end(), uv, uv + 2);
    }
    return at->second;
  };
  for (int p : paths)
  {
    const std::vector<Index>& ids = samples.Paths[p].Samples;
    for (std::size_t i = 0; i + 1 < ids.size(); ++i)
    {
      out.Segments.push_back(add(ids[i]));
      out.Segments.push_back(add(ids[i + 1]));
    }
  }
  for (Index s : interior)
  {
    add(s);
  }
  return out;
}

/// Moves each unused interior point to the centroid of the kept triangle
/// whose centroid is nearest (strictly inside the domain), one point per
/// triangle (two tips cut off by one chord went to one place); false if a
/// boundary point is unused (the domain is broken).
bool MoveInside(const DomainTriangulation& cdt, std::size_t firstInterior, ChartPoints& points)
{
  std::vector<std::uint8_t> taken(cdt.Triangles.size() / 3, 0);
  for (Index u : cdt.Unused)
  {
    if (static_cast<std::size_t>(u) < firstInterior || cdt.Triangles.empty())
    {
      return false;
    }
    double best = HUGE_VAL, target[2] = { 0.0, 0.0 };
    std::size_t nearest = taken.size();
    for (std::size_t t = 0; t < cdt.Triangles.size(); t += 3)
    {
      if (taken[t / 3])
      {
        continue;
      }
      double c[2] = { 0.0, 0.0 };
      for (int k = 0; k < 3; ++k)
      {
        c[0] += points.UV[2 * cdt.Triangles[t + k]] / 3.0;
        c[1] += points.UV[2 * cdt.Triangles[t + k] + 1] / 3.0;
      }
      const double d = std::hypot(c[0] - points.UV[2 * u], c[1] - points.UV[2 * u + 1]);
      if (d < best)
      {
        best = d;
        nearest = t / 3;
        target[0] = c[0];
        target[1] = c[1];
      }
    }
    if (nearest == taken.size())
    {
      return false;
    }
    taken[nearest] = 1;
    points.UV[2 * u] = target[0];
    points.UV[2 * u + 1] = target[1];
  }
  return true;
}

/// Twice the signed area of the triangle (a, b, c) of the points' UV.
double Cross2(const std::vector<double>& uv, Index a, Index b, Index c)
{
  return beltrami::Cross2(&uv[2 * a], &uv[2 * b], &uv[2 * c]);
}

/// Flips away the ears of the triangulation: triangles of three consecutive
/// boundary samples (two of their edges on the boundary).  The chart on the
/// other side of the boundary can have the same ear where the path turns
/// the same way in both planes (across a corner of both squares): two
/// triangles with the same three vertices.  Each ear's inner edge is
/// swapped where the quadrilateral is convex.
/// The key of the undirected edge a-b.
std::uint64_t EdgeKey(Index a, Index b)
{
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

void FlipEars(const ChartPoints& points, std::vector<Index>& triangles)
{
  std::unordered_map<std::uint64_t, std::uint8_t> constrained;
  for (std::size_t s = 0; s + 1 < points.Segments.size(); s += 2)
  {
    constrained[EdgeKey(points.Segments[s], points.Segments[s + 1])] = 1;
  }
  std::unordered_map<std::uint64_t, std::size_t> triangleOfEdge; // directed edge a -> b: its triangle
  const auto directed = [](Index a, Index b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b); };
  for (std::size_t t = 0; t < triangles.size(); t += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      triangleOfEdge[directed(triangles[t + k], triangles[t + (k + 1) % 3])] = t;
    }
  }
  for (std::size_t t = 0; t < triangles.size(); t += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      // Ear at corner k: its two edges there constrained, the opposite one not.
      const Index m = triangles[t + k], a = triangles[t + (k + 1) % 3], b = triangles[t + (k + 2) % 3];
      if (!constrained.count(EdgeKey(m, a)) || !constrained.count(EdgeKey(b, m)) || constrained.count(EdgeKey(a, b)))
      {
        continue;
      }
      const auto across = triangleOfEdge.find(directed(b, a));
      if (across == triangleOfEdge.end())
      {
        continue;
      }
      const std::size_t u = across->second;
      Index x = triangles[u];
      for (int j = 0; j < 3; ++j)
      {
        x = triangles[u + j] != a && triangles[u + j] != b ? triangles[u + j] : x;
      }
      if (Cross2(points.UV, m, a, x) > 0.0 && Cross2(points.UV, m, x, b) > 0.0)
      {
        // (m, a, b) + (b, a, x) -> (m, a, x) + (m, x, b)
        triangles[t] = m, triangles[t + 1] = a, triangles[t + 2] = x;
        triangles[u] = m, triangles[u + 1] = x, triangles[u + 2] = b;
        for (std::size_t f : { t, u })
        {
          for (int j = 0; j < 3; ++j)
          {
            triangleOfEdge[directed(triangles[f + j], triangles[f + (j + 1) % 3])] = f;
          }
        }
        break;
      }
    }
  }
}

/// The triangles of the joined charts, their chart and their corners' UV.
struct JoinedTriangles
{
  IndexArray Triangles;          ///< 3 per face
  std::vector<int> FaceChart;    ///< per face
  std::vector<double> CornerUV;  ///< 2 per corner
};

/// Pairs of faces with the same three vertices (only pairs: three or more
/// are left), and the faces at each of their vertices.
std::vector<std::array<std::size_t, 2>> DuplicateFaces(const IndexArray& triangles,
  std::unordered_map<Index, std::vector<std::size_t>>& facesAt)
{
  const std::size_t faces = triangles.size() / 3;
  std::vector<std::pair<std::array<Index, 3>, std::size_t>> sorted(faces);
  for (std::size_t f = 0; f < faces; ++f)
  {
    std::array<Index, 3> k = { triangles[3 * f], triangles[3 * f + 1], triangles[3 * f + 2] };
    std::sort(k.begin(), k.end());
    sorted[f] = { k, f };
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::array<std::size_t, 2>> pairs;
  for (std::size_t i = 0; i + 1 < faces; ++i)
  {
    if (sorted[i].first == sorted[i + 1].first && (i + 2 == faces || sorted[i + 2].first != sorted[i].first) &&
      (i == 0 || sorted[i - 1].first != sorted[i].first))
    {
      pairs.push_back({ sorted[i].second, sorted[i + 1].second });
      for (Index v : sorted[i].first)
      {
        facesAt[v];
      }
    }
  }
  for (std::size_t f = 0; !pairs.empty() && f < faces; ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      const auto at = facesAt.find(triangles[3 * f + k]);
      if (at != facesAt.end())
      {
        at->second.push_back(f);
      }
    }
  }
  return pairs;
}

/// Face `f` = (p, q, x), p -> q being the edge a-b, becomes (p, m, x) and
/// face `g` becomes (m, q, x) in f's chart, m at `mUV` there.
void SplitAt(JoinedTriangles& j, std::size_t f, std::size_t g, Index m, const double* mUV, Index a, Index b)
{
  int k = 0;
  while (j.Triangles[3 * f + (k + 2) % 3] == a || j.Triangles[3 * f + (k + 2) % 3] == b)
  {
    ++k; // k: the corner p, (k + 2) % 3 the corner x
  }
  Index corner[3];
  double uv[3][2];
  for (int i = 0; i < 3; ++i)
  {
    corner[i] = j.Triangles[3 * f + (k + i) % 3];
    uv[i][0] = j.CornerUV[2 * (3 * f + (k + i) % 3)];
    uv[i][1] = j.CornerUV[2 * (3 * f + (k + i) % 3) + 1];
  }
  const Index first[3] = { corner[0], m, corner[2] }, second[3] = { m, corner[1], corner[2] };
  const double* firstUV[3] = { uv[0], mUV, uv[2] };
  const double* secondUV[3] = { mUV, uv[1], uv[2] };
  for (int i = 0; i < 3; ++i)
  {
    j.Triangles[3 * f + i] = first[i];
    j.Triangles[3 * g + i] = second[i];
    std::copy(firstUV[i], firstUV[i] + 2, &j.CornerUV[2 * (3 * f + i)]);
    std::copy(secondUV[i], secondUV[i] + 2, &j.CornerUV[2 * (3 * g + i)]);
  }
  j.FaceChart[g] = j.FaceChart[f];
}

/// Faces in the order of their smallest vertex id (stable): a vertex's
/// fan then lies in a few cache lines, as its neighbours' fans do.
void SortFacesByVertex(JoinedTriangles& joined, Index numberOfVertices)
{
  const std::size_t faces = joined.FaceChart.size();
  std::vector<std::int64_t> start(static_cast<std::size_t>(numberOfVertices) + 1, 0);
  const auto key = [&](std::size_t f) {
    return std::min({ joined.Triangles[3 * f], joined.Triangles[3 * f + 1], joined.Triangles[3 * f + 2] });
  };
  for (std::size_t f = 0; f < faces; ++f)
  {
    ++start[key(f) + 1];
  }
  for (Index v = 0; v < numberOfVertices; ++v)
  {
    start[v + 1] += start[v];
  }
  JoinedTriangles sorted;
  sorted.Triangles.resize(joined.Triangles.size());
  sorted.FaceChart.resize(faces);
  sorted.CornerUV.resize(joined.CornerUV.size());
  for (std::size_t f = 0; f < faces; ++f)
  {
    const std::size_t g = static_cast<std::size_t>(start[key(f)]++);
    std::copy_n(&joined.Triangles[3 * f], 3, &sorted.Triangles[3 * g]);
    std::copy_n(&joined.CornerUV[6 * f], 6, &sorted.CornerUV[6 * g]);
    sorted.FaceChart[g] = joined.FaceChart[f];
  }
  joined = std::move(sorted);
}

/// Splits one double ear (see SplitDoubleEars); false if it is not one.
bool SplitDoubleEar(JoinedTriangles& j, const std::array<std::size_t, 2>& ears,
  std::unordered_map<Index, std::vector<std::size_t>>& facesAt)
{
  const Index* e = &j.Triangles[3 * ears[0]];
  int middle = -1; // the corner whose only faces are the two ears
  for (int k = 0; k < 3; ++k)
  {
    middle = facesAt[e[k]].size() == 2 ? (middle < 0 ? k : 3) : middle;
  }
  if (middle < 0 || middle == 3)
  {
    return false;
  }
  const Index m = e[middle], a = e[(middle + 1) % 3], b = e[(middle + 2) % 3];
  std::size_t other[2] = { 0, 0 }; // the other face on a-b in each ear's chart
  Index apex[2] = { -1, -1 };
  double mUV[2][2];
  for (int side = 0; side < 2; ++side)
  {
    for (std::size_t f : facesAt[a])
    {
      const Index* t = &j.Triangles[3 * f];
      if (f != ears[0] && f != ears[1] && (t[0] == b || t[1] == b || t[2] == b) &&
        j.FaceChart[f] == j.FaceChart[ears[side]])
      {
        other[side] = f;
        apex[side] = t[0] != a && t[0] != b ? t[0] : (t[1] != a && t[1] != b ? t[1] : t[2]);
      }
    }
    for (int k = 0; k < 3; ++k)
    {
      if (j.Triangles[3 * ears[side] + k] == m)
      {
        std::copy_n(&j.CornerUV[2 * (3 * ears[side] + k)], 2, mUV[side]);
      }
    }
  }
  if (apex[0] < 0 || apex[1] < 0 || apex[0] == apex[1])
  {
    return false;
  }
  for (int side = 0; side < 2; ++side)
  {
    SplitAt(j, other[side], ears[side], m, mUV[side], a, b);
  }
  return true;
}

/// Triangles of two charts with the same three vertices: ears that FlipEars
/// could not flip (their quadrilateral not convex in the plane) made on both
/// sides of a seam by three consecutive samples a, m, b, m's only triangles.
/// Each such pair is replaced by m inserted into the edge a-b: the other
/// triangle on a-b in each chart is split at m (the triangle count stays,
/// and the mesh is manifold).  The split triangles may be inverted in their
/// chart's plane; the chart rounds of the optimisation then leave them (no
/// move or swap passes its test there) and the stitching rounds, on the
/// surface, repair them.  Pairs whose two other triangles share their third
/// vertex are left (the join then reports the non-manifold mesh).
void SplitDoubleEars(JoinedTriangles& joined)
{
  std::unordered_map<Index, std::vector<std::size_t>> facesAt;
  for (const std::array<std::size_t, 2>& ears : DuplicateFaces(joined.Triangles, facesAt))
  {
    SplitDoubleEar(joined, ears, facesAt);
  }
}

/// Two boundary samples that two charts both join by a diagonal: a limb
/// thinner than the spacing whose two seams between the same two charts
/// have a sample each at its cross-section, which both charts' triangulations
/// join, pinching the limb to an edge of four triangles.  The diagonal is
/// flipped in one of the two charts (its quadrilateral convex in that
/// chart's plane, the new edge not in the mesh yet): the edge keeps two
/// triangles, the limb its cross-section.  Where neither chart's is convex
/// (a needle whose seam runs up one side and down the other: each chart
/// fans the same two samples), the first chart's is flipped anyway; its
/// triangles may be inverted in its plane, and the stitching rounds, on the
/// surface, repair them (as after SplitDoubleEars).  Likewise where one
/// chart's diagonal joins two samples that another chart's boundary chord
/// joins (three triangles on the edge: a rim's chord in one chart, a
/// diagonal cutting off a thin corner of its neighbour).
using FacesOnEdges = std::unordered_map<std::uint64_t, std::vector<std::size_t>>;

/// Flips the diagonal a-b of face `first`'s chart (FlipSharedDiagonals):
/// false where that chart has one face on it only, where the new edge is
/// in the mesh already, or (`convex`) where the quadrilateral is not convex
/// in the chart's plane.
bool FlipDiagonal(JoinedTriangles& j, FacesOnEdges& facesOn, Index a, Index b, const std::vector<std::size_t>& on,
  std::size_t first, bool convex)
{
  const std::size_t faces = j.Triangles.size() / 3;
  const auto uv = [&j](std::size_t f, int k) { return Vec2(j.CornerUV[2 * (3 * f + k)], j.CornerUV[2 * (3 * f + k) + 1]); };
  const auto cross = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
  };
  // The other face of `first`'s chart on a-b: the two sides of its diagonal.
  std::size_t second = faces;
  for (const std::size_t f : on)
  {
    second = f != first && j.FaceChart[f] == j.FaceChart[first] ? f : second;
  }
  if (second == faces || second < first)
  {
    return false;
  }
  // Corners: p, q, r of each face with p, q the edge's ends in the face's order.
  int ka = 0, kb = 0;
  for (int k = 0; k < 3; ++k)
  {
    ka = j.Triangles[3 * first + k] == a ? k : ka;
    kb = j.Triangles[3 * second + k] == a ? k : kb;
  }
  // Orient so that `first` runs p -> q -> x and `second` q -> p -> y.
  const int k1 = j.Triangles[3 * first + (ka + 1) % 3] == b ? ka : (ka + 2) % 3;
  const int k2 = (k1 == ka) ? (kb + 2) % 3 : kb;
  const Index p = j.Triangles[3 * first + k1], q = j.Triangles[3 * first + (k1 + 1) % 3];
  const Index x = j.Triangles[3 * first + (k1 + 2) % 3];
  const Index y = j.Triangles[3 * second + (k2 + 2) % 3];
  if (j.Triangles[3 * second + k2] != q || j.Triangles[3 * second + (k2 + 1) % 3] != p || x == y ||
    facesOn.count(EdgeKey(x, y)))
  {
    return false;
  }
  const Vec2 up = uv(first, k1), uq = uv(first, (k1 + 1) % 3), ux = uv(first, (k1 + 2) % 3);
  const Vec2 uy = uv(second, (k2 + 2) % 3);
  const double sign = cross(up, uq, ux);
  if (convex && !(cross(ux, up, uy) * sign > 0.0 && cross(uy, uq, ux) * sign > 0.0))
  {
    return false;
  }
  // (p, q, x) + (q, p, y) -> (x, p, y) + (y, q, x)
  const Index flipped[2][3] = { { x, p, y }, { y, q, x } };
  const Vec2 flippedUV[2][3] = { { ux, up, uy }, { uy, uq, ux } };
  for (int side = 0; side < 2; ++side)
  {
    const std::size_t f = side == 0 ? first : second;
    for (int k = 0; k < 3; ++k)
    {
      j.Triangles[3 * f + k] = flipped[side][k];
      j.CornerUV[2 * (3 * f + k)] = flippedUV[side][k][0];
      j.CornerUV[2 * (3 * f + k) + 1] = flippedUV[side][k][1];
    }
  }
  facesOn[EdgeKey(x, y)] = { first, second };
  return true;
}

void FlipSharedDiagonals(JoinedTriangles& j)
{
  FacesOnEdges facesOn;
  const std::size_t faces = j.Triangles.size() / 3;
  for (std::size_t f = 0; f < faces; ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      facesOn[EdgeKey(j.Triangles[3 * f + k], j.Triangles[3 * f + (k + 1) % 3])].push_back(f);
    }
  }
  std::vector<std::pair<std::uint64_t, std::vector<std::size_t>>> shared;
  for (const auto& [edge, on] : facesOn)
  {
    if (on.size() == 3 || on.size() == 4)
    {
      shared.emplace_back(edge, on);
    }
  }
  std::sort(shared.begin(), shared.end()); // (deterministic)
  for (const auto& [edge, on] : shared)
  {
    const Index a = static_cast<Index>(edge >> 32), b = static_cast<Index>(edge & 0xffffffffu);
    // One chart's diagonal flipped (a convex one first): the edge is the other's alone.
    bool flipped = false;
    for (const bool convex : { true, false })
    {
      for (std::size_t k = 0; k < on.size() && !flipped; ++k)
      {
        flipped = FlipDiagonal(j, facesOn, a, b, on, on[k], convex);
      }
    }
  }
}

ChartTriangles TriangulateChart(const MeshTopology& topology, const AtlasChart& chart, const ChartLocator& locator,
  const SurfaceSamples& samples, const std::vector<int>& paths, const std::vector<Index>& interior)
{
  ChartTriangles out;
  ChartPoints points = GatherChart(topology, chart, samples, paths, interior, out.Error);
  const std::size_t firstInterior = points.Sample.size() - interior.size();
  DomainTriangulation cdt;
  for (int attempt = 0; attempt < 3 && out.Error.empty(); ++attempt)
  {
    cdt = TriangulateDomain(points.UV, points.Segments);
    if (!cdt.Error.empty() || cdt.Unused.empty())
    {
      break;
    }
    if (!MoveInside(cdt, firstInterior, points))
    {
      out.Error = "the boundary samples of a chart do not enclose a domain";
    }
    for (Index u : cdt.Unused)
    {
      ChartTriangles::Moved moved;
      moved.Sample = points.Sample[u];
      const Index t = locator.LocateNearest(&points.UV[2 * u], moved.Weights);
      if (t < 0)
      {
        out.Error = "a sample moved inside its chart is off the chart";
        break;
      }
      moved.Triangle = chart.Triangles[t];
      out.Moves.push_back(moved);
    }
  }
  if (out.Error.empty() && !cdt.Error.empty())
  {
    out.Error = cdt.Error;
  }
  if (out.Error.empty() && !cdt.Unused.empty())
  {
    out.Error = "samples stayed outside their chart";
  }
  FlipEars(points, cdt.Triangles);
  for (Index p : cdt.Triangles)
  {
    out.Triangles.push_back(points.Sample[p]);
    out.UV.insert(out.UV.end(), { points.UV[2 * p], points.UV[2 * p + 1] });
  }
  return out;
}

} // namespace

bool ChartPosition(const MeshTopology& topology, const AtlasChart& chart, Index triangle, const double* barycentric,
  double* uv)
{
  uv[0] = uv[1] = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    if (barycentric[k] == 0.0)
    {
      continue;
    }
    const Index v = topology.CornerVertex(3 * triangle + k);
    const auto at = std::lower_bound(chart.Vertices.begin(), chart.Vertices.end(), v);
    if (at == chart.Vertices.end() || *at != v)
    {
      return false;
    }
    const std::size_t local = static_cast<std::size_t>(at - chart.Vertices.begin());
    uv[0] += barycentric[k] * chart.UV[2 * local];
    uv[1] += barycentric[k] * chart.UV[2 * local + 1];
  }
  return true;
}

Vec3 SurfacePoint(const MeshTopology& topology, const double* points, Index triangle, const double* barycentric)
{
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    x += barycentric[k] * Point(points, topology.CornerVertex(3 * triangle + k));
  }
  return x;
}

Remesh CreateRemesh(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const SurfaceSamples& samples, int numThreads, RemeshCache* cache)
{
  RemeshCache local;
  const std::vector<ChartLocator>& locators = (cache ? *cache : local).Locators(atlas);
  Remesh out;
  const Index n = static_cast<Index>(samples.Kind.size());
  const std::size_t charts = atlas.Charts.size();
  std::vector<std::vector<int>> paths(charts);
  std::vector<std::vector<Index>> interior(charts);
  out.Path.assign(n, -1);
  out.Arc.assign(n, 0.0);
  for (std::size_t p = 0; p < samples.Paths.size(); ++p)
  {
    const SamplePath& path = samples.Paths[p];
    for (int side = 0; side < 2; ++side)
    {
      if (path.Charts[side] >= 0)
      {
        paths[path.Charts[side]].push_back(static_cast<int>(p));
      }
    }
    for (std::size_t i = 1; i + 1 < path.Samples.size(); ++i)
    {
      out.Path[path.Samples[i]] = static_cast<int>(p);
      out.Arc[path.Samples[i]] = path.SampleArc[i];
    }
  }
  for (Index s = 0; s < n; ++s)
  {
    if ((samples.Kind[s] == SampleKind::Interior || samples.Kind[s] == SampleKind::Tip) && samples.Chart[s] >= 0)
    {
      interior[samples.Chart[s]].push_back(s); // (a Tip on a chart boundary is its path's)
    }
  }
  std::vector<ChartTriangles> parts(charts);
  ParallelFor(static_cast<std::int64_t>(charts), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t c = begin; c < end; ++c)
    {
      parts[c] = TriangulateChart(topology, atlas.Charts[c], locators[c], samples, paths[c], interior[c]);
    }
  }, {}, 0, 1);
  out.Triangle = samples.Triangle;
  out.Barycentric = samples.Barycentric;
  out.Kind = samples.Kind;
  JoinedTriangles joined;
  for (std::size_t c = 0; c < charts; ++c)
  {
    if (!parts[c].Error.empty())
    {
      out.Error = "chart " + std::to_string(c) + ": " + parts[c].Error;
      return out;
    }
    joined.Triangles.insert(joined.Triangles.end(), parts[c].Triangles.begin(), parts[c].Triangles.end());
    joined.FaceChart.insert(joined.FaceChart.end(), parts[c].Triangles.size() / 3, static_cast<int>(c));
    joined.CornerUV.insert(joined.CornerUV.end(), parts[c].UV.begin(), parts[c].UV.end());
    for (const ChartTriangles::Moved& moved : parts[c].Moves)
    {
      out.Triangle[moved.Sample] = moved.Triangle;
      std::copy(moved.Weights, moved.Weights + 3, &out.Barycentric[3 * moved.Sample]);
    }
  }
  SplitDoubleEars(joined);
  FlipSharedDiagonals(joined);
  SortFacesByVertex(joined, n); // neighbouring faces near in memory: the optimisation's fans
  const MeshTopology topologyOut(n, std::move(joined.Triangles));
  std::vector<double> positions(3 * static_cast<std::size_t>(n));
  for (Index s = 0; s < n; ++s)
  {
    const Vec3 x = SurfacePoint(topology, points, out.Triangle[s], &out.Barycentric[3 * s]);
    std::copy(x.data(), x.data() + 3, &positions[3 * s]);
  }
  if (topologyOut.NumberOfDroppedTriangles() > 0 ||
    !HalfEdgeMesh::FromTopology(topologyOut, positions.data(), out.Mesh, out.Error))
  {
    out.Error = "the charts' triangulations do not join into a manifold: " +
      (out.Error.empty() ? topologyOut.Describe() : out.Error);
    return out;
  }
  out.FaceChart = std::move(joined.FaceChart);
  out.CornerUV = std::move(joined.CornerUV);
  return out;
}

} // namespace beltrami
