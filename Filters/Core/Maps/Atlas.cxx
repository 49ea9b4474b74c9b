#include "Maps/Atlas.h"

#include "Maps/ChartPartition.h"
#include "Maps/Distortion.h"
#include "Maps/Parameterization.h"
#include "Mesh/MeshMeasures.h"
#include "Solvers/DenseBlocks.h"
#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace beltrami
{

namespace
{

/// True when the segments (a, b) and (c, d) cross (proper intersection).
bool Cross(const double* a, const double* b, const double* c, const double* d)
{
  const auto side = [](const double* p, const double* q, const double* r) {
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
  };
  const double d1 = side(c, d, a), d2 = side(c, d, b), d3 = side(a, b, c), d4 = side(a, b, d);
  return ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0));
}

/// True when the boundary loop of the chart's map is a simple polygon (a
/// free boundary, unlike a circle or a square, can overlap itself).
bool BoundaryIsSimple(const MeshTopology& topology, const std::vector<double>& uv)
{
  for (const std::vector<Index>& loop : topology.BoundaryLoops())
  {
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i)
    {
      for (std::size_t j = i + 2; j < n; ++j)
      {
        if ((j + 1) % n == i)
        {
          continue; // neighbouring segments
        }
        if (Cross(&uv[2 * loop[i]], &uv[2 * loop[(i + 1) % n]], &uv[2 * loop[j]], &uv[2 * loop[(j + 1) % n]]))
        {
          return false;
        }
      }
    }
  }
  return true;
}

/// Whether the map `uv` of the chart squeezes more than `squeezedShare` of
/// its 3D area to an eighth or less of the chart's mean area scale (3D area
/// per map area), or stretches more than `stretchedShare` of it three times
/// more one way than the other (a triangle's conformal distortion
/// |J|_F^2 / (2 det J) = sum over its edges of cot(opposite 3D angle)
/// |edge in the map|^2 / (4 map area) above 5/3: singular values 3:1).
bool TooDistorted(
  const MeshTopology& chart, const double* points, const double* uv, double squeezedShare, double stretchedShare)
{
  if (!(squeezedShare > 0.0 || stretchedShare > 0.0) || chart.NumberOfTriangles() < 2)
  {
    return false;
  }
  std::vector<double> area3D(chart.NumberOfTriangles()), area2D(chart.NumberOfTriangles());
  double total3D = 0.0, total2D = 0.0, stretched = 0.0;
  for (Index t = 0; t < chart.NumberOfTriangles(); ++t)
  {
    const Index v[3] = { chart.CornerVertex(3 * t), chart.CornerVertex(3 * t + 1), chart.CornerVertex(3 * t + 2) };
    const Vec3 a = Point(points, v[0]), b = Point(points, v[1]), c = Point(points, v[2]);
    area3D[t] = 0.5 * (b - a).cross(c - a).norm();
    area2D[t] = 0.5 * std::abs((uv[2 * v[1]] - uv[2 * v[0]]) * (uv[2 * v[2] + 1] - uv[2 * v[0] + 1]) -
                  (uv[2 * v[1] + 1] - uv[2 * v[0] + 1]) * (uv[2 * v[2]] - uv[2 * v[0]]));
    total3D += area3D[t];
    total2D += area2D[t];
    double dirichlet = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const Index i = v[(k + 1) % 3], j = v[(k + 2) % 3];
      const Vec3 p = Point(points, v[k]);
      const Vec3 e1 = Point(points, i) - p, e2 = Point(points, j) - p;
      const double du = uv[2 * i] - uv[2 * j], dv = uv[2 * i + 1] - uv[2 * j + 1];
      dirichlet += e1.dot(e2) / e1.cross(e2).norm() * (du * du + dv * dv);
    }
    stretched += !(dirichlet <= 4.0 * area2D[t] * 5.0 / 3.0) && area3D[t] > 0.0 ? area3D[t] : 0.0;
  }
  if (!(total3D > 0.0) || !(total2D > 0.0))
  {
    return false;
  }
  const double mean = total3D / total2D;
  double squeezed = 0.0;
  for (Index t = 0; t < chart.NumberOfTriangles(); ++t)
  {
    squeezed += area3D[t] > 8.0 * mean * area2D[t] ? area3D[t] : 0.0;
  }
  return (squeezedShare > 0.0 && squeezed > squeezedShare * total3D) ||
    (stretchedShare > 0.0 && stretched > stretchedShare * total3D);
}

