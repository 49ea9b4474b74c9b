#include "Remeshing/SurfaceSampling.h"

#include "Maps/GeometryImages.h"
#include "Mesh/Geometry.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/BoundaryChords.h"
#include "Remeshing/BoundarySampling.h"
#include "Remeshing/ErrorDiffusion.h"
#include "Remeshing/Remesh.h"
#include "Remeshing/RemeshMetric.h"
#include "Remeshing/SqueezedParts.h"
#include "Remeshing/Tips.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <limits>
#include <utility>

namespace beltrami
{

bool IsOpenEdge(const MeshTopology::EdgeTable& edges, std::int64_t e)
{
  return edges.OppositeCorners[2 * e] < 0 || edges.OppositeCorners[2 * e + 1] < 0;
}

bool IsKeptEdge(const MeshTopology::EdgeTable& edges, std::int64_t e, const std::uint8_t* featureEdges)
{
  return IsOpenEdge(edges, e) || (featureEdges && featureEdges[e]);
}

void AddSample(const MeshTopology& topology, const double* points, Index triangle, const double* w, SampleKind kind,
  int chart, SurfaceSamples& out)
{
  const Vec3 x = SurfacePoint(topology, points, triangle, w);
  out.Triangle.push_back(triangle);
  out.Barycentric.insert(out.Barycentric.end(), w, w + 3);
  out.Positions.insert(out.Positions.end(), { x.x(), x.y(), x.z() });
  out.Kind.push_back(kind);
  out.Chart.push_back(chart);
}

std::size_t NearestInterior(const std::vector<std::size_t>& samples, const Vec3& x, const SurfaceSamples& out)
{
  std::size_t nearest = out.Kind.size();
  double best = HUGE_VAL;
  for (std::size_t s : samples)
  {
    const double d = (Point(out.Positions.data(), static_cast<Index>(s)) - x).squaredNorm();
    if (out.Kind[s] == SampleKind::Interior && d < best)
    {
      best = d;
      nearest = s;
    }
  }
  return nearest;
}

void MoveSample(std::size_t s, const Vec3& x, Index triangle, const double w[3], SampleKind kind, SurfaceSamples& out)
{
  out.Triangle[s] = triangle;
  std::copy(w, w + 3, &out.Barycentric[3 * s]);
  std::copy(x.data(), x.data() + 3, &out.Positions[3 * s]);
  out.Kind[s] = kind;
}

/// The seams' spacings over the density's tried in turn (SamplingOptions::
/// SparserSeams).  A lattice of 81 handles at 2,000 vertices, 601 charts:
/// 2,924 boundary samples, 1,493 of them corners; at twice the spacing
/// 1,635, three times 1,505.
constexpr double SparserSeamSpacings[] = { 2.0, 3.0 };

namespace
{

/// The triangle of `chart` whose centre is farthest from the chart's
/// boundary (its vertices that a triangle of another chart, or the
/// surface's boundary, touches): where a sample leaves the fewest flat
/// triangles beside the boundary (a chart's largest triangle can be a long
/// sliver along it).
Index InnermostTriangle(const MeshTopology& topology, const double* points, const AtlasResult& atlas, int chart)
{
  std::vector<Vec3> border;
  for (Index v : atlas.Charts[chart].Vertices)
  {
    if (!topology.IsInterior(v) || std::any_of(topology.CornersBegin(v), topology.CornersEnd(v),
                                     [&](Index c) { return atlas.ChartOfTriangle[c / 3] != chart; }))
    {
      border.push_back(Point(points, v));
    }
  }
  // (At most about 1,000 triangles and border points looked at: charts
  // without a sample are small, but a count below the charts' is not.)
  const std::vector<Index>& triangles = atlas.Charts[chart].Triangles;
  const std::size_t step = 1 + triangles.size() / 1000, borderStep = 1 + border.size() / 1000;
  Index best = triangles.front();
  double farthest = -1.0;
  for (std::size_t i = 0; i < triangles.size(); i += step)
  {
    const Index t = triangles[i];
    const Vec3 centre = (Point(points, topology.CornerVertex(3 * t)) + Point(points, topology.CornerVertex(3 * t + 1)) +
                          Point(points, topology.CornerVertex(3 * t + 2))) / 3.0;
    double nearest = HUGE_VAL;
    for (std::size_t k = 0; k < border.size(); k += borderStep)
    {
      nearest = std::min(nearest, (border[k] - centre).squaredNorm());
    }
    if (nearest > farthest)
    {
      farthest = nearest;
      best = t;
    }
  }
  return best;
}

/// A chart far smaller than the spacing gets no interior sample; where its
/// neighbour across its boundary gets none either, both triangulate the
/// same few boundary samples into the same triangles (a speck of a scan, a
/// thin limb's tip).  Every chart without one gets one interior sample, at
/// the centre of its innermost triangle, taken from the chart with the most
/// (its last one): the count stays, and a component too small for the
/// spacing is kept as a closed mesh of a few vertices.  Returns how many
/// charts are left without one (the interior samples fewer than the charts).
std::size_t GiveEveryChartAnInteriorSample(
  const MeshTopology& topology, const double* points, const AtlasResult& atlas, SurfaceSamples& out)
{
  std::vector<std::int64_t> count(atlas.Charts.size(), 0), last(atlas.Charts.size(), -1);
  for (std::size_t s = 0; s < out.Kind.size(); ++s)
  {
    if (out.Kind[s] == SampleKind::Interior)
    {
      ++count[out.Chart[s]];
      last[out.Chart[s]] = static_cast<std::int64_t>(s);
    }
  }
  for (std::size_t c = 0; c < atlas.Charts.size(); ++c)
  {
    const std::size_t donor = static_cast<std::size_t>(std::max_element(count.begin(), count.end()) - count.begin());
    if (count[c] > 0 || count[donor] < 2)
    {
      continue;
    }
    const Index largest = InnermostTriangle(topology, points, atlas, static_cast<int>(c));
    // The donor's last sample takes the new one's place (interior samples
    // follow the boundary samples, whose ids the paths hold).
    const std::size_t s = static_cast<std::size_t>(last[donor]);
    const double w[3] = { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 };
    const Vec3 x = SurfacePoint(topology, points, largest, w);
    out.Triangle[s] = largest;
    std::copy(w, w + 3, &out.Barycentric[3 * s]);
    std::copy(x.data(), x.data() + 3, &out.Positions[3 * s]);
    out.Chart[s] = static_cast<int>(c);
    --count[donor];
    ++count[c];
    last[donor] = -1;
    for (std::size_t k = s; k-- > 0 && last[donor] < 0;) // the donor's new last sample
    {
      last[donor] = out.Kind[k] == SampleKind::Interior && out.Chart[k] == static_cast<int>(donor)
        ? static_cast<std::int64_t>(k) : -1;
    }
    last[c] = static_cast<std::int64_t>(s);
  }
  return static_cast<std::size_t>(std::count(count.begin(), count.end(), 0));
}

/// Drops every sample and path of `out` (to sample the boundaries again).
void ClearSamples(SurfaceSamples& out)
{
  out.Triangle.clear();
  out.Barycentric.clear();
  out.Positions.clear();
  out.Kind.clear();
  out.Chart.clear();
  out.Paths.clear();
}

/// Marks the texels (of an n x n image, coordinates in texels) whose centre
/// lies within `radius` of the segment from a to b, and for which `keep`
/// holds (the texel's index), as Outside.
template <typename Keep>
void MarkAroundSegment(const double* a, const double* b, double radius, int n, const Keep& keep,
  std::vector<std::uint8_t>& roles)
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
      const std::size_t p = static_cast<std::size_t>(y) * n + x;
      if ((px - s * dx) * (px - s * dx) + (py - s * dy) * (py - s * dy) <= radius * radius && keep(p))
      {
        roles[p] = static_cast<std::uint8_t>(PixelRole::Outside);
      }
    }
  }
}

