// The atlas of thesis section 4.2 (Maps/ChartPartition, Maps/Atlas): every
// triangle in one disk-like chart, no flipped triangle, charts inside their
// squares and packed without overlap, on surfaces of genus 0, 1 and 2,
// closed, open, with sharp edges and with several components.
#include "Maps/Atlas.h"
#include "Maps/ChartPartition.h"
#include "Maps/Distortion.h"
#include "Maps/GeometryImages.h"
#include "Mesh/MeshMeasures.h"
#include "Maps/MeshWithAtlas.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace beltrami;
using beltrami::test::Mesh;

namespace
{

/// Two meshes as one (the second's vertex ids shifted).
Mesh Join(const Mesh& a, const Mesh& b)
{
  Mesh m = a;
  const Index shift = a.NumberOfVertices();
  m.Points.insert(m.Points.end(), b.Points.begin(), b.Points.end());
  for (Index v : b.Triangles)
  {
    m.Triangles.push_back(v + shift);
  }
  return m;
}

/// Checks everything an atlas promises; returns the largest chart area over
/// the smallest (for the report).
void ExpectValidAtlas(const Mesh& mesh, const AtlasResult& atlas, const char* name)
{
  ASSERT_EQ(atlas.Error, "") << name;
  const MeshTopology topology = mesh.Topology();
  ASSERT_EQ(atlas.ChartOfTriangle.size(), static_cast<std::size_t>(topology.NumberOfTriangles()));
  std::vector<int> seen(topology.NumberOfTriangles(), 0);
  double surfaceArea = 0.0, largest = 0.0, smallest = HUGE_VAL;
  std::vector<std::array<double, 4>> boxes;
  for (std::size_t c = 0; c < atlas.Charts.size(); ++c)
  {
    const AtlasChart& chart = atlas.Charts[c];
    for (Index t : chart.Triangles)
    {
      ++seen[t];
      ASSERT_EQ(atlas.ChartOfTriangle[t], static_cast<int>(c));
    }
    ChartMesh piece = ExtractChart(topology, chart.Triangles);
    std::string why;
    EXPECT_TRUE(IsDisk(piece, &why)) << name << " chart " << c << ": " << why;
    const MeshTopology local(static_cast<Index>(chart.Vertices.size()), chart.Corners, 1);
    std::vector<double> points(3 * chart.Vertices.size());
    for (std::size_t v = 0; v < chart.Vertices.size(); ++v)
    {
      for (int k = 0; k < 3; ++k)
      {
        points[3 * v + k] = mesh.Points[3 * chart.Vertices[v] + k];
      }
    }
    EXPECT_EQ(CountFlipped(local, points.data(), chart.UV.data()), 0) << name << " chart " << c;
    std::array<double, 4> box = { HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (std::size_t v = 0; v < chart.Vertices.size(); ++v)
    {
      EXPECT_GE(chart.UV[2 * v], -1e-12);
      EXPECT_LE(chart.UV[2 * v + 1], 1.0 + 1e-12);
      double uv[2];
      AtlasUV(chart, static_cast<Index>(v), uv);
      box = { std::min(box[0], uv[0]), std::min(box[1], uv[1]), std::max(box[2], uv[0]), std::max(box[3], uv[1]) };
    }
    EXPECT_GE(box[0], 0.0);
    EXPECT_GE(box[1], 0.0);
    EXPECT_LE(box[2], 1.0);
    EXPECT_LE(box[3], 1.0);
    boxes.push_back(box);
    surfaceArea += chart.Area3D;
    largest = std::max(largest, chart.Area3D);
    smallest = std::min(smallest, chart.Area3D);
  }
  for (int count : seen)
  {
    ASSERT_EQ(count, 1) << name << ": every triangle in exactly one chart";
  }
  // Packed charts do not overlap: their boxes are at least the margin apart.
  for (std::size_t i = 0; i < boxes.size(); ++i)
  {
    for (std::size_t j = i + 1; j < boxes.size(); ++j)
    {
      const bool apart = boxes[i][2] < boxes[j][0] || boxes[j][2] < boxes[i][0] || boxes[i][3] < boxes[j][1] ||
        boxes[j][3] < boxes[i][1];
      ASSERT_TRUE(apart) << name << ": charts " << i << " and " << j << " overlap";
    }
  }
  EXPECT_NEAR(surfaceArea, mesh.TotalArea(), 1e-9 * mesh.TotalArea());
  EXPECT_GT(atlas.PackingEfficiency, 0.2) << name; // reported, not a target here (bounding-box shelves)
  EXPECT_LT(atlas.PackingEfficiency, 1.0) << name;
  const auto squares = std::count_if(atlas.Charts.begin(), atlas.Charts.end(),
    [](const AtlasChart& c) { return c.Boundary == ParameterizationBoundary::Square; });
  std::printf("%s: %zu charts (%ld on squares, %d split for flips), areas %.3g..%.3g, packing %.1f%%\n", name,
    atlas.Charts.size(), static_cast<long>(squares), atlas.SplitsForFlips, smallest, largest,
    100.0 * atlas.PackingEfficiency);
}

/// The unit square on an n x n grid (two triangles a cell), lifted to the
/// height z(x, y).
template <typename Height>
Mesh HeightGrid(int n, Height&& z)
{
  Mesh grid;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      const double x = double(i) / n, y = double(j) / n;
      grid.AddPoint(Eigen::Vector3d(x, y, z(x, y)));
    }
  }
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < n; ++j)
    {
      const Index a = i * (n + 1) + j, b = a + n + 1;
      grid.AddTriangle(a, b, b + 1);
      grid.AddTriangle(a, b + 1, a + 1);
    }
  }
  return grid;
}

} // namespace

