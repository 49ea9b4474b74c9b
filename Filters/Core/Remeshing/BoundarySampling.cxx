// Beltrami core: the chart boundaries as paths of surface vertices, and
// their samples at the density's spacing (Remeshing/BoundarySampling.h).
#include "Remeshing/BoundarySampling.h"

#include "Maps/ChartPartition.h"
#include "Mesh/Geometry.h"
#include "Remeshing/BoundaryChords.h"
#include "Remeshing/ErrorDiffusion.h"
#include "Remeshing/RemeshMetric.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace beltrami
{

namespace
{

/// StretchAlong at the i-th vertex of path `vertices` (its direction
/// there: between its neighbours on the path).
double AlongPath(const double* points, const std::vector<Index>& vertices, std::size_t i, const double* metric)
{
  const std::size_t before = i > 0 ? i - 1 : i, after = i + 1 < vertices.size() ? i + 1 : i;
  return StretchAlong(metric + 6 * static_cast<std::int64_t>(vertices[i]),
    Point(points, vertices[after]) - Point(points, vertices[before]));
}

/// Whether the kept line through v (along its kept edges to a and b) turns
/// there by more than SharpTurnDegrees, with both edges at least half the
/// density's spacing long: a corner of a jagged hole's rim, whose chord
/// would cut the corner and leave slivers beside it.  (Shorter edges: the
/// line's bends are sampled by MaximumLineSag instead.)  With a metric (6
/// per surface vertex), the spacing along the line (RemeshMetric's
/// StretchAlong).
constexpr double SharpTurnDegrees = 45.0;
bool IsSharpTurn(const double* points, const double* importance, const double* metric, double density, Index a,
  Index v, Index b)
{
  const Vec3 in = Point(points, v) - Point(points, a), out = Point(points, b) - Point(points, v);
  const double* m = metric ? metric + 6 * static_cast<std::int64_t>(v) : nullptr;
  const double shortest =
    0.5 * SpacingAt(importance, density, v) / (m ? std::max(StretchAlong(m, in), StretchAlong(m, out)) : 1.0);
  return in.norm() >= shortest && out.norm() >= shortest &&
    std::atan2(in.cross(out).norm(), in.dot(out)) > SharpTurnDegrees * M_PI / 180.0;
}

/// A kept line's curvature at each of its vertices (`arc`: their arc
/// lengths) at the scale of the spacing there (`spacing`, per path
/// vertex): the angle between the chords
/// to the line's points that spacing before and after it (or to the
/// vertices before and after, where farther), over their mean length (a
/// closed loop wraps around; towards a path's ends the chords shorten, and
/// its ends count 0).  Per input edge instead, the jagged rims
/// of holes punched into a scan, which turn at every vertex, took samples
/// a twelfth of the spacing apart, with slivers beside them; a zigzag
/// smaller than the spacing departs from its chords by less than its own
/// size, which the remesh's fidelity allows.
std::vector<double> LineCurvature(const double* points, const std::vector<Index>& path,
  const std::vector<double>& arc, const std::vector<double>& spacing)
{
  const std::size_t n = path.size();
  std::vector<double> curvature(n, 0.0);
  const bool loop = path.front() == path.back();
  const double total = arc.back();
  const auto pointAt = [&](double at) { // the line's point at arc length `at`
    const auto [k, t] = EdgeAtArc(arc, loop ? at - total * std::floor(at / total) : at);
    return Vec3((1.0 - t) * Point(points, path[k]) + t * Point(points, path[k + 1]));
  };
  for (std::size_t i = 0; i < n && n > 2 && total > 0.0; ++i)
  {
    if ((i == 0 || i + 1 == n) && !loop)
    {
      continue;
    }
    // (at least to the vertices before and after: a line of edges longer
    // than the spacing turns at its vertices, as the line itself)
    const double edgeIn = i > 0 ? arc[i] - arc[i - 1] : total - arc[n - 2];
    const double edgeOut = i + 1 < n ? arc[i + 1] - arc[i] : arc[1];
    const double most = loop ? 0.5 * total : total;
    const Vec3 in = Point(points, path[i]) - pointAt(arc[i] - std::min(most, std::max(spacing[i], edgeIn)));
    const Vec3 out = pointAt(arc[i] + std::min(most, std::max(spacing[i], edgeOut))) - Point(points, path[i]);
    const double lengths = in.norm() + out.norm();
    curvature[i] = in.norm() > 0.0 && out.norm() > 0.0 ? std::atan2(in.cross(out).norm(), in.dot(out)) / (0.5 * lengths)
                                                        : 0.0;
  }
  return curvature;
}

} // namespace

BoundaryPaths ChartBoundaries(const MeshTopology& topology, const double* points, const double* importance,
  const double* metric, double density, const std::vector<int>& chartOfTriangle, const std::uint8_t* featureEdges,
  const std::uint8_t* pinned)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  std::vector<std::uint8_t> boundary = EdgesBetweenLabels(topology, chartOfTriangle);
  std::vector<int> valence(topology.NumberOfVertices(), 0), kept(topology.NumberOfVertices(), 0);
  std::vector<Index> keptEnds(2 * static_cast<std::size_t>(topology.NumberOfVertices()), -1); // first two
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    boundary[e] = boundary[e] || IsOpenEdge(edges, e);
    const int keep = boundary[e] && IsKeptEdge(edges, e, featureEdges);
    for (int k = 0; k < 2; ++k)
    {
      const Index v = edges.Vertices[2 * e + k];
      valence[v] += boundary[e];
      if (keep && kept[v] < 2)
      {
        keptEnds[2 * v + kept[v]] = edges.Vertices[2 * e + 1 - k];
      }
      kept[v] += keep;
    }
  }
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    valence[v] += valence[v] == 2 && kept[v] == 1; // a kept line's end inside a path: a corner
    valence[v] += valence[v] == 2 && ((pinned && pinned[v]) ||
      (kept[v] == 2 &&
        IsSharpTurn(points, importance, metric, density, keptEnds[2 * v], v, keptEnds[2 * v + 1])));
  }
  BoundaryPaths result;
  std::vector<std::uint8_t> done(boundary.size(), 0);
  // Follows the boundary from `start` along edge `first` to the next corner.
  const auto walk = [&](Index start, std::int64_t first) {
    std::vector<Index> path = { start };
    for (std::int64_t e = first; e >= 0;)
    {
      done[e] = 1;
      const Index next = edges.Vertices[2 * e] == path.back() ? edges.Vertices[2 * e + 1] : edges.Vertices[2 * e];
      path.push_back(next);
      e = -1;
      if (valence[next] == 2 && next != start)
      {
        for (std::int64_t k = edges.NeighborOffsets[next]; k < edges.NeighborOffsets[next + 1]; ++k)
        {
          const std::int64_t f = edges.NeighborEdges[k];
          e = boundary[f] && !done[f] ? f : e;
        }
      }
    }
    result.Paths.push_back(std::move(path));
  };
  const auto walkAll = [&](Index v) {
    for (std::int64_t k = edges.NeighborOffsets[v]; k < edges.NeighborOffsets[v + 1]; ++k)
    {
      if (boundary[edges.NeighborEdges[k]] && !done[edges.NeighborEdges[k]])
      {
        walk(v, edges.NeighborEdges[k]);
      }
    }
  };
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    if (valence[v] > 0 && valence[v] != 2)
    {
      result.Corners.push_back(v);
      walkAll(v);
    }
  }
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    if (boundary[e] && !done[e]) // a loop without corners
    {
      result.Corners.push_back(edges.Vertices[2 * e]);
      walk(edges.Vertices[2 * e], e);
    }
  }
  return result;
}

