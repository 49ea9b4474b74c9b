// The remesher of thesis chapter 4 end to end: exactly N samples,
// constrained Delaunay triangulation per chart, joined along the seams and
// optimised (sections 4.4.1-4.4.4), on a closed organic mesh (bunny), one
// with a boundary (mushroom), genus 2 (eight) and a CAD part with sharp
// edges kept as chart boundaries (fandisk).
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/SurfaceRemeshing.h"
#include "Maps/MeshWithAtlas.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>
#include <cstdio>
#include <unordered_map>

using namespace beltrami;

namespace
{

AtlasOptions RemeshAtlas(bool features)
{
  AtlasOptions options = RemeshingAtlasOptions();
  options.SplitAtFeatures = features;
  return options;
}

/// Distance from p to the triangle (a, b, c).
double PointTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
  double w[3];
  return std::sqrt(ClosestPointOnTriangle(p, a, b, c, w));
}

/// The largest distance from the query points to the surface (points,
/// triangles): triangles bucketed on a grid, rings of cells searched until
/// the nearest triangle found is surely the nearest.
double MaxDistanceToSurface(const std::vector<double>& query, const std::vector<double>& points,
  const std::vector<Index>& triangles, double cell)
{
  const auto key = [](long x, long y, long z) { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); };
  std::unordered_map<long, std::vector<Index>> grid;
  for (std::size_t t = 0; t < triangles.size(); t += 3)
  {
    Vec3 lo = Point(points.data(), triangles[t]), hi = lo;
    for (int k = 1; k < 3; ++k)
    {
      lo = lo.cwiseMin(Point(points.data(), triangles[t + k]));
      hi = hi.cwiseMax(Point(points.data(), triangles[t + k]));
    }
    for (long x = std::floor(lo[0] / cell); x <= std::floor(hi[0] / cell); ++x)
      for (long y = std::floor(lo[1] / cell); y <= std::floor(hi[1] / cell); ++y)
        for (long z = std::floor(lo[2] / cell); z <= std::floor(hi[2] / cell); ++z)
          grid[key(x, y, z)].push_back(static_cast<Index>(t / 3));
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < query.size(); i += 3)
  {
    const Vec3 p(query[i], query[i + 1], query[i + 2]);
    const long cx = std::floor(p[0] / cell), cy = std::floor(p[1] / cell), cz = std::floor(p[2] / cell);
    double best = HUGE_VAL;
    for (long ring = 0; best > (ring - 1) * cell && ring < 64; ++ring)
    {
      for (long x = cx - ring; x <= cx + ring; ++x)
        for (long y = cy - ring; y <= cy + ring; ++y)
          for (long z = cz - ring; z <= cz + ring; ++z)
          {
            if (std::max({ std::abs(x - cx), std::abs(y - cy), std::abs(z - cz) }) != ring)
            {
              continue;
            }
            const auto at = grid.find(key(x, y, z));
            for (Index t : at == grid.end() ? std::vector<Index>() : at->second)
            {
              best = std::min(best, PointTriangleDistance(p, Point(points.data(), triangles[3 * t]),
                Point(points.data(), triangles[3 * t + 1]), Point(points.data(), triangles[3 * t + 2])));
            }
          }
    }
    worst = std::max(worst, best);
  }
  return worst;
}

/// The length of a mesh's bounding-box diagonal.
double Diagonal(const test::Mesh& mesh)
{
  Vec3 lo = Point(mesh.Points.data(), 0), hi = lo;
  for (Index v = 0; v < mesh.NumberOfVertices(); ++v)
  {
    lo = lo.cwiseMin(Point(mesh.Points.data(), v));
    hi = hi.cwiseMax(Point(mesh.Points.data(), v));
  }
  return (hi - lo).norm();
}

/// Two-sided Hausdorff distance between the input and the remesh over the
/// input's bounding-box diagonal: input vertices to the remesh, remesh
/// vertices and triangle centres to the input.
double RelativeHausdorff(const test::Mesh& input, const RemeshResult& r)
{
  const double diagonal = Diagonal(input);
  std::vector<double> centres = r.Points;
  for (std::size_t t = 0; t < r.Triangles.size(); t += 3)
  {
    const Vec3 c = (Point(r.Points.data(), r.Triangles[t]) + Point(r.Points.data(), r.Triangles[t + 1]) +
      Point(r.Points.data(), r.Triangles[t + 2])) / 3.0;
    centres.insert(centres.end(), { c[0], c[1], c[2] });
  }
  const double cell = 0.02 * diagonal;
  return std::max(MaxDistanceToSurface(input.Points, r.Points, r.Triangles, cell),
           MaxDistanceToSurface(centres, input.Points, input.Triangles, cell)) / diagonal;
}

RemeshResult RemeshWith(const test::MeshWithAtlas& loaded, std::int64_t count, const double* importance = nullptr,
  bool features = false, double lineSag = RemeshOptions().MaximumLineSag,
  double surfaceSag = RemeshOptions().MaximumSurfaceSag, double farPin = RemeshOptions().FarPinSpacings)
{
  RemeshOptions options;
  options.NumberOfVertices = count;
  options.FeatureAngle = features ? RemeshAtlas(true).FeatureAngle : 0.0;
  options.MaximumLineSag = lineSag;
  options.MaximumSurfaceSag = surfaceSag;
  options.FarPinSpacings = farPin;
  return RemeshSurface(loaded.Topology, loaded.Points(), loaded.Atlas, importance, options);
}

/// The importance |value / mean|^gamma.
std::vector<double> GammaImportance(const MeshTopology& topology, const double* points,
  const std::vector<double>& values, double gamma)
{
  ImportanceOptions options;
  options.Gamma = gamma;
  return ImportanceFromValues(topology, points, values, options).Importance;
}

MeshTopology TopologyOf(const RemeshResult& r)
{
  return MeshTopology(static_cast<Index>(r.Points.size() / 3), IndexArray(r.Triangles.begin(), r.Triangles.end()));
}

} // namespace