TEST(Atlas, ClosedSurfacesOfGenusZeroOneAndTwo)
{
  const Mesh sphere = test::OctahedronSphere(4);
  const Mesh torus = test::Torus(2.0, 0.7, 48, 24, 0.2, 5);
  std::string error;
  const Mesh eight = test::ReadMesh("eight.off", error);
  ASSERT_EQ(error, "");
  const Mesh fandisk = test::ReadMesh("fandisk.off", error); // sharp edges
  ASSERT_EQ(error, "");
  for (const auto& [mesh, name] : { std::make_pair(&sphere, "sphere"), std::make_pair(&torus, "torus"),
         std::make_pair(&eight, "genus 2"), std::make_pair(&fandisk, "fandisk") })
  {
    const MeshTopology topology = mesh->Topology();
    ExpectValidAtlas(*mesh, BuildAtlas(topology, mesh->Points.data()), name);
  }
}

TEST(Atlas, OpenSurfacesSeveralComponentsAndChartCounts)
{
  std::string error;
  const Mesh mushroom = test::ReadMesh("mushroom.off", error);
  ASSERT_EQ(error, "");
  const Mesh both = Join(mushroom, test::Torus(2.0, 0.5, 30, 12, 0.0, 1));
  const MeshTopology topology = both.Topology();
  for (int charts : { 1, 8, 40 })
  {
    AtlasOptions options;
    options.NumberOfCharts = charts;
    const AtlasResult atlas = BuildAtlas(topology, both.Points.data(), options);
    ExpectValidAtlas(both, atlas, ("mushroom + torus, " + std::to_string(charts) + " charts").c_str());
    EXPECT_GE(atlas.Charts.size(), static_cast<std::size_t>(std::max(charts, 3))); // a torus needs 2 or more
  }
}

TEST(Atlas, BadInputIsAnErrorNotACrash)
{
  Mesh nonManifold = test::OctahedronSphere(1);
  nonManifold.AddTriangle(0, 1, nonManifold.AddPoint({ 3.0, 3.0, 3.0 })); // a fin on an edge
  nonManifold.AddTriangle(0, 1, nonManifold.AddPoint({ -3.0, 3.0, 3.0 }));
  const MeshTopology fins = nonManifold.Topology();
  EXPECT_NE(BuildAtlas(fins, nonManifold.Points.data()).Error, "");

  Mesh nan = test::OctahedronSphere(2);
  nan.Points[4] = std::nan("");
  const MeshTopology nanTopology = nan.Topology();
  const AtlasResult withNaN = BuildAtlas(nanTopology, nan.Points.data());
  EXPECT_NE(withNaN.Error, "");
  EXPECT_TRUE(withNaN.Charts.empty());

  const MeshTopology empty(0, IndexArray(), 1);
  EXPECT_NE(BuildAtlas(empty, nullptr).Error, "");
}