/// The most a chart boundary's band is widened by its map's stretch across
/// the boundary, over its scale along it (4 made slivers beside the rims of
/// a noisy scan; 16 and 64 change no corpus remesh but the fan of 2,000
/// slivers', within CGAL's deviation).
constexpr double MostBandStretch = 64.0;

/// How far on the surface, in spacings, a texel of a chart boundary's band
/// may lie from the boundary edge (the band is half a spacing wide in the
/// map).  The band's width in the map follows the map's scale across the
/// edge at the triangle beside it; where the map squeezes the chart right
/// behind that triangle (a blade's tip beside a triangle the map stretches a
/// thousandfold), the band's texels lay several spacings from the boundary
/// on the surface, and covered the tip: no sample inside it, the remesh cut
/// it off.  A spacing rather than half: where the map is even, the band is
/// as it was.
constexpr double BandReach = 1.0;

/// The distance on the surface of texel p's point (of `packed`'s
/// triangle there) to the edge from surface vertex a to b.
double SurfaceDistanceToEdge(const MeshTopology& topology, const double* points, const AtlasChart& packed,
  const ChartRaster& raster, std::size_t p, Index a, Index b)
{
  double w[3];
  PixelBarycentric(packed, raster, p, w);
  const Index triangle = packed.Triangles[raster.Face[p]];
  return SegmentDistance(SurfacePoint(topology, points, triangle, w), Point(points, a), Point(points, b));
}

