#include "Remeshing/SurfaceSampling.h"

#include "Maps/ChartPartition.h"
#include "Maps/GeometryImages.h"
#include "Mesh/Geometry.h"
#include "Remeshing/ErrorDiffusion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace beltrami
{

namespace
{

/// The chart boundaries as paths of surface vertices between corners
/// (vertices where other than two boundary edges meet; a closed loop
/// without one starts and ends at its first vertex, made a corner).
struct BoundaryPaths
{
  std::vector<std::vector<Index>> Paths;
  std::vector<Index> Corners;
};

/// The edge joining vertices a and b (-1: none).
std::int64_t EdgeOf(const MeshTopology::EdgeTable& edges, Index a, Index b)
{
  const Index* begin = edges.Neighbors.data() + edges.NeighborOffsets[a];
  const Index* end = edges.Neighbors.data() + edges.NeighborOffsets[a + 1];
  const Index* at = std::lower_bound(begin, end, b);
  return at != end && *at == b ? edges.NeighborEdges[at - edges.Neighbors.data()] : -1;
}

BoundaryPaths ChartBoundaries(const MeshTopology& topology, const std::vector<int>& chartOfTriangle)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  std::vector<std::uint8_t> boundary = EdgesBetweenLabels(topology, chartOfTriangle);
  std::vector<int> valence(topology.NumberOfVertices(), 0);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    boundary[e] = boundary[e] || edges.OppositeCorners[2 * e + 1] < 0 || edges.OppositeCorners[2 * e] < 0;
    valence[edges.Vertices[2 * e]] += boundary[e];
    valence[edges.Vertices[2 * e + 1]] += boundary[e];
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

/// A sample in `triangle` at barycentric weights w (of its corners).
void AddSample(const MeshTopology& topology, const double* points, Index triangle, const double* w, SampleKind kind,
  int chart, SurfaceSamples& out)
{
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
  {
    x += w[k] * Point(points, topology.CornerVertex(3 * triangle + k));
  }
  out.Triangle.push_back(triangle);
  out.Barycentric.insert(out.Barycentric.end(), w, w + 3);
  out.Positions.insert(out.Positions.end(), { x.x(), x.y(), x.z() });
  out.Kind.push_back(kind);
  out.Chart.push_back(chart);
}

/// A sample at fraction t of the way from vertex a to vertex b (b == a: at
/// the vertex), on a triangle that has them.
void AddBoundarySample(const MeshTopology& topology, const double* points, Index a, Index b, double t,
  SampleKind kind, SurfaceSamples& out)
{
  Index triangle = topology.CornersBegin(a)[0] / 3;
  if (b != a)
  {
    const MeshTopology::EdgeTable& edges = topology.Edges();
    const std::int64_t e = EdgeOf(edges, std::min(a, b), std::max(a, b));
    triangle = (edges.OppositeCorners[2 * e] >= 0 ? edges.OppositeCorners[2 * e] : edges.OppositeCorners[2 * e + 1]) / 3;
  }
  double w[3];
  for (int k = 0; k < 3; ++k)
  {
    const Index v = topology.CornerVertex(3 * triangle + k);
    w[k] = v == a ? 1.0 - t : (v == b ? t : 0.0);
  }
  AddSample(topology, points, triangle, w, kind, -1, out);
}

/// The corners, then samples along every path at the spacing of the density
/// (1D error diffusion: samples where the integral of sqrt(density) passes
/// even fractions of it; a closed loop keeps at least three samples).
void SampleBoundaries(const MeshTopology& topology, const double* points, const double* importance,
  const BoundaryPaths& boundaries, double density, SurfaceSamples& out)
{
  const auto lambda = [&](Index v) { return std::sqrt(density * (importance ? std::max(0.0, importance[v]) : 1.0)); };
  for (Index c : boundaries.Corners)
  {
    AddBoundarySample(topology, points, c, c, 0.0, SampleKind::Corner, out);
  }
  for (const std::vector<Index>& path : boundaries.Paths)
  {
    std::vector<double> cumulative(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i)
    {
      const double length = (Point(points, path[i]) - Point(points, path[i - 1])).norm();
      cumulative[i] = cumulative[i - 1] + 0.5 * (lambda(path[i]) + lambda(path[i - 1])) * length;
    }
    const double total = cumulative.back();
    const bool loop = path.front() == path.back();
    const std::int64_t inside = std::max<std::int64_t>(loop ? 2 : 0, std::llround(total) - 1);
    std::size_t node = 0;
    for (std::int64_t j = 1; j <= inside; ++j)
    {
      const double at = total > 0.0 ? j * total / (inside + 1) : 0.0;
      while (node + 2 < path.size() && cumulative[node + 1] < at)
      {
        ++node;
      }
      const double span = cumulative[node + 1] - cumulative[node];
      const double t = span > 0.0 ? std::clamp((at - cumulative[node]) / span, 0.0, 1.0) : 0.5;
      AddBoundarySample(topology, points, path[node], path[node + 1], t, SampleKind::Boundary, out);
    }
  }
}

/// Marks the texels (of an n x n image, coordinates in texels) whose centre
/// lies within `radius` of the segment from a to b as Outside.
void MarkAroundSegment(const double* a, const double* b, double radius, int n, std::vector<std::uint8_t>& roles)
{
  const double dx = b[0] - a[0], dy = b[1] - a[1], length2 = dx * dx + dy * dy;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a[0], b[0]) - radius)));
  const int x1 = std::min(n - 1, static_cast<int>(std::ceil(std::max(a[0], b[0]) + radius)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a[1], b[1]) - radius)));
  const int y1 = std::min(n - 1, static_cast<int>(std::ceil(std::max(a[1], b[1]) + radius)));
  for (int y = y0; y <= y1; ++y)
  {
    for (int x = x0; x <= x1; ++x)
    {
      const double px = x + 0.5 - a[0], py = y + 0.5 - a[1];
      const double s = length2 > 0.0 ? std::clamp((px * dx + py * dy) / length2, 0.0, 1.0) : 0.0;
      if ((px - s * dx) * (px - s * dx) + (py - s * dy) * (py - s * dy) <= radius * radius)
      {
        roles[static_cast<std::size_t>(y) * n + x] = static_cast<std::uint8_t>(PixelRole::Outside);
      }
    }
  }
}