/// Charts of fewer triangles are not split for their length (TooLong): a
/// needle's few slivers can be longer than MaximumChartAspect on their own,
/// and halving such a chart down to one triangle would leave it so.
constexpr std::size_t LongChartTriangles = 64;

/// The bounding box of a map's `uv` (2 per vertex): min u, min v, max u, max v.
std::array<double, 4> BoundsOf(const std::vector<double>& uv)
{
  std::array<double, 4> box = { HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (std::size_t v = 0; v < uv.size() / 2; ++v)
  {
    box = { std::min(box[0], uv[2 * v]), std::min(box[1], uv[2 * v + 1]), std::max(box[2], uv[2 * v]),
      std::max(box[3], uv[2 * v + 1]) };
  }
  return box;
}

/// The bounding box of the map `uv` is more than `aspect` times longer
/// than wide (aspect 0: never).
bool TooLong(const std::vector<double>& uv, double aspect)
{
  const std::array<double, 4> box = BoundsOf(uv);
  const double a = box[2] - box[0], b = box[3] - box[1];
  return aspect > 0.0 && std::max(a, b) > aspect * std::min(a, b);
}

/// Maps the chart `mesh` onto its own square by DCP into `chart` (its
/// triangles and vertices moved there); false (mesh kept) when the map
/// fails, flips a triangle, distorts too much (TooDistorted) or is too
/// long (TooLong).
bool MapChart(ChartMesh& mesh, const double* points, const AtlasOptions& atlasOptions, AtlasChart& chart)
{
  std::vector<double> local(3 * mesh.Vertices.size());
  for (std::size_t v = 0; v < mesh.Vertices.size(); ++v)
  {
    std::copy(points + 3 * static_cast<std::size_t>(mesh.Vertices[v]),
      points + 3 * static_cast<std::size_t>(mesh.Vertices[v]) + 3, local.begin() + 3 * v);
  }
  const MeshTopology& chartTopology = *mesh.Topology;
  // The requested boundary; where a square flips a triangle (three boundary
  // points of a triangle on one side) or a natural boundary overlaps itself,
  // the circle, which never puts three points on a line; else the chart is split.
  ParameterizationResult map;
  for (const ParameterizationBoundary shape : { atlasOptions.ChartBoundary, ParameterizationBoundary::Circle })
  {
    ParameterizationOptions options;
    options.Boundary = shape;
    options.Corners = SquareCorners::Sharpest;
    options.NumberOfThreads = 1; // the charts run in parallel
    map = Parameterize(chartTopology, local.data(), options);
    chart.Boundary = shape;
    if (map.Error.empty() && CountFlipped(chartTopology, local.data(), map.UV.data()) == 0 &&
      (shape != ParameterizationBoundary::Natural || BoundaryIsSimple(chartTopology, map.UV)))
    {
      break;
    }
    map.UV.clear();
  }
  if (map.UV.empty() ||
    TooDistorted(chartTopology, local.data(), map.UV.data(), atlasOptions.MaximumSqueezedShare,
      atlasOptions.MaximumStretchedShare) ||
    (mesh.Triangles.size() >= LongChartTriangles && TooLong(map.UV, atlasOptions.MaximumChartAspect)))
  {
    return false;
  }
  const DistortionReport distortion = atlasOptions.MeasureDistortion
    ? MeasureDistortion(chartTopology, local.data(), map.UV.data(), 1)
    : DistortionReport();
  chart.Triangles = std::move(mesh.Triangles);
  chart.Vertices = std::move(mesh.Vertices);
  chart.Corners = std::move(mesh.Corners);
  chart.UV = std::move(map.UV);
  chart.Area3D = TotalArea3D(chartTopology, local.data(), 1);
  chart.MeanAngleDistortion = distortion.MeanAngle;
  chart.MeanAreaDistortion = distortion.MeanArea;
  return true;
}

/// A chart's rectangle for the packing: its map's bounding box at the scale
/// that gives its map its 3D area.
struct Box
{
  double MinU = 0, MinV = 0, Width = 0, Height = 0, Scale = 1;
  double X = 0, Y = 0; ///< where it goes (lower left corner, gap included)
};

Box BoxOf(const AtlasChart& chart)
{
  Box box;
  const std::array<double, 4> bounds = BoundsOf(chart.UV);
  box.MinU = bounds[0];
  box.MinV = bounds[1];
  const double maxU = bounds[2], maxV = bounds[3];
  double area2D = 0.0;
  for (std::size_t t = 0; t < chart.Corners.size() / 3; ++t)
  {
    const double* a = &chart.UV[2 * chart.Corners[3 * t]];
    const double* b = &chart.UV[2 * chart.Corners[3 * t + 1]];
    const double* c = &chart.UV[2 * chart.Corners[3 * t + 2]];
    area2D += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
  }
  box.Scale = area2D > 0.0 ? std::sqrt(chart.Area3D / area2D) : 1.0;
  box.Width = box.Scale * (maxU - box.MinU);
  box.Height = box.Scale * (maxV - box.MinV);
  return box;
}

/// Shelf packing of the boxes (each grown by `gap`) in rows at most `rowWidth`
/// wide, tallest first; returns the side of the square that holds them.
double Shelves(std::vector<Box>& boxes, const std::vector<std::size_t>& order, double rowWidth, double gap)
{
  double x = 0.0, y = 0.0, rowHeight = 0.0, width = 0.0;
  for (std::size_t k : order)
  {
    Box& b = boxes[k];
    if (x > 0.0 && x + b.Width + gap > rowWidth)
    {
      y += rowHeight;
      x = rowHeight = 0.0;
    }
    b.X = x;
    b.Y = y;
    x += b.Width + gap;
    rowHeight = std::max(rowHeight, b.Height + gap);
    width = std::max(width, x);
  }
  return std::max(width, y + rowHeight);
}

/// Packs the charts into [0, 1]^2 (Offset, Scale of every chart): the best of
/// a few row widths, with a gap of MarginTexels; returns the packing efficiency.
double PackCharts(std::vector<AtlasChart>& charts, const AtlasOptions& options)
{
  std::vector<Box> boxes;
  double area = 0.0, widest = 0.0;
  for (const AtlasChart& chart : charts)
  {
    boxes.push_back(BoxOf(chart));
    area += boxes.back().Width * boxes.back().Height;
    widest = std::max(widest, boxes.back().Width);
  }
  std::vector<std::size_t> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return boxes[a].Height > boxes[b].Height; });
  const double margin = options.MarginTexels / std::max(1, options.TextureSize); // in [0, 1]^2 units
  // The gap between charts depends on the final scale: pack, measure, pack
  // again with the gap that scale needs, until the gap is at least the margin.
  double gap = 0.0, rowWidth = widest, side = 0.0, fit = 1.0;
  for (int pass = 0; pass < 8; ++pass)
  {
    double best = HUGE_VAL;
    for (double f = 1.0; f <= 1.6; f += 0.05)
    {
      const double width = std::max(widest + gap, f * std::sqrt(area));
      const double s = Shelves(boxes, order, width, gap);
      if (s < best)
      {
        best = s;
        rowWidth = width;
      }
    }
    side = Shelves(boxes, order, rowWidth, gap);
    fit = (1.0 - margin) / side; // the last chart ends a margin before 1
    if (fit * gap >= margin * (1.0 - 1e-9))
    {
      break;
    }
    gap = std::max(gap * 1.01, margin / fit);
  }
  double efficiency = 0.0;
  for (std::size_t k = 0; k < charts.size(); ++k)
  {
    const Box& b = boxes[k];
    charts[k].Scale = fit * b.Scale;
    charts[k].Offset[0] = fit * (b.X + gap) - charts[k].Scale * b.MinU;
    charts[k].Offset[1] = fit * (b.Y + gap) - charts[k].Scale * b.MinV;
    efficiency += fit * fit * charts[k].Area3D;
  }
  return efficiency;
}