/// Marks the texels within half a sample spacing of every chart boundary
/// edge (in each chart it bounds, of that chart) as outside the halftone:
/// the boundary samples stand for that band.
void ExcludeBoundaryBand(const MeshTopology& topology, const double* points, const double* importance,
  const AtlasResult& atlas, const AtlasChart& packed, const ChartRaster& raster, const BoundaryPaths& boundaries,
  double density, std::vector<std::uint8_t>& roles)
{
  const int n = raster.Resolution;
  for (const std::vector<Index>& path : boundaries.Paths)
  {
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
    {
      const Index a = path[i], b = path[i + 1];
      const std::int64_t e = topology.Edges().Find(a, b);
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
        const int c = atlas.ChartOfTriangle[corner / 3];
        const AtlasChart& chart = atlas.Charts[c];
        const Index apex = topology.CornerVertex(corner);
        double uv[3][2];
        for (int k = 0; k < 3; ++k)
        {
          const Index v = k == 0 ? a : (k == 1 ? b : apex);
          const Index local = static_cast<Index>(
            std::lower_bound(chart.Vertices.begin(), chart.Vertices.end(), v) - chart.Vertices.begin());
          AtlasUV(chart, local, uv[k]);
          uv[k][0] *= n;
          uv[k][1] *= n;
        }
        // The band's width in texels by the map's scale across the edge (the
        // height of the triangle there in texels over its height in 3D): a
        // map squeezed across the boundary would otherwise have a band far
        // wider than half a spacing on the surface.  At most MostBandStretch
        // times the scale along it: a sliver of next to no height in 3D (an
        // isosurface's, where its level passes a grid point) made a band
        // over the whole image.  Only the chart's own texels: where its map
        // widens towards its boundary (80 times, a chart of a triply periodic
        // surface cut by a box), the band reached over its neighbours in the
        // packing, and 31 of 93 charts were left without a sample inside.
        const double lengthPx = std::hypot(uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
        const double areaPx = std::abs((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1]) - (uv[1][1] - uv[0][1]) * (uv[2][0] - uv[0][0]));
        const double area3D = (Point(points, b) - Point(points, a)).cross(Point(points, apex) - Point(points, a)).norm();
        const double along = lengthPx / length3D;
        const double scale = area3D > 0.0 && lengthPx > 0.0
          ? std::min((areaPx / lengthPx) / (area3D / length3D), MostBandStretch * along) : along;
        const auto own = [&](std::size_t p) {
          return raster.Face[p] >= 0 && atlas.ChartOfTriangle[packed.Triangles[raster.Face[p]]] == c &&
            SurfaceDistanceToEdge(topology, points, packed, raster, p, a, b) <= BandReach * spacing3D;
        };
        MarkAroundSegment(uv[0], uv[1], 0.5 * spacing3D * scale, n, own, roles);
      }
    }
  }
}