Index EdgePoint(const MeshTopology& topology, Index a, Index b, double t, double* w)
{
  Index triangle = topology.CornersBegin(a)[0] / 3;
  if (b != a)
  {
    const MeshTopology::EdgeTable& edges = topology.Edges();
    const std::int64_t e = edges.Find(a, b);
    triangle = (edges.OppositeCorners[2 * e] >= 0 ? edges.OppositeCorners[2 * e] : edges.OppositeCorners[2 * e + 1]) / 3;
  }
  for (int k = 0; k < 3; ++k)
  {
    const Index v = topology.CornerVertex(3 * triangle + k);
    w[k] = v == a ? 1.0 - t : (v == b && b != a ? t : 0.0);
  }
  return triangle;
}

void SampleBoundaries(const MeshTopology& topology, const double* points, const double* importance,
  const std::vector<int>& chartOfTriangle, const BoundaryPaths& boundaries, double density,
  const std::uint8_t* featureEdges, double maxSag, const double* metric, SurfaceSamples& out, double seamSpacing)
{
  const auto lambda = [&](Index v) { return std::sqrt(density * (importance ? std::max(0.0, importance[v]) : 1.0)); };
  std::vector<Index> cornerSample(topology.NumberOfVertices(), -1);
  for (Index c : boundaries.Corners)
  {
    double w[3];
    cornerSample[c] = static_cast<Index>(out.Kind.size());
    AddSample(topology, points, EdgePoint(topology, c, c, 0.0, w), w, SampleKind::Corner, -1, out);
  }
  // Two paths between the same two corners (around a limb thinner than the
  // spacing) would both be the one segment between them: each gets at
  // least one sample between its ends, or the charts on both sides meet
  // along a doubled edge.
  std::map<std::pair<Index, Index>, int> parallel;
  for (const std::vector<Index>& vertices : boundaries.Paths)
  {
    ++parallel[std::minmax(vertices.front(), vertices.back())];
  }
  for (const std::vector<Index>& vertices : boundaries.Paths)
  {
    SamplePath path;
    path.Vertices = vertices;
    const MeshTopology::EdgeTable& edges = topology.Edges();
    const std::int64_t first = edges.Find(vertices[0], vertices[1]);
    for (int side = 0, k = 0; side < 2; ++side)
    {
      const Index corner = edges.OppositeCorners[2 * first + side];
      path.Charts[k] = corner >= 0 ? chartOfTriangle[corner / 3] : path.Charts[k];
      k += corner >= 0;
    }
    path.Arc.assign(vertices.size(), 0.0);
    const bool kept = IsKeptEdge(edges, first, featureEdges);
    std::vector<double> spacing(vertices.size()), edge(vertices.size(), 0.0); // edge i: from vertex i - 1
    std::vector<double> lambdas(vertices.size()); // samples per length at each vertex
    for (std::size_t i = 0; i < vertices.size(); ++i)
    {
      edge[i] = i > 0 ? (Point(points, vertices[i]) - Point(points, vertices[i - 1])).norm() : 0.0;
      path.Arc[i] = i > 0 ? path.Arc[i - 1] + edge[i] : 0.0;
      lambdas[i] =
        lambda(vertices[i]) * (metric ? AlongPath(points, vertices, i, metric) : 1.0) / (kept ? 1.0 : seamSpacing);
      spacing[i] = 1.0 / std::max(1e-300, lambdas[i]);
    }
    const std::vector<double> curvature = maxSag > 0.0 && kept
      ? LineCurvature(points, vertices, path.Arc, spacing)
      : std::vector<double>(vertices.size(), 0.0);
    const auto along = [&](std::size_t i) {
      const double l = lambdas[i];
      return std::max(l, std::sqrt(curvature[i] * l / (8.0 * maxSag)));
    };
    for (std::size_t i = 0; i < vertices.size(); ++i)
    {
      if (along(i) > lambdas[i])
      {
        path.Refinement.resize(vertices.size(), 1.0);
        path.Refinement[i] = along(i) / lambdas[i];
      }
    }
    std::vector<double> cumulative(vertices.size(), 0.0);
    for (std::size_t i = 1; i < vertices.size(); ++i)
    {
      cumulative[i] = cumulative[i - 1] + 0.5 * (along(i) + along(i - 1)) * edge[i];
    }
    const double total = cumulative.back();
    const bool loop = vertices.front() == vertices.back();
    const std::int64_t fewest = loop ? 2 : (parallel[std::minmax(vertices.front(), vertices.back())] > 1 ? 1 : 0);
    const std::int64_t inside = std::max<std::int64_t>(fewest, std::llround(total) - 1);
    path.Samples.push_back(cornerSample[vertices.front()]);
    path.SampleArc.push_back(0.0);
    std::size_t node = 0;
    for (std::int64_t j = 1; j <= inside; ++j)
    {
      const double at = total > 0.0 ? j * total / (inside + 1) : 0.0;
      while (node + 2 < vertices.size() && cumulative[node + 1] < at)
      {
        ++node;
      }
      const double span = cumulative[node + 1] - cumulative[node];
      const double t = span > 0.0 ? std::clamp((at - cumulative[node]) / span, 0.0, 1.0) : 0.5;
      double w[3];
      path.Samples.push_back(static_cast<Index>(out.Kind.size()));
      path.SampleArc.push_back(path.Arc[node] + t * (path.Arc[node + 1] - path.Arc[node]));
      AddSample(topology, points, EdgePoint(topology, vertices[node], vertices[node + 1], t, w), w,
        SampleKind::Boundary, -1, out);
    }
    path.Samples.push_back(cornerSample[vertices.back()]);
    path.SampleArc.push_back(path.Arc.back());
    out.Paths.push_back(std::move(path));
  }
}

} // namespace beltrami