/// Maps every region; a region whose map fails or flips is split (into
/// disks) and its parts mapped again.  False with `error` on a failure that
/// splitting cannot cure.
bool MapAllCharts(const MeshTopology& topology, const double* points, const DualGraph& graph,
  std::vector<ChartMesh> regions, const AtlasOptions& options, const ProgressCallback& progress,
  AtlasResult& result)
{
  const SingleThreadedBlas blas; // the charts run in parallel: no BLAS threads within
  while (!regions.empty())
  {
    std::vector<AtlasChart> round(regions.size());
    std::vector<std::uint8_t> mapped(regions.size(), 0);
    const bool completed = ParallelFor(static_cast<std::int64_t>(regions.size()), options.NumberOfThreads,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t k = begin; k < end; ++k)
        {
          mapped[k] = MapChart(regions[k], points, options, round[k]) ? 1 : 0;
        }
      },
      progress, 0, 1);
    if (!completed)
    {
      result.Completed = false;
      return false;
    }
    std::vector<ChartMesh> again;
    for (std::size_t k = 0; k < regions.size(); ++k)
    {
      if (mapped[k])
      {
        result.Charts.push_back(std::move(round[k]));
        continue;
      }
      std::vector<std::vector<Index>> halves = SplitRegion(graph, regions[k].Triangles);
      if (halves[1].empty())
      {
        result.Error =
          "The map of a single triangle failed (degenerate triangle " + std::to_string(regions[k].Triangles[0]) + ")";
        return false;
      }
      ++result.SplitsForFlips;
      for (std::vector<Index>& half : halves)
      {
        if (!SplitIntoDisks(topology, graph, std::move(half), again, result.Error))
        {
          return false;
        }
      }
    }
    regions = std::move(again);
  }
  std::sort(result.Charts.begin(), result.Charts.end(),
    [](const AtlasChart& a, const AtlasChart& b) { return a.Triangles.front() < b.Triangles.front(); });
  return true;
}

} // namespace