/// The charts rasterized at n^2 texels with their area map, from the cache
/// when it has them.  The cache keeps the last used: at most four rasters,
/// and beyond 256 MiB only the last two.
const RemeshCache::Raster& RasterAt(const AtlasChart& packed, const double* points, int n, int threads,
  RemeshCache& cache)
{
  const auto kept = cache.Rasters.find(n);
  if (kept != cache.Rasters.end())
  {
    kept->second.LastUse = ++cache.Clock;
    return kept->second;
  }
  const auto bytes = [&]() {
    std::size_t total = 0;
    for (const auto& [size, r] : cache.Rasters)
    {
      total += r.Charts.Face.size() * (sizeof(Index) + sizeof(double));
    }
    return total;
  };
  while (cache.Rasters.size() >= 4 || (cache.Rasters.size() >= 2 && bytes() > (std::size_t(256) << 20)))
  {
    cache.Rasters.erase(std::min_element(cache.Rasters.begin(), cache.Rasters.end(),
      [](const auto& a, const auto& b) { return a.second.LastUse < b.second.LastUse; }));
  }
  RemeshCache::Raster& r = cache.Rasters[n];
  r.LastUse = ++cache.Clock;
  RasterizeChart(packed, n, r.Charts, threads);
  r.AreaRatio.resize(r.Charts.Face.size());
  AreaMap(r.Charts, packed, points, r.AreaRatio.data(), threads);
  return r;
}

/// The control map on a raster: expected samples per texel at unit density
/// (the area map times the importance, NaN outside the charts); returns its
/// sum.
double BuildControlMap(const RemeshCache::Raster& r, const AtlasChart& packed, const double* importance,
  int threads, LargeVector<double>& map)
{
  const ChartRaster& raster = r.Charts;
  const double n = raster.Resolution;
  LargeVector<double> weight(raster.Face.size(), 1.0);
  if (importance)
  {
    InterpolateOnRaster(raster, packed, importance, 1, weight.data(), false, threads);
  }
  double mass = 0.0;
  map.resize(raster.Face.size());
  for (std::size_t p = 0; p < raster.Face.size(); ++p)
  {
    const double d = raster.Face[p] >= 0 ? r.AreaRatio[p] * std::max(0.0, weight[p]) / (n * n) : 0.0;
    map[p] = raster.Face[p] >= 0 ? d : std::numeric_limits<double>::quiet_NaN();
    mass += d;
  }
  return mass;
}

/// The q-quantile of the finite values.
double Quantile(const LargeVector<double>& values, double q)
{
  LargeVector<double> finite;
  std::copy_if(values.begin(), values.end(), std::back_inserter(finite), [](double v) { return std::isfinite(v); });
  if (finite.empty())
  {
    return 0.0;
  }
  const auto at = finite.begin() + static_cast<std::ptrdiff_t>(q * (finite.size() - 1));
  std::nth_element(finite.begin(), at, finite.end());
  return *at;
}

/// A hash of the atlas's charts, a 64-bit word at a time (FNV-1a's
/// steps): their triangles and maps, and where they lie in memory (the
/// locators point into them).
std::uint64_t AtlasKey(const AtlasResult& atlas)
{
  std::uint64_t key = 1469598103934665603ULL;
  const auto add = [&key](std::uint64_t word) { key = (key ^ word) * 1099511628211ULL; };
  for (const AtlasChart& chart : atlas.Charts)
  {
    add(reinterpret_cast<std::uintptr_t>(&chart));
    add(reinterpret_cast<std::uintptr_t>(chart.UV.data()));
    add(chart.Triangles.size());
    for (const Index t : chart.Triangles)
    {
      add(static_cast<std::uint64_t>(t));
    }
    for (const double u : chart.UV)
    {
      std::uint64_t bits;
      std::memcpy(&bits, &u, sizeof(bits));
      add(bits);
    }
  }
  return key;
}

} // namespace