TEST(SurfaceRemeshing, ExactCountsWithTheInputsTopologyAndUniformQuality)
{
  // The bunny's distance is the largest: the rims of its ears are curved
  // tighter than a uniform 10k mesh can follow (0.51% at 10k, measured at
  // an ear's tip, without MaximumSurfaceSag; 0.31% with its default, see
  // SurfaceSagRaisesTheDensityWhereTheSpacingCannotFollow).
  const struct
  {
    const char* Name;
    bool Features;
    double Hausdorff; ///< at 10k vertices, of the diagonal
  } meshes[] = { { "bunny00.off", false, 0.0045 }, { "mushroom.off", false, 0.003 }, { "eight.off", false, 0.003 },
    { "fandisk.off", true, 0.003 } };
  for (const auto& m : meshes)
  {
    const test::MeshWithAtlas loaded(m.Name, RemeshAtlas(m.Features));
    ASSERT_EQ(loaded.Error, "") << m.Name;
    const TopologySummary& input = loaded.Topology.Summary();
    double previous = HUGE_VAL, first = HUGE_VAL;
    for (std::int64_t count : { 2000, 5000, 10000 })
    {
      const RemeshResult out = RemeshWith(loaded, count, nullptr, m.Features);
      ASSERT_EQ(out.Error, "") << m.Name << " " << count;
      const MeshTopology topology = TopologyOf(out);
      const TopologySummary& s = topology.Summary();
      EXPECT_EQ(s.NumberOfUsedVertices, count) << m.Name;
      EXPECT_EQ(s.NumberOfVertices, count) << m.Name;
      EXPECT_EQ(s.EulerCharacteristic, input.EulerCharacteristic) << m.Name;
      EXPECT_EQ(s.NumberOfBoundaryLoops, input.NumberOfBoundaryLoops) << m.Name;
      EXPECT_EQ(topology.CountComponents(), loaded.Topology.CountComponents()) << m.Name;
      EXPECT_TRUE(s.IsManifold()) << m.Name;
      EXPECT_TRUE(s.IsOriented()) << m.Name;
      const TriangleQuality q = MeasureTriangleQuality(topology, out.Points.data());
      EXPECT_EQ(q.DegenerateTriangles, 0) << m.Name;
      const double hausdorff = RelativeHausdorff(loaded.Surface, out);
      std::printf("%-12s %5lld: min angle mean %.2f, worst %.2f, below 30 deg %.3f%%, valence 6 %.1f%%, edge cv %.3f, "
                  "Hausdorff %.3f%% of the diagonal, %lld seam samples freed; %.3f + %.3f + %.3f s\n",
        m.Name, static_cast<long long>(count), q.MeanMinimumAngle, q.MinimumAngle, 100.0 * q.FractionBelow30,
        100.0 * q.FractionValence6, q.EdgeLengthVariation, 100.0 * hausdorff,
        static_cast<long long>(out.Optimization.FreedVertices), out.SamplingSeconds,
        out.TriangulationSeconds, out.OptimizationSeconds);
      // The distance shrinks as the count grows, but for the last bits the
      // remesh follows (fandisk's worst spot, where a crease fades out
      // below the feature angle, at 0.174% at 5k and 0.188% at 10k with
      // OpenBLAS's generic x86-64 kernels, 0.17% at both with others).
      EXPECT_LT(hausdorff, 1.1 * previous) << m.Name << ": the distance shrinks as the count grows";
      first = count == 2000 ? hausdorff : first;
      EXPECT_TRUE(count != 10000 || hausdorff < 0.7 * first) << m.Name << ": 10k vertices no closer than 2k";
      previous = hausdorff;
      // The seams are stitched (RemeshOptimization): before that, triangles
      // at close chart corners and unflippable ears along the seams had
      // worst angles of 0.0-7 deg.
      EXPECT_GE(q.MinimumAngle, 15.0) << m.Name << " " << count;
      if (count == 10000)
      {
        EXPECT_GE(q.MeanMinimumAngle, 51.5) << m.Name;
        EXPECT_LE(q.FractionBelow30, 0.003) << m.Name;
        EXPECT_GE(q.FractionValence6, 0.80) << m.Name;
        EXPECT_LE(q.EdgeLengthVariation, 0.11) << m.Name;
        EXPECT_LE(hausdorff, m.Hausdorff) << m.Name;
      }
    }
  }
}

TEST(SurfaceRemeshing, CurvatureAdaptedRemeshIsCloser)
{
  // The bunny at 10k vertices, with the importance max |kappa_i|^0.25: the
  // ears' rims get the samples they need (Hausdorff 0.52% -> 0.31% of the
  // diagonal; 0.29% with MaximumSurfaceSag's default on top) and the
  // triangles stay nearly as good as uniform ones.
  const test::MeshWithAtlas loaded("bunny00.off", RemeshAtlas(false));
  ASSERT_EQ(loaded.Error, "");
  const std::vector<double> importance = GammaImportance(loaded.Topology, loaded.Points(),
    CurvatureValues(loaded.Topology, loaded.Points(), CurvatureMeasure::MaximumCurvature), 0.25);
  const RemeshResult out = RemeshWith(loaded, 10000, importance.data());
  ASSERT_EQ(out.Error, "");
  const MeshTopology topology = TopologyOf(out);
  EXPECT_EQ(topology.Summary().NumberOfUsedVertices, 10000);
  const TriangleQuality q = MeasureTriangleQuality(topology, out.Points.data());
  const double hausdorff = RelativeHausdorff(loaded.Surface, out);
  std::printf("bunny00 10k, max curvature^0.25: Hausdorff %.3f%%, min angle mean %.2f, worst %.2f, valence 6 %.1f%%\n",
    100.0 * hausdorff, q.MeanMinimumAngle, q.MinimumAngle, 100.0 * q.FractionValence6);
  EXPECT_LE(hausdorff, 0.005);
  EXPECT_GE(q.MinimumAngle, 15.0);
  EXPECT_GE(q.MeanMinimumAngle, 51.0);
  EXPECT_GE(q.FractionValence6, 0.78);
}