TEST(GeometryImages, EmbeddingAreaAndVertexValuesOfEveryChart)
{
  const test::MeshWithAtlas loaded("eight.off");
  ASSERT_EQ(loaded.Error, "");
  const Mesh& eight = loaded.Surface;
  const AtlasResult& atlas = loaded.Atlas;
  double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (Index v = 0; v < eight.NumberOfVertices(); ++v)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], eight.Points[3 * v + k]);
      hi[k] = std::max(hi[k], eight.Points[3 * v + k]);
    }
  }
  const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  double worstPosition = 0.0, worstArea = 0.0, worstVertex = 0.0;
  const int n = 512;
  for (const AtlasChart& chart : atlas.Charts)
  {
    std::vector<double> positions(3 * chart.Vertices.size());
    for (std::size_t v = 0; v < chart.Vertices.size(); ++v)
    {
      std::copy_n(&eight.Points[3 * chart.Vertices[v]], 3, &positions[3 * v]);
    }
    const ChartRaster raster = RasterizeChart(chart, n, 2);
    std::vector<double> embedding(3 * raster.Face.size());
    InterpolateOnRaster(raster, chart, positions.data(), 3, embedding.data(), true);
    // The embedding map against the face found anew at every 7th pixel centre.
    for (std::size_t p = 0; p < raster.Face.size(); p += 7)
    {
      const double centre[2] = { (p % n + 0.5) / n, (p / n + 0.5) / n };
      double w[3];
      const Index t = LocateInChart(chart, centre, w);
      ASSERT_EQ(t < 0, raster.Face[p] < 0) << "pixel " << p;
      for (int k = 0; t >= 0 && k < 3; ++k)
      {
        double x = 0.0;
        for (int c = 0; c < 3; ++c)
        {
          x += w[c] * positions[3 * chart.Corners[3 * t + c] + k];
        }
        worstPosition = std::max(worstPosition, std::abs(x - embedding[3 * p + k]) / diagonal);
      }
    }
    // The area map integrates to the chart's area.
    std::vector<double> area(raster.Face.size());
    AreaMap(raster, chart, eight.Points.data(), area.data());
    double integral = 0.0;
    for (double a : area)
    {
      integral += std::isnan(a) ? 0.0 : a / (double(n) * n);
    }
    worstArea = std::max(worstArea, std::abs(integral - chart.Area3D) / chart.Area3D);
    // Interpolated values at a vertex's own UV are its values.
    for (std::size_t v = 0; v < chart.Vertices.size(); ++v)
    {
      double w[3];
      const Index t = LocateInChart(chart, &chart.UV[2 * v], w);
      ASSERT_GE(t, 0);
      double x = 0.0;
      for (int c = 0; c < 3; ++c)
      {
        x += w[c] * positions[3 * chart.Corners[3 * t + c]];
      }
      worstVertex = std::max(worstVertex, std::abs(x - positions[3 * v]) / diagonal);
    }
  }
  std::printf("geometry images of genus 2 at %d^2: position %.2e, area %.2e, vertex %.2e\n", n, worstPosition,
    worstArea, worstVertex);
  EXPECT_LT(worstPosition, 1e-6);
  // Sampling: a triangle squeezed in the map (large area ratio, a few
  // pixels) is hit or missed whole: 8.6e-4 here (1.3e-3 with the area
  // balancing, whose longer charts squeeze their corners more).
  EXPECT_LT(worstArea, 1e-3);
  EXPECT_LT(worstVertex, 1e-12);
}

TEST(GeometryImages, PackedAtlasSamplesTheWholeSurfaceOnce)
{
  const test::MeshWithAtlas loaded("eight.off");
  ASSERT_EQ(loaded.Error, "");
  const Mesh& eight = loaded.Surface;
  const MeshTopology& topology = loaded.Topology;
  const AtlasResult& atlas = loaded.Atlas;
  const AtlasChart packed = PackedAtlas(atlas);
  // Every surface triangle once, every corner on its chart's surface vertex.
  std::vector<Index> triangles = packed.Triangles;
  std::sort(triangles.begin(), triangles.end());
  ASSERT_EQ(static_cast<Index>(triangles.size()), topology.NumberOfTriangles());
  for (Index t = 0; t < topology.NumberOfTriangles(); ++t)
  {
    ASSERT_EQ(triangles[t], t);
  }
  for (std::size_t t = 0; t < packed.Triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(packed.Vertices[packed.Corners[3 * t + k]], topology.CornerVertex(3 * packed.Triangles[t] + k));
    }
  }
  // The texels of the packed atlas: pixels in the chart of their triangle
  // (the charts do not overlap), the area map summing to the surface's area.
  const int n = 1024;
  const ChartRaster raster = RasterizeChart(packed, n, 2);
  std::vector<double> area(raster.Face.size());
  AreaMap(raster, packed, eight.Points.data(), area.data());
  double integral = 0.0, total = 0.0;
  std::size_t inside = 0, wrongChart = 0;
  for (std::size_t p = 0; p < raster.Face.size(); ++p)
  {
    integral += std::isnan(area[p]) ? 0.0 : area[p] / (double(n) * n);
    if (raster.Face[p] < 0)
    {
      continue;
    }
    ++inside;
    const AtlasChart& chart = atlas.Charts[atlas.ChartOfTriangle[packed.Triangles[raster.Face[p]]]];
    const double uv[2] = { ((p % n + 0.5) / n - chart.Offset[0]) / chart.Scale,
      ((p / n + 0.5) / n - chart.Offset[1]) / chart.Scale };
    double w[3];
    wrongChart += LocateInChart(chart, uv, w) < 0;
  }
  for (const AtlasChart& chart : atlas.Charts)
  {
    total += chart.Area3D;
  }
  EXPECT_NEAR(packed.Area3D, total, 1e-12 * total);
  std::printf("packed atlas of genus 2 at %d^2: %zu texels inside (%.1f%%), area %.2e\n", n, inside,
    100.0 * inside / (double(n) * n), std::abs(integral - total) / total);
  EXPECT_GT(inside, static_cast<std::size_t>(0.5 * atlas.PackingEfficiency * n * n));
  EXPECT_EQ(wrongChart, 0u);
  EXPECT_LT(std::abs(integral - total) / total, 3e-3);
}