const std::vector<ChartLocator>& RemeshCache::Locators(const AtlasResult& atlas)
{
  const std::uint64_t key = AtlasKey(atlas);
  if (ChartLocators.size() != atlas.Charts.size() || key != LocatorsKey)
  {
    LocatorsKey = key;
    ChartLocators.clear();
    ChartLocators.reserve(atlas.Charts.size());
    for (const AtlasChart& chart : atlas.Charts)
    {
      ChartLocators.emplace_back(chart);
    }
  }
  return ChartLocators;
}

bool SurfaceKey::Renew(const MeshTopology& topology, const double* points)
{
  const SurfaceKey now{ points, topology.TriangleList().data(), topology.NumberOfTriangles() };
  const bool other = now.Points != Points || now.Triangles != Triangles || now.Count != Count;
  *this = now;
  return other;
}

const TriangleGrid& RemeshCache::SurfaceGrid(const MeshTopology& topology, const double* points, int numThreads)
{
  if (GridKey.Renew(topology, points) || !Grid)
  {
    Grid = std::make_unique<TriangleGrid>(
      points, topology.TriangleList().data(), static_cast<std::size_t>(topology.NumberOfTriangles()), numThreads);
  }
  return *Grid;
}

const RemeshCache::SurfaceFigures& RemeshCache::Figures(
  const MeshTopology& topology, const double* points, int numThreads)
{
  if (FiguresKey.Renew(topology, points))
  {
    KeptFigures.Diagonal =
      UsedBoundingBoxDiagonal(points, topology.TriangleList().data(), topology.NumberOfTriangles());
    KeptFigures.Area = SurfaceArea(topology, points, numThreads);
    KeptFigures.Components = topology.CountComponents();
  }
  return KeptFigures;
}

const std::vector<double>& RemeshCache::AngleDefects(const MeshTopology& topology, const double* points, int numThreads)
{
  const Index n = topology.NumberOfVertices();
  if (DefectsKey.Renew(topology, points) || Defects.size() != static_cast<std::size_t>(n))
  {
    Defects.assign(n, 0.0);
    ParallelFor(n, numThreads, [&](std::int64_t begin, std::int64_t end) {
      for (Index v = static_cast<Index>(begin); v < end; ++v)
      {
        Defects[v] = topology.IsInterior(v) && topology.Valence(v) > 0 ? AngleDefect(topology, points, v) : 0.0;
      }
    });
  }
  return Defects;
}

std::pair<std::size_t, double> EdgeAtArc(const std::vector<double>& arcs, double arc)
{
  const std::size_t last = arcs.size() - 1;
  std::size_t node = static_cast<std::size_t>(std::upper_bound(arcs.begin(), arcs.end(), arc) - arcs.begin());
  node = std::clamp<std::size_t>(node, 1, last) - 1;
  const double span = arcs[node + 1] - arcs[node];
  return { node, span > 0.0 ? std::clamp((arc - arcs[node]) / span, 0.0, 1.0) : 0.0 };
}

double SpacingAt(const double* importance, double density, Index v)
{
  return SpacingOf(density, importance ? importance[v] : 1.0);
}

Index LocateOnPath(const MeshTopology& topology, const SamplePath& path, double arc, double barycentric[3])
{
  const auto [node, t] = EdgeAtArc(path.Arc, arc);
  return EdgePoint(topology, path.Vertices[node], path.Vertices[node + 1], t, barycentric);
}