TEST(SurfaceRemeshing, SurfaceSagRaisesTheDensityWhereTheSpacingCannotFollow)
{
  // A unit sphere: at 10k samples a triangle departs from it by about
  // s^2 / 8 = 0.0044 s, far under 0.1 s: the density stands.  At 12 samples
  // (s = 1.02) the bound asks for about 1.3 times the density everywhere:
  // the same uniform density.
  const test::Mesh sphere = test::OctahedronSphere(5);
  const MeshTopology topology = sphere.Topology();
  const std::vector<double> kappa =
    CurvatureValues(topology, sphere.Points.data(), CurvatureMeasure::MaximumCurvature);
  EXPECT_TRUE(RaiseImportanceForSag(topology, sphere.Points.data(), nullptr, kappa, nullptr, 10000, 0.1).empty());
  const std::vector<double> coarse =
    RaiseImportanceForSag(topology, sphere.Points.data(), nullptr, kappa, nullptr, 12, 0.1);
  ASSERT_EQ(coarse.size(), kappa.size());
  const auto [lo, hi] = std::minmax_element(coarse.begin(), coarse.end());
  std::printf("sphere, 12 samples: importance %.4f-%.4f (expected about %.4f)\n", *lo, *hi,
    std::sqrt(4.0 * M_PI / 12.0) / 0.8);
  EXPECT_NEAR(*lo, std::sqrt(4.0 * M_PI / 12.0) / 0.8, 0.05);
  EXPECT_LE(*hi / *lo, 1.02);
  // The bunny at 10k: its ears' rims (and the scan's bumps) are curved
  // tighter than the uniform spacing follows.  Raised there, the remesh is
  // closer, its triangles as regular as the uniform ones.  (Measured
  // without the fidelity rounds, which pin the farthest input vertices of
  // both: 0.371% of the diagonal -> 0.313%, 0.84 times; with them 0.363%
  // -> 0.313%.  The largest distance moves with the layout, which follows
  // one CPU's BLAS kernels or another's: with the rounds, before they kept
  // a round no farther in the larger deviation, 0.51% -> 0.31% on one,
  // 0.43% -> 0.33% on another.)
  const test::MeshWithAtlas loaded("bunny00.off", RemeshAtlas(false));
  ASSERT_EQ(loaded.Error, "");
  const RemeshResult uniform = RemeshWith(loaded, 10000, nullptr, false, 0.025, 0.0, 0.0);
  const RemeshResult raised =
    RemeshWith(loaded, 10000, nullptr, false, RemeshOptions().MaximumLineSag, RemeshOptions().MaximumSurfaceSag, 0.0);
  const double before = RelativeHausdorff(loaded.Surface, uniform), after = RelativeHausdorff(loaded.Surface, raised);
  const TriangleQuality q0 = MeasureTriangleQuality(TopologyOf(uniform), uniform.Points.data());
  const TriangleQuality q1 = MeasureTriangleQuality(TopologyOf(raised), raised.Points.data());
  std::printf("bunny00 10k, MaximumSurfaceSag 0 -> 0.1: Hausdorff %.3f%% -> %.3f%%, edge cv %.3f -> %.3f, "
              "valence 6 %.1f%% -> %.1f%%, min angle mean %.2f -> %.2f\n",
    100.0 * before, 100.0 * after, q0.EdgeLengthVariation, q1.EdgeLengthVariation, 100.0 * q0.FractionValence6,
    100.0 * q1.FractionValence6, q0.MeanMinimumAngle, q1.MeanMinimumAngle);
  EXPECT_LE(after, 0.9 * before);
  EXPECT_LE(q1.EdgeLengthVariation, 0.1);
  EXPECT_GE(q1.FractionValence6, 0.8);
}

TEST(SurfaceRemeshing, FarInputVerticesArePinnedInMoreRemeshes)
{
  // Where a remesh leaves input vertices farther than 0.15 of its spacing
  // (the elephant's trunk and feet, the peaks' tips), the nearest vertex of
  // the remesh that can is moved onto each and kept there, up to three
  // rounds (else the remesh is made again with them pinned): the closest is
  // kept, its triangles within the quality bar (no angle below 15 degrees,
  // at most 0.5% below 30) or as good as the first's, with a vertex
  // exactly at every input vertex reached.  Measured: elephant 10k 0.514%
  // -> 0.249% of the diagonal, three_peaks 2k 0.905% -> 0.508%, 10k 0.377%
  // -> 0.214%; elephant at 2k keeps its first remesh.
  int closer = 0;
  std::size_t reached = 0; // input vertices a remesh vertex was moved onto
  for (const char* name : { "elephant.off", "three_peaks.off" })
  {
    const test::MeshWithAtlas loaded(name, RemeshAtlas(false));
    ASSERT_EQ(loaded.Error, "");
    for (const std::int64_t count : { 2000, 10000 })
    {
      RemeshOptions options;
      options.NumberOfVertices = count;
      const RemeshResult pinned = RemeshSurface(loaded.Topology, loaded.Points(), loaded.Atlas, nullptr, options);
      options.FarPinSpacings = 0.0;
      const RemeshResult once = RemeshSurface(loaded.Topology, loaded.Points(), loaded.Atlas, nullptr, options);
      ASSERT_EQ(pinned.Error, "");
      ASSERT_EQ(once.Error, "");
      const double before = std::max(once.DeviationToInput, once.DeviationFromInput);
      const double after = std::max(pinned.DeviationToInput, pinned.DeviationFromInput);
      const TriangleQuality q0 = MeasureTriangleQuality(TopologyOf(once), once.Points.data());
      const TriangleQuality q1 = MeasureTriangleQuality(TopologyOf(pinned), pinned.Points.data());
      std::printf("%s %lld: deviation %.3f%% -> %.3f%%, smallest angle %.1f -> %.1f, below 30 %.2f%% -> %.2f%%\n", name,
        static_cast<long long>(count), 100.0 * before, 100.0 * after, q0.MinimumAngle, q1.MinimumAngle,
        100.0 * q0.FractionBelow30, 100.0 * q1.FractionBelow30);
      EXPECT_EQ(pinned.Points.size(), once.Points.size());
      for (const Index v : pinned.ReachedFarVertices)
      {
        double nearest = HUGE_VAL;
        for (std::size_t k = 0; k < pinned.Points.size() / 3; ++k)
        {
          const Vec3 p = Point(pinned.Points.data(), static_cast<Index>(k));
          nearest = std::min(nearest, (p - Point(loaded.Points(), v)).norm());
        }
        EXPECT_LT(nearest, 1e-12 * pinned.Diagonal) << name << " " << count << " input vertex " << v;
      }
      EXPECT_TRUE(after == before || after < FarPinGain * before) << name << " " << count;
      reached += pinned.ReachedFarVertices.size();
      if (after < before)
      {
        ++closer;
        EXPECT_GE(q1.MinimumAngle, std::min(q0.MinimumAngle, 15.0)) << name << " " << count;
        EXPECT_LE(q1.FractionBelow30, std::max(q0.FractionBelow30 + 1e-3, 0.005)) << name << " " << count;
      }
    }
  }
  EXPECT_GE(closer, 3);
  EXPECT_GE(reached, 1u);
}