AtlasResult BuildAtlas(const MeshTopology& topology, const double* points, const AtlasOptions& options,
  const ProgressCallback& progress)
{
  AtlasResult result;
  const Index nt = topology.NumberOfTriangles();
  if (nt == 0)
  {
    result.Error = "The surface has no triangles";
    return result;
  }
  result.Error = CoordinateRangeProblem(topology, points);
  if (!result.Error.empty())
  {
    return result;
  }
  if (!options.SeamLabels.empty() && options.SeamLabels.size() != static_cast<std::size_t>(nt))
  {
    result.Error = "The seam labels have " + std::to_string(options.SeamLabels.size()) + " values for " +
      std::to_string(nt) + " triangles";
    return result;
  }
  std::vector<std::uint8_t> cut;
  if (options.SplitAtFeatures)
  {
    result.FeatureEdges = SharpEdges(topology, points, options.FeatureAngle);
    BridgeFeatureGaps(topology, points, 0.5 * options.FeatureAngle, options.LongestFeatureGap, result.FeatureEdges);
    DropShortFeatureChains(topology, points, options.MinimumFeatureLength, result.FeatureEdges);
    if (options.MostFeatureTurn > 0.0)
    {
      ExtendFeatureEnds(topology, points, 0.5 * options.FeatureAngle, options.MostFeatureTurn, result.FeatureEdges);
    }
    cut = result.FeatureEdges;
  }
  if (!options.SeamLabels.empty())
  {
    const std::vector<std::uint8_t> seams = EdgesBetweenLabels(topology, options.SeamLabels);
    cut.resize(seams.size(), 0);
    std::transform(cut.begin(), cut.end(), seams.begin(), cut.begin(), [](std::uint8_t a, std::uint8_t b) { return a | b; });
  }
  result.CutEdges = std::count(cut.begin(), cut.end(), std::uint8_t(1));
  const DualGraph graph(topology, points, cut.empty() ? nullptr : &cut);
  int count = options.NumberOfCharts > 0 ? options.NumberOfCharts : std::max(1, nt / TrianglesPerChart);
  if (options.MaximumChartArea > 0.0) // start from enough charts (better shapes than halving large ones)
  {
    const double total = std::accumulate(graph.Areas.begin(), graph.Areas.end(), 0.0);
    count = std::max<double>(count, std::min<double>(nt, std::ceil(total / options.MaximumChartArea)));
  }
  std::vector<ChartMesh> regions;
  int oversized = 0;
  if (!PartitionIntoCharts(
        topology, graph, count, regions, result.Error, options.BalanceAreas, options.NumberOfThreads) ||
    (options.MaximumChartArea > 0.0 &&
      !SplitLargeCharts(
        topology, graph, regions, options.MaximumChartArea, result.Error, oversized, options.NumberOfThreads)) ||
    !MapAllCharts(topology, points, graph, std::move(regions), options, progress, result))
  {
    result.Charts.clear();
    return result;
  }
  if (oversized > 0)
  {
    result.Warning = std::to_string(oversized) + " triangle(s) are larger than the maximum chart area on their own";
  }
  result.ChartOfTriangle.assign(nt, -1);
  for (std::size_t c = 0; c < result.Charts.size(); ++c)
  {
    for (Index t : result.Charts[c].Triangles)
    {
      result.ChartOfTriangle[t] = static_cast<int>(c);
    }
  }
  result.PackingEfficiency = PackCharts(result.Charts, options);
  return result;
}

} // namespace beltrami