std::optional<double> RefinedMiddle(const SamplePath& path, double lo, double hi)
{
  if (path.Refinement.empty() || !(hi > lo))
  {
    return std::nullopt;
  }
  // The refinement, linear on each edge, at the ends and at the vertices
  // between them; the integral by the trapezoid rule.
  const auto at = [&](double arc) {
    const auto [i, t] = EdgeAtArc(path.Arc, arc);
    return (1.0 - t) * path.Refinement[i] + t * path.Refinement[i + 1];
  };
  std::vector<double> arcs = { lo };
  for (std::size_t i = 0; i < path.Arc.size(); ++i)
  {
    if (path.Arc[i] > lo && path.Arc[i] < hi)
    {
      arcs.push_back(path.Arc[i]);
    }
  }
  arcs.push_back(hi);
  if (std::all_of(arcs.begin(), arcs.end(), [&](double arc) { return at(arc) == 1.0; }))
  {
    return std::nullopt;
  }
  std::vector<double> integral(arcs.size(), 0.0);
  for (std::size_t k = 1; k < arcs.size(); ++k)
  {
    integral[k] = integral[k - 1] + 0.5 * (at(arcs[k - 1]) + at(arcs[k])) * (arcs[k] - arcs[k - 1]);
  }
  const double half = 0.5 * integral.back();
  std::size_t k = 1;
  while (k + 1 < arcs.size() && integral[k] < half)
  {
    ++k;
  }
  // In the piece, the refinement a + slope t integrates to a u + slope u^2 / 2.
  const double a = at(arcs[k - 1]), slope = (at(arcs[k]) - a) / std::max(arcs[k] - arcs[k - 1], 1e-300);
  const double rest = half - integral[k - 1];
  const double u = std::abs(slope) * rest > 1e-12 * a * a ? (std::sqrt(a * a + 2.0 * slope * rest) - a) / slope : rest / a;
  return std::clamp(arcs[k - 1] + u, lo, hi);
}

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
  int n = options.Resolution > 0
    ? options.Resolution
    : std::clamp(static_cast<int>(std::ceil(std::sqrt(8.0 * options.NumberOfSamples / packing))), 32, 8192);
  RemeshCache local;
  RemeshCache& cache = options.Cache ? *options.Cache : local;
  if (!cache.Packed)
  {
    cache.Packed = std::make_unique<AtlasChart>(PackedAtlas(atlas));
  }
  const AtlasChart& packed = *cache.Packed;
  const RemeshCache::Raster* kept = &RasterAt(packed, points, n, options.NumberOfThreads, cache);
  double mass = BuildControlMap(*kept, packed, importance, options.NumberOfThreads, out.ControlMap);
  if (options.Resolution <= 0 && mass > 0.0)
  {
    // Where the charts' maps shrink the surface most, a texel would need
    // more than one sample: finer texels until 99.9% of them need at most
    // half a sample.
    const double busiest = Quantile(out.ControlMap, 0.999) * options.NumberOfSamples / mass;
    const int finer = std::min(8192, static_cast<int>(std::ceil(n * std::sqrt(busiest / 0.5))));
    if (finer > n)
    {
      n = finer;
      kept = &RasterAt(packed, points, n, options.NumberOfThreads, cache);
      mass = BuildControlMap(*kept, packed, importance, options.NumberOfThreads, out.ControlMap);
    }
  }
  const ChartRaster& raster = kept->Charts;
  out.Resolution = n;
  if (!(mass > 0.0))
  {
    out.Error = "the importance is zero everywhere: no density to sample";
    return out;
  }
  // The band around the boundaries holds as many expected samples as the
  // boundary paths get (a band one spacing wide), so the whole count goes
  // by the map's mass.
  out.Density = options.NumberOfSamples / mass;
  const BoundaryPaths boundaries =
    ChartBoundaries(topology, points, importance, options.Metric, out.Density, atlas.ChartOfTriangle,
      options.FeatureEdges, options.PinnedVertices);
  // The boundaries sampled afresh (the line sag bound, the seams' spacing
  // over the density's); whether they leave fewer than `room` samples.
  double sag = options.MaximumLineSag;
  const auto sample = [&](double seamSpacing) {
    ClearSamples(out);
    SampleBoundaries(topology, points, importance, atlas.ChartOfTriangle, boundaries, out.Density,
      options.FeatureEdges, sag, options.Metric, out, seamSpacing);
    out.SeamSpacing = seamSpacing;
  };
  const auto exceeds = [&](std::size_t room) {
    return static_cast<std::int64_t>(out.Kind.size() + room) > options.NumberOfSamples;
  };
  sample(1.0);
  if (sag > 0.0 && exceeds(0))
  {
    // Lines that bend at every vertex (the jagged rims of a scan's many
    // holes) would take more than the count: the density's spacing along
    // them instead.
    sag = 0.0;
    sample(1.0);
  }
  if (options.SparserSeams && exceeds(0))
  {
    // The seams of a surface of many handles (a lattice of bars, a block
    // drilled through: many charts) take more than the count: sparser,
    // until every chart has room for a sample inside.  The stitching
    // rounds free their samples and even the remesh across them.
    for (const double sparser : SparserSeamSpacings)
    {
      sample(sparser);
      if (!exceeds(atlas.Charts.size()))
      {
        break;
      }
    }
  }
  SeparateCrossingChords(topology, points, atlas, out);
  out.BoundarySamples = static_cast<std::int64_t>(out.Kind.size());
  out.NeededSamples = out.BoundarySamples + static_cast<std::int64_t>(atlas.Charts.size());
  for (const SamplePath& path : out.Paths)
  {
    if ((path.Charts[0] < 0 || path.Charts[1] < 0) && !path.Samples.empty())
    {
      out.RimSamples += static_cast<std::int64_t>(path.Samples.size()) - 1; // (corners shared with the next path)
    }
  }
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
  ExcludeBoundaryBand(topology, points, importance, atlas, packed, raster, boundaries, out.Density, roles);
  // The parts the charts' maps squeeze past the texels are sampled on the
  // surface (Remeshing/SqueezedParts), and their texels left out.
  const SqueezedSamples squeezed = SampleSqueezedParts(
    topology, points, atlas, packed, importance, out.Density, n, options.NumberOfSamples - out.BoundarySamples);
  for (std::size_t p = 0; p < roles.size() && !squeezed.Triangle.empty(); ++p)
  {
    if (raster.Face[p] >= 0 && squeezed.PackedSqueezed[raster.Face[p]])
    {
      roles[p] = static_cast<std::uint8_t>(PixelRole::Outside);
    }
  }
  const std::int64_t squeezedCount = static_cast<std::int64_t>(squeezed.Chart.size());
  HalftoneResult halftone = Halftone(
    out.ControlMap.data(), n, n, options.NumberOfSamples - out.BoundarySamples - squeezedCount, roles.data());
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
      double w[3];
      PixelBarycentric(packed, raster, p, w);
      AddSample(topology, points, triangle, w, SampleKind::Interior,
        atlas.ChartOfTriangle[triangle], out);
    }
  }
  for (std::int64_t s = 0; s < squeezedCount; ++s)
  {
    AddSample(topology, points, squeezed.Triangle[s], &squeezed.Barycentric[3 * s], SampleKind::Interior,
      squeezed.Chart[s], out);
  }
  out.Halftone = std::move(halftone.Samples);
  out.ChartsWithoutSample =
    static_cast<std::int64_t>(GiveEveryChartAnInteriorSample(topology, points, atlas, out));
  const std::vector<double>& defects = cache.AngleDefects(topology, points, options.NumberOfThreads);
  if (PinTips(topology, points, atlas, options.TipAngleDefect, defects.data(), options.PinnedVertices, importance,
        out.Density, out) > 0)
  {
    // (A path sample moved onto a tip can leave a chord on the far side of
    // another: a speck of eight triangles whose seam loop went round its
    // two tips.)
    SeparateCrossingChords(topology, points, atlas, out, true);
  }
  return out;
}

} // namespace beltrami