/// `mesh` remeshed at `count` vertices with its fidelity rounds (first)
/// and without them (second).
std::pair<RemeshResult, RemeshResult> WithAndWithoutRounds(const test::Mesh& mesh, std::int64_t count)
{
  const MeshTopology input = mesh.Topology();
  const AtlasResult atlas = BuildAtlas(input, mesh.Points.data(), RemeshingAtlasOptions());
  EXPECT_EQ(atlas.Error, "");
  RemeshOptions options;
  options.NumberOfVertices = count;
  std::pair<RemeshResult, RemeshResult> out;
  out.first = RemeshSurface(input, mesh.Points.data(), atlas, nullptr, options);
  options.FarPinSpacings = 0.0;
  out.second = RemeshSurface(input, mesh.Points.data(), atlas, nullptr, options);
  EXPECT_EQ(out.first.Error, "");
  EXPECT_EQ(out.second.Error, "");
  return out;
}

TEST(SurfaceRemeshing, TheCornersOfACoarsePolyhedronAreMovedOnto)
{
  // A sphere of 1,026 vertices remeshed at 10,000: its vertices are corners
  // at the remesh's scale (the density follows the sphere, not its facets),
  // left 0.06 spacings off, below FarPinSpacings but beyond CornerPinSpacings
  // and four times the sag of a spacing on it.  Once no input vertex is
  // farther, a round moves remesh vertices onto them (all beyond the bound,
  // not only the farthest of their rings): measured 0.054% -> 0.037% of
  // the diagonal, 641 corners reached.
  const test::Mesh sphere = test::OctahedronSphere(4);
  const auto [pinned, once] = WithAndWithoutRounds(sphere, 10000);
  ASSERT_EQ(pinned.Error + once.Error, "");
  const double before = WorstDeviation(once), after = WorstDeviation(pinned);
  const TriangleQuality q = MeasureTriangleQuality(TopologyOf(pinned), pinned.Points.data());
  std::printf("deviation %.4f%% -> %.4f%%, %zu corners reached, smallest angle %.1f, below 30 %.2f%%\n",
    100.0 * before, 100.0 * after, pinned.ReachedFarVertices.size(), q.MinimumAngle, 100.0 * q.FractionBelow30);
  EXPECT_LT(after, 0.85 * before);
  EXPECT_GT(pinned.ReachedFarVertices.size(), 100u);
  // The deviations the rounds report (measured again where they moved the
  // remesh) are those measured anew: the input's vertices, edge midpoints
  // and triangle centres to the remesh, the remesh's triangle centres and
  // edge midpoints to the input.
  const SurfaceDeviation measured = MeasureDeviation(sphere.Points.data(), sphere.Triangles.data(),
    sphere.Triangles.size() / 3, DeviationSamples::All, pinned.Points.data(), pinned.Triangles.data(),
    pinned.Triangles.size() / 3, DeviationSamples::Midpoints);
  EXPECT_NEAR(pinned.DeviationFromInput * pinned.Diagonal, measured.FirstToSecond, 1e-14);
  EXPECT_NEAR(pinned.DeviationToInput * pinned.Diagonal, measured.SecondToFirst, 1e-14);
  EXPECT_GE(q.MinimumAngle, 15.0);
  EXPECT_LE(q.FractionBelow30, 0.005);
}

TEST(SurfaceRemeshing, TheDeviationIsMeasuredWhereTheRemeshCutsTheInputsEdges)
{
  // A cube of 12 triangles remeshed at 300 vertices, its edges rounded off
  // (no sharp edges kept): every input vertex is a corner the remesh keeps,
  // so measured at the input's vertices the remesh is 0 from the input; at
  // points along its edges and at its faces' centres it is not (measured:
  // 3.8% of the diagonal, 3.4% at the edges' midpoints).  The reported
  // deviation is the largest over all of those samples, however few of
  // them were measured (MeasureDeviation: all, at the midpoints).
  const test::Mesh cube = test::CubeSurface(1);
  const MeshTopology input = cube.Topology();
  const AtlasResult atlas = BuildAtlas(input, cube.Points.data(), RemeshingAtlasOptions());
  ASSERT_EQ(atlas.Error, "");
  RemeshOptions options;
  options.NumberOfVertices = 300;
  const RemeshResult r = RemeshSurface(input, cube.Points.data(), atlas, nullptr, options);
  ASSERT_EQ(r.Error, "");
  const auto measured = [&](DeviationSamples samples) {
    return MeasureDeviation(cube.Points.data(), cube.Triangles.data(), cube.Triangles.size() / 3, samples,
      r.Points.data(), r.Triangles.data(), r.Triangles.size() / 3, DeviationSamples::Midpoints);
  };
  std::printf("from the input %.4f%% (at its vertices %.4f%%), to it %.4f%%\n", 100.0 * r.DeviationFromInput,
    100.0 * measured(DeviationSamples::Vertices).FirstToSecond / r.Diagonal, 100.0 * r.DeviationToInput);
  EXPECT_LT(measured(DeviationSamples::Vertices).FirstToSecond, 1e-9 * r.Diagonal);
  EXPECT_GT(r.DeviationFromInput, 0.02);
  // (its edges, 6.6 spacings long, measured in parts of at most a spacing:
  // at least as far as at their midpoints)
  EXPECT_GE(r.DeviationFromInput * r.Diagonal, measured(DeviationSamples::All).FirstToSecond - 1e-14);
  EXPECT_NEAR(r.DeviationToInput * r.Diagonal, measured(DeviationSamples::All).SecondToFirst, 1e-14);
}