/// Marks the texels within half a sample spacing of every chart boundary
/// edge (in each chart it bounds) as outside the halftone: the boundary
/// samples stand for that band.
void ExcludeBoundaryBand(const MeshTopology& topology, const double* points, const double* importance,
  const AtlasResult& atlas, const BoundaryPaths& boundaries, double density, int n, std::vector<std::uint8_t>& roles)
{
  for (const std::vector<Index>& path : boundaries.Paths)
  {
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
    {
      const Index a = path[i], b = path[i + 1];
      const std::int64_t e = EdgeOf(topology.Edges(), std::min(a, b), std::max(a, b));
      const double length3D = (Point(points, a) - Point(points, b)).norm();
      const double imp = importance ? 0.5 * (std::max(0.0, importance[a]) + std::max(0.0, importance[b])) : 1.0;
      const double spacing3D = density * imp > 0.0 ? 1.0 / std::sqrt(density * imp) : 0.0;
      for (int side = 0; side < 2; ++side)
      {
        const Index corner = topology.Edges().OppositeCorners[2 * e + side];
        if (corner < 0 || length3D <= 0.0)
        {
          continue;
        }
        const AtlasChart& chart = atlas.Charts[atlas.ChartOfTriangle[corner / 3]];
        double uv[2][2];
        for (int k = 0; k < 2; ++k)
        {
          const Index local = static_cast<Index>(
            std::lower_bound(chart.Vertices.begin(), chart.Vertices.end(), k ? b : a) - chart.Vertices.begin());
          AtlasUV(chart, local, uv[k]);
          uv[k][0] *= n;
          uv[k][1] *= n;
        }
        const double lengthPx = std::hypot(uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
        MarkAroundSegment(uv[0], uv[1], 0.5 * spacing3D * lengthPx / length3D, n, roles);
      }
    }
  }
}

} // namespace