TEST(Atlas, AreaBalancedRefinementEvensTheCharts)
{
  // Section 4.2.4 on meshes with long protrusions (the elephant's trunk and
  // legs, the bunny's ears): the largest chart over the smallest, with and
  // without the refinement.
  for (const char* name : { "elephant.off", "bunny00.off" })
  {
    std::string error;
    const Mesh mesh = test::ReadMesh(name, error);
    ASSERT_EQ(error, "");
    const MeshTopology topology = mesh.Topology();
    double spread[2] = { 0.0, 0.0 };
    for (const bool balance : { false, true })
    {
      AtlasOptions options;
      options.NumberOfCharts = 24;
      options.BalanceAreas = balance;
      const AtlasResult atlas = BuildAtlas(topology, mesh.Points.data(), options);
      ExpectValidAtlas(mesh, atlas, name);
      double largest = 0.0, smallest = HUGE_VAL;
      for (const AtlasChart& chart : atlas.Charts)
      {
        largest = std::max(largest, chart.Area3D);
        smallest = std::min(smallest, chart.Area3D);
      }
      spread[balance] = largest / smallest;
    }
    std::printf("%s: largest / smallest chart %.2f unbalanced, %.2f balanced\n", name, spread[0], spread[1]);
    EXPECT_LT(spread[1], 8.0);             // the bound: no chart 8 times another's area
    EXPECT_LT(3.0 * spread[1], spread[0]); // and at least 3 times more even than without
  }
}

TEST(Atlas, NaturalConformalChartsHaveLessAngleDistortion)
{
  std::string error;
  const Mesh bunny = test::ReadMesh("bunny00.off", error);
  ASSERT_EQ(error, "");
  const MeshTopology topology = bunny.Topology();
  double distortion[2] = { 0.0, 0.0 };
  for (const auto boundary : { ParameterizationBoundary::Square, ParameterizationBoundary::Natural })
  {
    AtlasOptions options;
    options.ChartBoundary = boundary;
    const AtlasResult atlas = BuildAtlas(topology, bunny.Points.data(), options);
    ExpectValidAtlas(bunny, atlas, boundary == ParameterizationBoundary::Natural ? "bunny, natural" : "bunny, square");
    double weighted = 0.0, area = 0.0;
    for (const AtlasChart& chart : atlas.Charts)
    {
      weighted += chart.MeanAngleDistortion * chart.Area3D;
      area += chart.Area3D;
    }
    distortion[boundary == ParameterizationBoundary::Natural] = weighted / area;
    if (boundary == ParameterizationBoundary::Square)
    {
      // Corners at the sharpest turns and smoothed split boundaries: charts
      // stay on their squares (no triangle flat on a side), which fill their
      // boxes (before: 0-20% of the charts on squares, packing 71%).
      const auto squares = std::count_if(atlas.Charts.begin(), atlas.Charts.end(),
        [](const AtlasChart& c) { return c.Boundary == ParameterizationBoundary::Square; });
      EXPECT_GE(squares, static_cast<long>(0.9 * atlas.Charts.size()));
      EXPECT_GT(atlas.PackingEfficiency, 0.85);
    }
  }
  std::printf("bunny: mean angle distortion %.2f deg on squares, %.2f deg natural\n", distortion[0], distortion[1]);
  EXPECT_LT(distortion[1], 1.0);
  EXPECT_LT(10.0 * distortion[1], distortion[0]);
}

TEST(Atlas, HolesZeroAreaTrianglesAndIsolatedPoints)
{
  // A flat grid with two square holes (three boundary loops), a zero-area
  // triangle (three points on a line, glued in at a corner) and an isolated
  // point: every triangle still in one disk-like chart, no flip.
  Mesh grid;
  const int n = 20;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      grid.AddPoint({ i * 0.1, j * 0.1, 0.02 * std::sin(i * 0.7) * std::cos(j * 0.5) });
    }
  }
  const auto id = [n](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const bool hole = (i >= 4 && i < 7 && j >= 4 && j < 7) || (i >= 12 && i < 16 && j >= 10 && j < 13);
      if (!hole)
      {
        grid.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        grid.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  }
  const Index a = grid.AddPoint({ -0.1, 0.0, 0.0 }); // on the line through (0,0) and (0.1,0)
  grid.AddTriangle(id(1, 0), id(0, 0), a);          // zero area: a, (0,0), (0.1,0) are collinear
  grid.AddPoint({ 5.0, 5.0, 5.0 });                 // isolated
  const MeshTopology topology = grid.Topology();
  ASSERT_EQ(topology.BoundaryLoops().size(), 3u);
  for (const auto boundary : { ParameterizationBoundary::Square, ParameterizationBoundary::Natural })
  {
    AtlasOptions options;
    options.ChartBoundary = boundary;
    options.NumberOfCharts = 3;
    const AtlasResult atlas = BuildAtlas(topology, grid.Points.data(), options);
    ExpectValidAtlas(
      grid, atlas, boundary == ParameterizationBoundary::Square ? "grid with holes, square" : "grid with holes, natural");
  }
}

namespace
{

/// The edges of `cut` whose two triangles lie in one chart.
int CutEdgesInsideCharts(const MeshTopology& topology, const std::vector<std::uint8_t>& cut, const AtlasResult& atlas)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  int inside = 0;
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
    inside += cut[e] && atlas.ChartOfTriangle[c0 / 3] == atlas.ChartOfTriangle[c1 / 3];
  }
  return inside;
}

} // namespace