TEST(SurfaceRemeshing, FidelityRoundsFollowTheCreasesOfACoarseInput)
{
  // A torus of 8 x 4 quads (64 triangles, edges 6-16 spacings long, creases
  // of 90 degrees) remeshed at 2,000 vertices: its triangles cut the
  // creases, points along its long edges the farthest input points.  The
  // fidelity rounds move vertices onto points a spacing apart along those
  // edges, those on one edge joined along it (measured: 1.04% / 0.73% of
  // the diagonal from / to the input without the rounds, 0.68% / 0.74% with
  // them, the worst angle 24.8 degrees).  Measured along every input edge
  // at 64 points, not only a spacing apart, the remesh is as close (0.76%).
  const test::Mesh torus = test::Torus(1.0, 0.3, 8, 4, 0.0, 1);
  const auto [r, once] = WithAndWithoutRounds(torus, 2000);
  ASSERT_EQ(r.Error + once.Error, "");
  const TriangleGrid grid(r.Points.data(), r.Triangles.data(), r.Triangles.size() / 3);
  double along = 0.0; // the largest distance of the input's edges from the remesh
  for (std::size_t c = 0; c < torus.Triangles.size(); ++c)
  {
    const Vec3 a = Point(torus.Points.data(), torus.Triangles[c]);
    const Vec3 b = Point(torus.Points.data(), torus.Triangles[c - c % 3 + (c + 1) % 3]);
    for (int k = 1; k < 64; ++k)
    {
      along = std::max(along, grid.Distance(a + (b - a) * (k / 64.0)));
    }
  }
  const TriangleQuality q = MeasureTriangleQuality(TopologyOf(r), r.Points.data());
  std::printf("from / to the input %.3f%% / %.3f%% without the rounds, %.3f%% / %.3f%% with them (along its "
              "edges %.3f%%); worst angle %.1f, below 30 degrees %.2f%%\n",
    100.0 * once.DeviationFromInput, 100.0 * once.DeviationToInput, 100.0 * r.DeviationFromInput,
    100.0 * r.DeviationToInput, 100.0 * along / r.Diagonal, q.MinimumAngle, 100.0 * q.FractionBelow30);
  EXPECT_GT(once.DeviationFromInput, 0.009);
  EXPECT_LT(WorstDeviation(r), 0.8 * WorstDeviation(once));
  EXPECT_LT(along / r.Diagonal, 0.8 * once.DeviationFromInput);
  EXPECT_GE(q.MinimumAngle, 15.0);
  EXPECT_LE(q.FractionBelow30, 0.005);
}

TEST(SurfaceRemeshing, EdgeLengthsFollowTheCurvatureToTheRequestedGamma)
{
  // Density proportional to the importance kappa^gamma makes the local edge
  // length proportional to kappa^(-gamma/2).  On an ellipsoid with axes
  // 1, 1, 3 (max |kappa_i| from 1 at the equator to 3 at the poles), the
  // least-squares slope of log(mean edge length at a vertex) against
  // log(kappa there), over all 5000 vertices, measured -0.246, -0.491 and
  // -1.011 for gamma 0.5, 1 and 2 (within 2% of -gamma/2; at 3000 vertices
  // gamma 0.5, whose lengths vary by 32% only, measured 8% off).
  test::Mesh ellipsoid = test::OctahedronSphere(6);
  for (std::size_t i = 2; i < ellipsoid.Points.size(); i += 3)
  {
    ellipsoid.Points[i] *= 3.0;
  }
  const MeshTopology input = ellipsoid.Topology();
  const AtlasResult atlas = BuildAtlas(input, ellipsoid.Points.data(), RemeshingAtlasOptions());
  ASSERT_EQ(atlas.Error, "");
  const std::vector<double> kappa = CurvatureValues(input, ellipsoid.Points.data(), CurvatureMeasure::MaximumCurvature);
  for (double gamma : { 0.5, 1.0, 2.0 })
  {
    const std::vector<double> importance = GammaImportance(input, ellipsoid.Points.data(), kappa, gamma);
    RemeshOptions options;
    options.NumberOfVertices = 5000;
    options.ImportanceGradation = 0.0; // (the density as given, not graded)
    const RemeshResult out = RemeshSurface(input, ellipsoid.Points.data(), atlas, importance.data(), options);
    ASSERT_EQ(out.Error, "");
    const Index n = static_cast<Index>(out.Points.size() / 3);
    std::vector<double> length(n, 0.0), edges(n, 0.0);
    for (std::size_t t = 0; t < out.Triangles.size(); t += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index a = out.Triangles[t + k], b = out.Triangles[t + (k + 1) % 3];
        const double l = (Point(out.Points.data(), a) - Point(out.Points.data(), b)).norm();
        length[a] += l;
        length[b] += l;
        edges[a] += 1.0;
        edges[b] += 1.0;
      }
    }
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    for (Index v = 0; v < n; ++v)
    {
      double k = 0.0;
      for (int j = 0; j < 3; ++j)
      {
        k += out.SourceBarycentric[3 * v + j] * kappa[input.CornerVertex(3 * out.SourceTriangle[v] + j)];
      }
      const Eigen::Vector2d row(1.0, std::log(k));
      normal += row * row.transpose();
      rhs += row * std::log(length[v] / edges[v]);
    }
    const double slope = normal.ldlt().solve(rhs)[1];
    std::printf("gamma %.1f: slope %.4f (expected %.4f)\n", gamma, slope, -gamma / 2);
    EXPECT_NEAR(slope / (-gamma / 2), 1.0, 0.06) << gamma;
  }
}