SurfaceSamples SampleSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const SamplingOptions& options)
{
  SurfaceSamples out;
  if (!atlas.Error.empty() || atlas.Charts.empty() || options.NumberOfSamples <= 0)
  {
    out.Error = atlas.Error.empty() ? "nothing to sample: no charts or no samples requested" : atlas.Error;
    return out;
  }
  const double packing = std::max(1e-3, atlas.PackingEfficiency);
  const int n = options.Resolution > 0
    ? options.Resolution
    : std::clamp(static_cast<int>(std::ceil(std::sqrt(8.0 * options.NumberOfSamples / packing))), 32, 8192);
  out.Resolution = n;
  // The control map: expected samples per texel at unit density.
  const AtlasChart packed = PackedAtlas(atlas);
  const ChartRaster raster = RasterizeChart(packed, n, options.NumberOfThreads);
  std::vector<double> ratio(raster.Face.size()), weight(raster.Face.size(), 1.0);
  AreaMap(raster, packed, points, ratio.data());
  if (importance)
  {
    InterpolateOnRaster(raster, packed, importance, 1, weight.data(), false, options.NumberOfThreads);
  }
  double mass = 0.0;
  out.ControlMap.resize(raster.Face.size());
  for (std::size_t p = 0; p < raster.Face.size(); ++p)
  {
    const double d = raster.Face[p] >= 0 ? ratio[p] * std::max(0.0, weight[p]) / (double(n) * n) : 0.0;
    out.ControlMap[p] = raster.Face[p] >= 0 ? d : std::numeric_limits<double>::quiet_NaN();
    mass += d;
  }
  if (!(mass > 0.0))
  {
    out.Error = "the importance is zero everywhere: no density to sample";
    return out;
  }
  // The band around the boundaries holds as many expected samples as the
  // boundary paths get (a band one spacing wide), so the whole count goes
  // by the map's mass.
  out.Density = options.NumberOfSamples / mass;
  const BoundaryPaths boundaries = ChartBoundaries(topology, atlas.ChartOfTriangle);
  SampleBoundaries(topology, points, importance, boundaries, out.Density, out);
  out.BoundarySamples = static_cast<std::int64_t>(out.Kind.size());
  if (out.BoundarySamples > options.NumberOfSamples)
  {
    out.Error = "the chart boundaries need " + std::to_string(out.BoundarySamples) + " samples, more than the " +
      std::to_string(options.NumberOfSamples) + " requested";
    return out;
  }
  std::vector<std::uint8_t> roles(raster.Face.size());
  for (std::size_t p = 0; p < roles.size(); ++p)
  {
    roles[p] = static_cast<std::uint8_t>(raster.Face[p] >= 0 ? PixelRole::Free : PixelRole::Outside);
    out.ControlMap[p] *= out.Density;
  }
  ExcludeBoundaryBand(topology, points, importance, atlas, boundaries, out.Density, n, roles);
  HalftoneResult halftone =
    Halftone(out.ControlMap.data(), n, n, options.NumberOfSamples - out.BoundarySamples, roles.data());
  if (!halftone.Error.empty())
  {
    out.Error = "the control map at " + std::to_string(n) + "^2 texels " + halftone.Error;
    return out;
  }
  for (std::size_t p = 0; p < halftone.Samples.size(); ++p)
  {
    if (halftone.Samples[p])
    {
      const Index triangle = packed.Triangles[raster.Face[p]];
      AddSample(topology, points, triangle, &raster.Barycentric[3 * p], SampleKind::Interior,
        atlas.ChartOfTriangle[triangle], out);
    }
  }
  out.Halftone = std::move(halftone.Samples);
  return out;
}

} // namespace beltrami