TEST(Atlas, SeamsAndSharpEdgesAreChartBoundaries)
{
  std::string error;
  // Sharp edges (section 4.2.3): fandisk's creases, some ending inside smooth regions.
  for (const char* name : { "fandisk.off", "elephant.off" })
  {
    const Mesh mesh = test::ReadMesh(name, error);
    ASSERT_EQ(error, "");
    const MeshTopology topology = mesh.Topology();
    AtlasOptions options;
    options.SplitAtFeatures = true;
    const AtlasResult atlas = BuildAtlas(topology, mesh.Points.data(), options);
    ExpectValidAtlas(mesh, atlas, name);
    const std::vector<std::uint8_t> sharp = SharpEdges(topology, mesh.Points.data(), options.FeatureAngle);
    EXPECT_GT(atlas.CutEdges, 100) << name;
    EXPECT_EQ(atlas.CutEdges, std::count(sharp.begin(), sharp.end(), std::uint8_t(1))) << name;
    EXPECT_EQ(CutEdgesInsideCharts(topology, sharp, atlas), 0) << name;
    const AtlasResult plain = BuildAtlas(topology, mesh.Points.data());
    EXPECT_GT(CutEdgesInsideCharts(topology, sharp, plain), 0) << name << ": charts cross sharp edges by default";
    std::printf("%s: %zu charts keeping %lld sharp edges on their boundaries (%zu without)\n", name,
      atlas.Charts.size(), static_cast<long long>(atlas.CutEdges), plain.Charts.size());
  }
  // User seams: labels of a segmentation (a polar cap and two half-spheres).
  const Mesh sphere = test::OctahedronSphere(5);
  const MeshTopology topology = sphere.Topology();
  AtlasOptions options;
  for (Index t = 0; t < topology.NumberOfTriangles(); ++t)
  {
    const Index* v = &topology.TriangleList()[3 * t];
    const Eigen::Vector3d c = (sphere.Point(v[0]) + sphere.Point(v[1]) + sphere.Point(v[2])) / 3.0;
    options.SeamLabels.push_back(c.z() > 0.5 ? 2 : (c.x() > 0.0 ? 1 : 0));
  }
  const AtlasResult atlas = BuildAtlas(topology, sphere.Points.data(), options);
  ExpectValidAtlas(sphere, atlas, "sphere with seams");
  const std::vector<std::uint8_t> seams = EdgesBetweenLabels(topology, options.SeamLabels);
  EXPECT_GT(atlas.CutEdges, 50);
  EXPECT_EQ(CutEdgesInsideCharts(topology, seams, atlas), 0);
  for (const AtlasChart& chart : atlas.Charts) // no chart spans two labels
  {
    for (Index t : chart.Triangles)
    {
      EXPECT_EQ(options.SeamLabels[t], options.SeamLabels[chart.Triangles.front()]);
    }
  }
  options.SeamLabels.pop_back();
  EXPECT_NE(BuildAtlas(topology, sphere.Points.data(), options).Error, "") << "one label short";
}