TEST(SurfaceRemeshing, GradationIsTheHeatKernelOfItsWidth)
{
  // A step of the importance (0.5 for x < 0, 1.5 for x > 0: values 1 and 3
  // with gamma 1) on a jittered flat square [-0.5, 0.5]^2, filtered with
  // width s = 0.05: the profile across the step is the Gaussian's,
  // 1 + 0.5 erf(x / (s sqrt 2)), within 0.036 (eight implicit heat steps
  // differ from the Gaussian by 0.012 in 1D; a jittered mesh of spacing s/5
  // places the step itself within +-s/25), and the integral over the
  // surface is kept.
  const test::Mesh square = test::HeightField([](double, double) { return 0.0; }, 0.5, 101, 0.2, true, 3);
  const MeshTopology topology = square.Topology();
  std::vector<double> values(topology.NumberOfVertices());
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    values[v] = square.Points[3 * v] < 0.0 ? 1.0 : 3.0;
  }
  ImportanceOptions options;
  options.Gradation = 0.05;
  const ImportanceResult smooth = ImportanceFromValues(topology, square.Points.data(), values, options);
  EXPECT_EQ(smooth.Warning, "");
  options.Gradation = 0.0;
  const ImportanceResult step = ImportanceFromValues(topology, square.Points.data(), values, options);
  GraphLaplacian laplacian;
  AssembleSurfaceLaplacian(topology, square.Points.data(), LaplacianWeights::Cotangent, laplacian);
  double before = 0.0, after = 0.0, worst = 0.0;
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    before += laplacian.Mass[v] * step.Importance[v];
    after += laplacian.Mass[v] * smooth.Importance[v];
    const double x = square.Points[3 * v];
    worst = std::max(worst, std::abs(smooth.Importance[v] - (1.0 + 0.5 * std::erf(x / (0.05 * std::sqrt(2.0))))));
  }
  std::printf("gradation 0.05: largest difference from the Gaussian profile %.4f (step 1); integral %.8f -> %.8f\n",
    worst, before, after);
  EXPECT_LT(worst, 0.045);
  EXPECT_NEAR(after, before, 1e-6 * before);
}

TEST(SurfaceRemeshing, TransferFunctionIsPiecewiseLinearAndTheMinimumHolds)
{
  // x = value / mean (mean 1 here); the points are given unsorted, with one
  // left out for its NaN.
  const test::Mesh square = test::HeightField([](double, double) { return 0.0; }, 0.5, 5, 0.0, false, 1);
  const MeshTopology topology = square.Topology();
  std::vector<double> values(topology.NumberOfVertices(), 1.0);
  values[0] = 0.0;
  values[1] = 0.5;
  values[2] = 2.0;
  values[3] = 10.0;
  values[4] = std::nan("");
  double mean = 0.0;
  for (double v : values)
  {
    mean += std::isfinite(v) ? v / (values.size() - 1) : 0.0;
  }
  ImportanceOptions options;
  options.TransferFunction = { 3.0, 4.0, 0.0, 0.2, std::nan(""), 9.0, 1.0, 1.0 };
  options.Minimum = 0.3;
  const std::vector<double> importance = ImportanceFromValues(topology, square.Points.data(), values, options).Importance;
  const auto expected = [&](double value) {
    const double x = value / mean;
    const double f = x <= 1.0 ? 0.2 + 0.8 * x : (x <= 3.0 ? 1.0 + 1.5 * (x - 1.0) : 4.0);
    return std::max(0.3, f);
  };
  for (int v = 0; v < 4; ++v)
  {
    EXPECT_NEAR(importance[v], expected(values[v]), 1e-12) << v;
  }
  EXPECT_NEAR(importance[4], 1.0, 1e-12) << "NaN counts as the mean";
  EXPECT_NEAR(importance[5], expected(1.0), 1e-12);
}