TEST(Atlas, FeatureFragmentsShorterThanTheLengthAsked)
{
  // A cube of side 2 in cells of 1/4: its 12 edges (closed lines, 96 sharp
  // edges) with a dangling line of 3 cells from an edge into the top face
  // and a free segment of 2 cells on it.
  const Mesh cube = test::CubeSurface(8);
  const MeshTopology topology = cube.Topology();
  const auto vertexAt = [&](double x, double y, double z) {
    for (Index v = 0; v < topology.NumberOfVertices(); ++v)
    {
      if ((cube.Point(v) - Eigen::Vector3d(x, y, z)).norm() < 1e-9)
      {
        return v;
      }
    }
    return Index(-1);
  };
  const std::vector<std::uint8_t> sharp = SharpEdges(topology, cube.Points.data(), 60.0);
  ASSERT_EQ(std::count(sharp.begin(), sharp.end(), std::uint8_t(1)), 96);
  std::vector<std::uint8_t> marked = sharp;
  const auto mark = [&](std::initializer_list<double> xs, double y) {
    for (auto x = xs.begin(); x + 1 != xs.end(); ++x)
    {
      const std::int64_t e = topology.Edges().Find(vertexAt(*x, y, 1.0), vertexAt(*(x + 1), y, 1.0));
      ASSERT_GE(e, 0);
      marked[e] = 1;
    }
  };
  mark({ 1.0, 0.75, 0.5, 0.25 }, 0.0);
  mark({ -0.5, -0.25, 0.0 }, -0.5);
  const auto count = [](const std::vector<std::uint8_t>& f) { return std::count(f.begin(), f.end(), std::uint8_t(1)); };
  for (const auto& [length, dropped] : { std::pair<double, int>(0.0, 0), { 0.4, 0 }, { 0.6, 2 }, { 0.8, 5 } })
  {
    std::vector<std::uint8_t> features = marked;
    EXPECT_EQ(DropShortFeatureChains(topology, cube.Points.data(), length, features), dropped) << length;
    EXPECT_EQ(count(features), 101 - dropped) << length;
    if (dropped == 5)
    {
      EXPECT_EQ(features, sharp) << "the cube's closed edges stay";
    }
  }
  // The coarse elephant's sharp edges are mostly fragments (146 ends), each
  // splitting its chart.  Kept only where longer than the spacing of 2,000
  // vertices, the atlas has every kept line on its charts' boundaries, no
  // fragment left, and fewer charts.
  std::string error;
  const Mesh elephant = test::ReadMesh("elephant.off", error);
  ASSERT_EQ(error, "");
  const MeshTopology surface = elephant.Topology();
  AtlasOptions options;
  options.SplitAtFeatures = true;
  const AtlasResult all = BuildAtlas(surface, elephant.Points.data(), options);
  options.MinimumFeatureLength =
    std::sqrt(2.0 * SurfaceArea(surface, elephant.Points.data()) / (std::sqrt(3.0) * 2000));
  const AtlasResult kept = BuildAtlas(surface, elephant.Points.data(), options);
  ExpectValidAtlas(elephant, kept, "elephant");
  EXPECT_EQ(all.CutEdges, count(SharpEdges(surface, elephant.Points.data(), 60.0)));
  EXPECT_EQ(all.FeatureEdges, SharpEdges(surface, elephant.Points.data(), 60.0));
  EXPECT_EQ(kept.CutEdges, count(kept.FeatureEdges));
  EXPECT_LT(kept.CutEdges, all.CutEdges);
  EXPECT_EQ(CutEdgesInsideCharts(surface, kept.FeatureEdges, kept), 0);
  std::vector<std::uint8_t> again = kept.FeatureEdges;
  EXPECT_EQ(DropShortFeatureChains(surface, elephant.Points.data(), options.MinimumFeatureLength, again), 0);
  EXPECT_LT(kept.Charts.size(), all.Charts.size());
  std::printf("elephant: %zu charts keeping %lld sharp edges (%zu charts, %lld edges with every fragment)\n",
    kept.Charts.size(), static_cast<long long>(kept.CutEdges), all.Charts.size(), static_cast<long long>(all.CutEdges));
}

TEST(Atlas, CreaseFragmentsJoined)
{
  // A roof on a 32 x 32 grid, its crease (a bend of 113 degrees) at 30
  // degrees to the grid's lines: the triangles it crosses share the bend,
  // so that only some of its edges are sharper than 60 degrees, in
  // fragments.  Joined along edges sharper than 30 degrees over gaps of up
  // to three cells, the crease is one line from border to border: no end
  // inside, no junction, every edge beside the crease.
  constexpr int n = 32;
  const double slant = M_PI / 6.0;
  const auto across = [&](double x, double y) {
    return x * std::sin(slant) - y * std::cos(slant) + 0.5 * (std::cos(slant) - std::sin(slant)) + 0.013;
  };
  const Mesh roof = HeightGrid(n, [&](double x, double y) { return 1.5 * std::abs(across(x, y)); });
  const MeshTopology topology = roof.Topology();
  const MeshTopology::EdgeTable& e = topology.Edges();
  // (vertices with one feature edge inside the grid, with three or more)
  const auto endsAndJunctions = [&](const std::vector<std::uint8_t>& features) {
    std::vector<int> degree(roof.NumberOfVertices(), 0);
    for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
    {
      degree[e.Vertices[2 * k]] += features[k];
      degree[e.Vertices[2 * k + 1]] += features[k];
    }
    int ends = 0, junctions = 0;
    for (Index v = 0; v < roof.NumberOfVertices(); ++v)
    {
      const Eigen::Vector3d p = roof.Point(v);
      ends += degree[v] == 1 && std::min({ p[0], p[1], 1.0 - p[0], 1.0 - p[1] }) > 1e-9;
      junctions += degree[v] > 2;
    }
    return std::pair<int, int>(ends, junctions);
  };
  std::vector<std::uint8_t> features = SharpEdges(topology, roof.Points.data(), 60.0);
  const auto [endsBefore, junctionsBefore] = endsAndJunctions(features);
  EXPECT_GE(endsBefore, 20);
  EXPECT_EQ(junctionsBefore, 0);
  std::vector<std::uint8_t> unchanged = features;
  EXPECT_EQ(BridgeFeatureGaps(topology, roof.Points.data(), 30.0, 0.0, unchanged), 0);
  EXPECT_EQ(unchanged, features);
  const std::int64_t added = BridgeFeatureGaps(topology, roof.Points.data(), 30.0, 3.0 / n, features);
  EXPECT_GT(added, 0);
  EXPECT_EQ(endsAndJunctions(features), std::make_pair(0, 0));
  for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
  {
    const Eigen::Vector3d middle = 0.5 * (roof.Point(e.Vertices[2 * k]) + roof.Point(e.Vertices[2 * k + 1]));
    EXPECT_TRUE(!features[k] || std::abs(across(middle[0], middle[1])) < 1.0 / n) << k;
  }
  std::printf(
    "roof: %d ends of crease fragments inside, %lld edges added\n", endsBefore, static_cast<long long>(added));
}