TEST(SurfaceRemeshing, SharpEdgesOfACadPartAreReproduced)
{
  // fandisk with SplitAtFeatures: its sharp edges (normals more than 60
  // degrees apart) are chart boundaries, sampled along them and kept as
  // lines while stitching, and every crease's end is a corner with a sample
  // on it (where the crease fades out below the 60 degrees, as at vertex
  // 161, the chart boundary goes on as a plain seam), so the remesh passes
  // through them.  The creases are sampled more densely where they bend
  // (MaximumLineSag): every end and middle of an input sharp edge lies
  // within 0.105-0.111% of the diagonal of the remesh at 10k vertices and
  // 0.088-0.097% at 5k at the default 0.05 (2-core x86-64); with the
  // density's spacing along them (MaximumLineSag 0) the small round crease
  // (22.5 degrees of turn per input edge) is cut between samples: 0.105%
  // and 0.130% (at 10k the default's bound does not ask for more samples
  // there); with the stricter 0.025, 0.078% and 0.099%.  (x86-64 machines
  // whose BLAS and libm round the charts' maps differently measured up to
  // a tenth apart here.)  Before the crease ends were corners:
  // 0.16-0.19% and 0.43-0.44%, at vertex 161.  Without the features the
  // remesh cuts the creases: 0.83-0.94% and 1.14-1.39%.
  for (bool features : { true, false })
  {
    const test::MeshWithAtlas loaded("fandisk.off", RemeshAtlas(features));
    ASSERT_EQ(loaded.Error, "");
    const double diagonal = Diagonal(loaded.Surface);
    const std::vector<std::uint8_t> sharp = SharpEdges(loaded.Topology, loaded.Points(), 60.0);
    std::vector<double> creases; // ends and middles of the sharp edges
    for (std::size_t e = 0; e < sharp.size(); ++e)
    {
      const Vec3 a = Point(loaded.Points(), loaded.Topology.Edges().Vertices[2 * e]);
      const Vec3 b = Point(loaded.Points(), loaded.Topology.Edges().Vertices[2 * e + 1]);
      for (const Vec3& p : { a, b, Vec3(0.5 * (a + b)) })
      {
        if (sharp[e])
        {
          creases.insert(creases.end(), { p[0], p[1], p[2] });
        }
      }
    }
    ASSERT_GT(creases.size(), 1000u);
    for (std::int64_t count : { 5000, 10000 })
    {
      const RemeshResult out = RemeshWith(loaded, count, nullptr, features);
      ASSERT_EQ(out.Error, "");
      const double distance = MaxDistanceToSurface(creases, out.Points, out.Triangles, 0.02 * diagonal) / diagonal;
      std::printf("fandisk %lld vertices, features %s: sharp edges within %.4f%% of the diagonal of the remesh\n",
        static_cast<long long>(count), features ? "kept" : "off", 100.0 * distance);
      if (features)
      {
        // (0.097-0.128% at both counts: the remesh follows the last bits of
        // the solves, which differ between CPUs' BLAS kernels: 0.111% at
        // 10k on one x86-64 CPU, 0.105% on another, 0.124% with OpenBLAS's
        // generic x86-64 kernels; 0.128% there with the creases continued
        // where they fade out)
        EXPECT_LE(distance, 0.0014) << count;
        const RemeshResult straight = RemeshWith(loaded, count, nullptr, features, 0.0);
        const RemeshResult strict = RemeshWith(loaded, count, nullptr, features, 0.025);
        const double cut = MaxDistanceToSurface(creases, straight.Points, straight.Triangles, 0.02 * diagonal) / diagonal;
        const double tight = MaxDistanceToSurface(creases, strict.Points, strict.Triangles, 0.02 * diagonal) / diagonal;
        std::printf("  with the density's spacing along the creases: %.4f%%; MaximumLineSag 0.025: %.4f%%\n",
          100.0 * cut, 100.0 * tight);
        EXPECT_LE(distance, cut) << count;
        EXPECT_GT(cut, 1.2 * tight) << count;
        // A remesh vertex on every crease's end (a vertex with one sharp
        // edge), where the crease fades out below half the feature angle
        // (ExtendFeatureEnds: two of fandisk's ends at 60 degrees move).
        std::vector<std::uint8_t> lines = sharp;
        EXPECT_GT(ExtendFeatureEnds(loaded.Topology, loaded.Points(), 30.0, 30.0, lines), 0);
        std::vector<int> sharpAt(loaded.Topology.NumberOfVertices(), 0);
        for (std::size_t e = 0; e < lines.size(); ++e)
        {
          sharpAt[loaded.Topology.Edges().Vertices[2 * e]] += lines[e];
          sharpAt[loaded.Topology.Edges().Vertices[2 * e + 1]] += lines[e];
        }
        int ends = 0;
        for (Index v = 0; v < loaded.Topology.NumberOfVertices(); ++v)
        {
          if (sharpAt[v] == 1)
          {
            ++ends;
            double nearest = HUGE_VAL;
            for (std::size_t i = 0; i < out.Points.size(); i += 3)
            {
              nearest = std::min(nearest, (Point(out.Points.data(), i / 3) - Point(loaded.Points(), v)).norm());
            }
            EXPECT_LT(nearest, 1e-9 * diagonal) << "crease end " << v;
          }
        }
        EXPECT_GT(ends, 0);
      }
      else
      {
        // Without the features the creases are rounded, several times as
        // far (measured 0.77% at 5k, 0.54% at 10k: the corners that stand
        // out are pinned, the creases between them cut).
        EXPECT_GT(distance, 0.004) << count;
      }
    }
  }
}

TEST(SurfaceRemeshing, MoreVerticesThanTheControlMapHoldsIsAClearError)
{
  // A control map of 64^2 texels holds at most one sample per texel inside
  // the charts: 10,000 vertices do not fit (the automatic resolution grows
  // with the count up to 8192^2 texels, about 30M vertices on a typical
  // atlas, where the same error is given).
  const test::MeshWithAtlas loaded("mushroom.off", RemeshAtlas(false));
  ASSERT_EQ(loaded.Error, "");
  RemeshOptions options;
  options.NumberOfVertices = 10000;
  options.Resolution = 64;
  const RemeshResult out = RemeshSurface(loaded.Topology, loaded.Points(), loaded.Atlas, nullptr, options);
  EXPECT_NE(out.Error.find("cannot place"), std::string::npos) << out.Error;
  EXPECT_TRUE(out.Points.empty() && out.Triangles.empty());
}