TEST(Atlas, CreasesThatFadeOutAreFollowed)
{
  // A roof on a 40 x 40 grid, z = s(x) |y - 1/2| with the slope s falling
  // from 1 at x = 0 to 0 at x = 1: its crease along y = 1/2 bends by
  // 2 atan(s), 90 degrees at x = 0, 60 at x = 0.42, 30 at x = 0.73.  The
  // edges sharper than 60 degrees stop at 0.42; continued along edges
  // sharper than 30 that turn the line by at most 30 degrees, the line
  // runs on to 0.73, on the crease only (the hysteresis of Canny's edge
  // detector).
  constexpr int n = 40;
  const Mesh roof = HeightGrid(n, [](double x, double y) { return (1.0 - x) * std::abs(y - 0.5); });
  const MeshTopology topology = roof.Topology();
  const MeshTopology::EdgeTable& e = topology.Edges();
  std::vector<std::uint8_t> features = SharpEdges(topology, roof.Points.data(), 60.0);
  // (the largest x of the crease's feature edges; none off the crease)
  const auto reach = [&](const std::vector<std::uint8_t>& f) {
    double farthest = 0.0;
    for (std::int64_t k = 0; k < e.NumberOfEdges(); ++k)
    {
      const Eigen::Vector3d a = roof.Point(e.Vertices[2 * k]), b = roof.Point(e.Vertices[2 * k + 1]);
      EXPECT_TRUE(!f[k] || (std::abs(a[1] - 0.5) < 1e-12 && std::abs(b[1] - 0.5) < 1e-12)) << k;
      farthest = f[k] ? std::max({ farthest, a[0], b[0] }) : farthest;
    }
    return farthest;
  };
  const double before = reach(features);
  EXPECT_NEAR(before, 0.42, 0.03);
  const std::int64_t added = ExtendFeatureEnds(topology, roof.Points.data(), 30.0, 30.0, features);
  EXPECT_NEAR(reach(features), 0.73, 0.03);
  EXPECT_EQ(added, std::lround((reach(features) - before) * n)); // (one edge a cell)
  // Extended again, nothing changes: the line's end is where the crease is
  // below 30 degrees.
  EXPECT_EQ(ExtendFeatureEnds(topology, roof.Points.data(), 30.0, 30.0, features), 0);
}

TEST(Atlas, CapsAndFoldsHaveNoSharpEdges)
{
  // A triangle folded back between its neighbours (its normal opposite
  // theirs): a fold of the input, whose normal means nothing, as a cap's
  // (its middle corner 0.01 off its long edge: 178.9 degrees) does not.
  for (const double offset : { 0.5, 0.01 })
  {
    Mesh fold;
    for (const Eigen::Vector3d& p : { Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0),
           Eigen::Vector3d(1, -offset, 0), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(1, -1, 0) })
    {
      fold.AddPoint(p);
    }
    fold.AddTriangle(0, 1, 2); // the folded one
    fold.AddTriangle(0, 2, 3);
    fold.AddTriangle(2, 1, 3);
    fold.AddTriangle(0, 4, 1);
    const MeshTopology topology = fold.Topology();
    const std::vector<std::uint8_t> sharp = SharpEdges(topology, fold.Points.data(), 60.0);
    EXPECT_EQ(std::count(sharp.begin(), sharp.end(), std::uint8_t(1)), 0) << offset;
  }
  // A knife edge (two triangles at 169 degrees, each turned at one edge
  // only) is sharp.
  Mesh knife;
  for (const Eigen::Vector3d& p :
    { Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(1, 1, 0.2) })
  {
    knife.AddPoint(p);
  }
  knife.AddTriangle(0, 1, 2);
  knife.AddTriangle(1, 0, 3);
  const std::vector<std::uint8_t> sharp = SharpEdges(knife.Topology(), knife.Points.data(), 60.0);
  EXPECT_EQ(std::count(sharp.begin(), sharp.end(), std::uint8_t(1)), 1);
}

TEST(Atlas, CapsInACreaseKeepTheCrease)
{
  // A right-angled crease along the x axis (one side in the plane z = 0,
  // the other in y = 0) with a cap lying in it, as decimation leaves them:
  // its middle corner 0.002 off the crease (179.7 degrees).  Its two short
  // edges are the crease, its long edge is not.
  Mesh crease;
  for (const Eigen::Vector3d& p : { Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, -0.001, 0.001),
         Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(1, 0, 1) })
  {
    crease.AddPoint(p);
  }
  crease.AddTriangle(0, 1, 2); // the cap
  crease.AddTriangle(1, 0, 3); // the side z = 0
  crease.AddTriangle(2, 1, 3);
  crease.AddTriangle(0, 2, 4); // the side y = 0, across the cap's long edge
  const MeshTopology topology = crease.Topology();
  const std::vector<std::uint8_t> sharp = SharpEdges(topology, crease.Points.data(), 60.0);
  const MeshTopology::EdgeTable& edges = topology.Edges();
  EXPECT_EQ(std::count(sharp.begin(), sharp.end(), std::uint8_t(1)), 2);
  EXPECT_EQ(sharp[edges.Find(0, 1)], 1);
  EXPECT_EQ(sharp[edges.Find(1, 2)], 1);
  EXPECT_EQ(sharp[edges.Find(0, 2)], 0);
}