TEST(SurfaceRemeshing, EarsOnBothSidesOfASeamAreSplit)
{
  // The elephant (genus 3) adapted to max |kappa_i| through a steep
  // transfer function: at 3000 and 4000 vertices a seam got the same ear
  // (three consecutive samples) in both of its charts, not flippable in
  // either plane, and the join was not manifold (an error, no remesh).  The
  // middle sample now goes into the ears' common edge.
  const test::MeshWithAtlas loaded("elephant.off", RemeshAtlas(false));
  ASSERT_EQ(loaded.Error, "");
  ImportanceOptions transfer;
  transfer.TransferFunction = { 0.0, 0.3, 3.0, 4.0 };
  const std::vector<double> importance = ImportanceFromValues(loaded.Topology, loaded.Points(),
    CurvatureValues(loaded.Topology, loaded.Points(), CurvatureMeasure::MaximumCurvature), transfer).Importance;
  for (std::int64_t count : { 3000, 4000 })
  {
    const RemeshResult out = RemeshWith(loaded, count, importance.data());
    ASSERT_EQ(out.Error, "") << count;
    const MeshTopology topology = TopologyOf(out);
    const TopologySummary& s = topology.Summary();
    EXPECT_EQ(s.NumberOfUsedVertices, count);
    EXPECT_EQ(s.EulerCharacteristic, loaded.Topology.Summary().EulerCharacteristic);
    EXPECT_TRUE(s.IsManifold() && s.IsOriented());
    const TriangleQuality q = MeasureTriangleQuality(topology, out.Points.data());
    EXPECT_EQ(q.DegenerateTriangles, 0);
    std::printf("elephant %lld, steep curvature transfer: worst angle %.2f, mean %.2f\n", static_cast<long long>(count),
      q.MinimumAngle, q.MeanMinimumAngle);
  }
}

TEST(SurfaceRemeshing, ACountTheRimsOfManyHolesTakeNamesOneThatKeepsThem)
{
  // bunny00 with a hole for every few triangles (each a triangle whose
  // corners touch no other hole): the rims alone take more samples than
  // 2,000; the counts named for the message remesh, the one that keeps the
  // input leaves every input point within its spacing.
  std::string error;
  test::Mesh holed = test::ReadMesh("bunny00.off", error);
  ASSERT_EQ(error, "");
  std::vector<std::uint8_t> touched(holed.Points.size() / 3, 0);
  std::vector<Index> kept;
  std::int64_t holes = 0;
  for (std::size_t t = 0; 3 * t < holed.Triangles.size(); ++t)
  {
    const Index* c = &holed.Triangles[3 * t];
    const bool hole = t % 16 == 0 && !touched[c[0]] && !touched[c[1]] && !touched[c[2]];
    holes += hole ? 1 : 0;
    for (int k = 0; k < 3; ++k)
    {
      touched[c[k]] |= hole ? 1 : 0;
      if (!hole)
      {
        kept.push_back(c[k]);
      }
    }
  }
  holed.Triangles = kept;
  const MeshTopology topology = holed.Topology();
  const AtlasResult atlas = BuildAtlas(topology, holed.Points.data(), RemeshAtlas(false));
  ASSERT_EQ(atlas.Error, "");
  RemeshOptions options;
  options.NumberOfVertices = 2000;
  const RemeshResult failed = RemeshSurface(topology, holed.Points.data(), atlas, nullptr, options);
  std::printf("%lld holes: %lld samples on their rims\n", static_cast<long long>(holes),
    static_cast<long long>(failed.Samples.RimSamples));
  EXPECT_NE(failed.Error, "");
  EXPECT_GE(failed.Samples.RimSamples, 3 * holes);
  EXPECT_LE(failed.Samples.RimSamples, failed.Samples.BoundarySamples);
  const CountAdvice counts = AdviseCounts(topology, holed.Points.data(), atlas, nullptr, options, failed);
  std::printf("remeshes with %lld, keeps the input with %lld\n", static_cast<long long>(counts.Remeshes),
    static_cast<long long>(counts.Keeps));
  ASSERT_GT(counts.Keeps, failed.Samples.RimSamples);
  EXPECT_TRUE(counts.Remeshes > 0 && counts.Remeshes <= counts.Keeps);
  options.NumberOfVertices = counts.Keeps;
  const RemeshResult keeping = RemeshSurface(topology, holed.Points.data(), atlas, nullptr, options);
  ASSERT_EQ(keeping.Error, "");
  EXPECT_EQ(static_cast<std::int64_t>(keeping.Points.size() / 3), counts.Keeps);
  EXPECT_LE(keeping.DeviationFromInput * keeping.Diagonal, keeping.Spacing);
  const TopologySummary& before = topology.Summary();
  const TopologySummary& after = TopologyOf(keeping).Summary();
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.NumberOfBoundaryLoops, before.NumberOfBoundaryLoops);
}

TEST(SurfaceRemeshing, FoldedEdgesAreCountedOnTheInteriorEdges)
{
  // A height field of unit spacing: smooth, none folded; with every other
  // row of vertices raised by far more than the spacing (a washboard), the
  // triangles on either side of each ridge face apart by more than 90
  // degrees wherever an edge runs along a ridge or a valley.
  const test::Mesh flat = test::HeightField([](double, double) { return 0.0; }, 5.5, 12, 0.0, false, 1);
  EXPECT_EQ(FoldedEdgeShare(flat.Topology(), flat.Points.data()), 0.0);
  test::Mesh folded = flat;
  for (Index v = 0; v < folded.NumberOfVertices(); ++v)
  {
    folded.Points[3 * v + 2] = std::fmod(std::round(folded.Points[3 * v + 1] + 5.5), 2.0) == 0.0 ? 0.0 : 5.0;
  }
  const double share = FoldedEdgeShare(folded.Topology(), folded.Points.data());
  std::printf("washboard: %.1f%% of the interior edges folded\n", 100.0 * share);
  EXPECT_GT(share, 0.2);
  EXPECT_LT(share, 0.5);
  // A cube's faces meet at 90 degrees: none folded, turned any way (their
  // normals' product is round-off there, of either sign: 5 of its 18 edges
  // counted, and a third of the corpus' cube's).
  test::Mesh cube = test::CubeSurface(1);
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()) *
    Eigen::AngleAxisd(1.1, Eigen::Vector3d(-2.0, 0.5, 1.0).normalized())).toRotationMatrix();
  for (Index v = 0; v < cube.NumberOfVertices(); ++v)
  {
    Eigen::Map<Eigen::Vector3d>(&cube.Points[3 * v]) = turn * Eigen::Vector3d(Point(cube.Points.data(), v));
  }
  EXPECT_EQ(FoldedEdgeShare(cube.Topology(), cube.Points.data()), 0.0);
}