TEST(Atlas, MaximumChartAreaIsKept)
{
  std::string error;
  const Mesh bunny = test::ReadMesh("bunny00.off", error);
  ASSERT_EQ(error, "");
  const MeshTopology topology = bunny.Topology();
  for (const double share : { 1.0 / 100, 1.0 / 400 })
  {
    AtlasOptions options;
    options.MaximumChartArea = share * bunny.TotalArea();
    options.NumberOfCharts = 10; // raised to the area over the limit
    const AtlasResult atlas = BuildAtlas(topology, bunny.Points.data(), options);
    ExpectValidAtlas(bunny, atlas, share > 0.005 ? "bunny, 1/100 of the area at most" : "bunny, 1/400 at most");
    EXPECT_GE(atlas.Charts.size(), 1.0 / share);
    EXPECT_EQ(atlas.Warning, "");
    for (const AtlasChart& chart : atlas.Charts)
    {
      EXPECT_LE(chart.Area3D, options.MaximumChartArea * (1 + 1e-12));
    }
  }
  // A limit below a triangle's area: every chart a single triangle, a warning.
  const Mesh sphere = test::OctahedronSphere(1);
  const MeshTopology coarse = sphere.Topology();
  AtlasOptions tiny;
  tiny.MaximumChartArea = 1e-3;
  const AtlasResult atlas = BuildAtlas(coarse, sphere.Points.data(), tiny);
  ExpectValidAtlas(sphere, atlas, "sphere, charts below a triangle");
  EXPECT_EQ(atlas.Charts.size(), static_cast<std::size_t>(coarse.NumberOfTriangles()));
  EXPECT_NE(atlas.Warning, "");
}

TEST(Atlas, LongStripsAreSplitToTheAspectAsked)
{
  // A twisted ribbon 1,000 times longer than wide: two charts whose maps'
  // boxes are 250 times longer than wide, packed into a square they leave
  // nearly empty (0.4% packing; the remesher's control map of it at 10,000
  // vertices, 8192^2 texels, took 1 GB).
  Mesh ribbon;
  const int along = 800, across = 4;
  for (int i = 0; i < along; ++i)
  {
    const double x = 10.0 * i / (along - 1), turn = 4.0 * 3.141592653589793 * x / 10.0;
    for (int j = 0; j < across; ++j)
    {
      const double y = 0.01 * (j / (across - 1.0) - 0.5);
      ribbon.Points.insert(ribbon.Points.end(), { x, y * std::cos(turn), y * std::sin(turn) });
    }
  }
  for (int i = 0; i + 1 < along; ++i)
  {
    for (int j = 0; j + 1 < across; ++j)
    {
      const Index a = i * across + j, b = a + across;
      ribbon.Triangles.insert(ribbon.Triangles.end(), { a, b, a + 1, a + 1, b, b + 1 });
    }
  }
  const MeshTopology topology = ribbon.Topology();
  const auto longest = [](const AtlasChart& chart) {
    double lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
    for (std::size_t k = 0; k < chart.UV.size(); ++k)
    {
      lo[k % 2] = std::min(lo[k % 2], chart.UV[k]);
      hi[k % 2] = std::max(hi[k % 2], chart.UV[k]);
    }
    return std::max(hi[0] - lo[0], hi[1] - lo[1]) / std::min(hi[0] - lo[0], hi[1] - lo[1]);
  };
  AtlasOptions options;
  options.ChartBoundary = ParameterizationBoundary::Natural;
  const AtlasResult whole = BuildAtlas(topology, ribbon.Points.data(), options);
  ASSERT_EQ(whole.Error, "");
  double worst = 0.0;
  for (const AtlasChart& chart : whole.Charts)
  {
    worst = std::max(worst, longest(chart));
  }
  EXPECT_GT(worst, 200.0);
  options.MaximumChartAspect = 100.0;
  const AtlasResult split = BuildAtlas(topology, ribbon.Points.data(), options);
  ASSERT_EQ(split.Error, "");
  std::vector<int> seen(topology.NumberOfTriangles(), 0);
  for (const AtlasChart& chart : split.Charts)
  {
    EXPECT_LE(longest(chart), 100.0);
    for (const Index t : chart.Triangles)
    {
      ++seen[t];
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), topology.NumberOfTriangles());
  EXPECT_GT(split.PackingEfficiency, 10.0 * whole.PackingEfficiency);
  std::printf("ribbon: %zu charts, longest %.0f:1, packing %.2f%%; at most 100:1: %zu charts, packing %.2f%%\n",
    whole.Charts.size(), worst, 100.0 * whole.PackingEfficiency, split.Charts.size(), 100.0 * split.PackingEfficiency);
}
