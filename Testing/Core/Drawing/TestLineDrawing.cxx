// Line drawings: curvature derivatives against analytic surfaces,
// suggestive contours on a Gaussian bump, contours on spheres, ridges and
// valleys of an ellipsoid, suggestive contours meeting contours on a torus,
// chaining, no curvature lines along the creases of a CAD part, the
// smoothing of the fields, and bad input.
#include "TestMeshes.h"

#include "Drawing/FieldSmoothing.h"
#include "Drawing/LineChaining.h"
#include "Drawing/LineDrawing.h"
#include "Mesh/CurvatureDerivatives.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

using namespace beltrami;
using test::Mesh;

namespace
{

LineDrawingGeometry Geometry(const Mesh& m, int threads = 0)
{
  LineDrawingGeometry geo;
  geo.Build(m.Topology(threads), m.Points.data(), threads);
  return geo;
}

LineDrawingOptions Only(LineType type)
{
  LineDrawingOptions o;
  for (bool& d : o.Draw)
  {
    d = false;
  }
  o.Draw[static_cast<int>(type)] = true;
  return o;
}

LineView Orthographic(const Vec3& direction)
{
  LineView v;
  v.Perspective = false;
  v.Direction = direction;
  return v;
}

/// The points of the lines of one type.
std::vector<Vec3> PointsOf(const LineSet& lines, LineType type)
{
  std::vector<Vec3> points;
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    if (lines.Type[l] != static_cast<std::uint8_t>(type))
    {
      continue;
    }
    for (Index k = lines.Offsets[l]; k < lines.Offsets[l + 1]; ++k)
    {
      points.push_back(Point(lines.Points.data(), lines.Connectivity[k]));
    }
  }
  return points;
}

/// The options of the scan tests: ridges and valleys drawn too.
LineDrawingOptions CurvatureLines()
{
  LineDrawingOptions o;
  o.Draw[int(LineType::Ridge)] = o.Draw[int(LineType::Valley)] = true;
  o.MinimumLength = 0.0; // (every piece: the tests below set what they test)
  o.HysteresisRatio = 1.0;
  return o;
}

/// The view-independent pass of bunny00 (a raw scan).
LineDrawingGeometry ScanGeometry()
{
  std::string error;
  const Mesh m = test::ReadMesh("bunny00.off", error);
  EXPECT_EQ(error, "");
  return Geometry(m);
}

/// The demo's front view of bunny00, orthographic.
LineView ScanFront()
{
  return Orthographic(-Vec3(0.0, 0.05, 1.0).normalized());
}

/// The lengths of the polylines of one type (along their points).
std::vector<double> PolylineLengths(const LineSet& lines, LineType type)
{
  std::vector<double> out;
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    if (lines.Type[l] != static_cast<std::uint8_t>(type))
    {
      continue;
    }
    double length = 0.0;
    for (Index k = lines.Offsets[l] + 1; k < lines.Offsets[l + 1]; ++k)
    {
      length += (Point(lines.Points.data(), lines.Connectivity[k]) -
        Point(lines.Points.data(), lines.Connectivity[k - 1])).norm();
    }
    out.push_back(length);
  }
  return out;
}

double Bump(double x, double y, double h, double s)
{
  return h * std::exp(-(x * x + y * y) / (2 * s * s));
}

/// The worst relative distance of the suggestive-contour points of the bump
/// (s = 1) seen from above to the inflection circle r = s, and their count.
std::pair<double, std::size_t> BumpContourError(int n)
{
  const Mesh m = test::HeightField([](double x, double y) { return Bump(x, y, 1.0, 1.0); }, 3.0, n, 0.0, false, 1);
  const LineDrawingGeometry geo = Geometry(m);
  LineDrawingOptions o = Only(LineType::SuggestiveContour);
  o.SuggestiveThreshold = 0.0;
  const LineSet lines = DrawLines(geo, Orthographic({ 0, 0, -1 }), o);
  double worst = 0.0;
  const std::vector<Vec3> points = PointsOf(lines, LineType::SuggestiveContour);
  for (const Vec3& p : points)
  {
    worst = std::max(worst, std::abs(std::hypot(p[0], p[1]) - 1.0));
  }
  return { worst, points.size() };
}

/// The ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 from a subdivided
/// octahedron turned first (so that no vertex lies on a symmetry plane);
/// outward triangles, or inward ones when `inward`.
Mesh Ellipsoid(double a, double b, double c, int levels, bool inward)
{
  Mesh m = test::OctahedronSphere(levels);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const Eigen::Vector3d p = turn * m.Point(i);
    m.SetPoint(i, { a * p[0], b * p[1], c * p[2] });
  }
  if (inward)
  {
    for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      std::swap(m.Triangles[t + 1], m.Triangles[t + 2]);
    }
  }
  return m;
}

/// Distance from p to the nearest segment of the lines of one type.
double DistanceToLines(const LineSet& lines, LineType type, const Vec3& p)
{
  double best = std::numeric_limits<double>::infinity();
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    if (lines.Type[l] != static_cast<std::uint8_t>(type))
    {
      continue;
    }
    for (Index k = lines.Offsets[l]; k + 1 < lines.Offsets[l + 1]; ++k)
    {
      const Vec3 a = Point(lines.Points.data(), lines.Connectivity[k]);
      const Vec3 b = Point(lines.Points.data(), lines.Connectivity[k + 1]);
      const double t = std::clamp((p - a).dot(b - a) / std::max(1e-300, (b - a).squaredNorm()), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - p).norm());
    }
  }
  return best;
}

Index CountLines(const LineSet& lines, LineType type, bool closedOnly = false)
{
  Index count = 0;
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    count += lines.Type[l] == static_cast<std::uint8_t>(type) && (!closedOnly || lines.Closed[l]);
  }
  return count;
}

} // namespace

TEST(LineDrawing, CurvatureDerivativeOfBump)
{
  // Along a meridian (a geodesic), C(r,r,r) is the arc-length derivative of
  // the meridian's curvature: compare with the analytic value.
  const double h = 1.0, s = 1.0;
  const Mesh m = test::HeightField([&](double x, double y) { return Bump(x, y, h, s); }, 3.0, 121, 0.0, false, 1);
  const LineDrawingGeometry geo = Geometry(m);
  double worst = 0.0, scale = 0.0;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    const Eigen::Vector3d p = m.Point(i);
    const double rho = std::hypot(p[0], p[1]);
    if (rho < 0.4 || rho > 2.5)
    {
      continue; // (the umbilic at the top leaves the directions undefined)
    }
    const double f = Bump(p[0], p[1], h, s), f1 = -rho / (s * s) * f, f2 = f * (rho * rho / std::pow(s, 4) - 1 / (s * s));
    const double f3 = f * (3 * rho / std::pow(s, 4) - std::pow(rho, 3) / std::pow(s, 6));
    const double q = 1 + f1 * f1;
    const double expected = -(f3 * q - 3 * f1 * f2 * f2) / std::pow(q, 2.5) / std::sqrt(q);
    const Vec3 radial = Vec3(p[0] / rho, p[1] / rho, f1).normalized();
    double r[2] = { radial.dot(Point(geo.E1.data(), i)), radial.dot(Point(geo.E2.data(), i)) };
    const double norm = std::hypot(r[0], r[1]);
    r[0] /= norm;
    r[1] /= norm;
    const double estimate = EvaluateCubicForm(geo.Derivatives.data() + 4 * i, r, r, r);
    worst = std::max(worst, std::abs(estimate - expected));
    scale = std::max(scale, std::abs(expected));
  }
  std::printf("bump C(r,r,r): worst error %.4f of max %.4f\n", worst, scale);
  EXPECT_LT(worst, 0.05 * scale); // (largest near the top's umbilic)
}

TEST(LineDrawing, SphereDerivativesVanish)
{
  const LineDrawingGeometry geo = Geometry(test::OctahedronSphere(5, 2.0));
  double worst = 0.0;
  for (double c : geo.Derivatives)
  {
    worst = std::max(worst, std::abs(c));
  }
  std::printf("sphere |C| max %.5f (1/R^2 = 0.25)\n", worst);
  EXPECT_LT(worst, 0.01 * 0.25);
}

TEST(LineDrawing, BumpSuggestiveContourOnInflectionCircle)
{
  double previous = 1.0;
  for (int n : { 61, 121, 241 })
  {
    const auto [error, count] = BumpContourError(n);
    std::printf("bump n=%d: %zu points, worst |r - s|/s = %.5f\n", n, count, error);
    EXPECT_GT(count, 100u);
    EXPECT_LT(error, previous / 2.5) << "the error shrinks with refinement";
    previous = error;
  }
  EXPECT_LT(previous, 0.01);
}

TEST(LineDrawing, SphereContoursAreGreatCircles)
{
  const Mesh m = test::OctahedronSphere(5);
  const LineDrawingGeometry geo = Geometry(m);
  const Vec3 d = Vec3(1, 2, 3).normalized();
  LineDrawingOptions o; // defaults: contours, suggestive contours, boundaries, creases
  const LineSet lines = DrawLines(geo, Orthographic(d), o);
  const std::vector<Vec3> contour = PointsOf(lines, LineType::Contour);
  double worst = 0.0;
  for (const Vec3& p : contour)
  {
    worst = std::max(worst, std::abs(p.dot(d)));
  }
  std::printf("sphere: %zu contour points, worst |p.d| %.5f, %d lines\n", contour.size(), worst,
    lines.NumberOfLines());
  EXPECT_GT(contour.size(), 100u);
  EXPECT_LT(worst, 0.01); // the zero set of n.v interpolated on chords of a sphere of 4098 vertices
  EXPECT_EQ(lines.NumberOfLines(), 1) << "one closed contour, nothing else";
  EXPECT_EQ(CountLines(lines, LineType::Contour, true), 1);
  // No suggestive contours even without a threshold: kappa_r = 1 everywhere.
  LineDrawingOptions all = Only(LineType::SuggestiveContour);
  all.SuggestiveThreshold = 0.0;
  all.SuggestiveAngle = 0.0;
  EXPECT_EQ(DrawLines(geo, Orthographic(d), all).NumberOfLines(), 0);
  // Perspective from (0, 0, 5): the contour is the circle z = 1/5.
  LineView camera;
  camera.Position = Vec3(0, 0, 5);
  const LineSet near = DrawLines(geo, camera, o);
  worst = 0.0;
  for (const Vec3& p : PointsOf(near, LineType::Contour))
  {
    worst = std::max(worst, std::abs(p[2] - 0.2));
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_EQ(CountLines(near, LineType::Contour, true), 1);
}

TEST(LineDrawing, EllipsoidRidgesAndValleysInCoordinatePlanes)
{
  const double axes[3] = { 3.0, 2.0, 1.0 };
  for (bool inward : { false, true })
  {
    const Mesh m = Ellipsoid(axes[0], axes[1], axes[2], 6, inward);
    const LineDrawingGeometry geo = Geometry(m);
    const LineType type = inward ? LineType::Valley : LineType::Ridge;
    LineDrawingOptions o = Only(type);
    o.DropBackFacing = false;
    o.RidgeThreshold = 0.05; // kappa > 0.67 with the automatic feature size (the default 0.4 keeps none: max kappa 3)
    const LineSet lines = DrawLines(geo, Orthographic({ 0, 0, -1 }), o);
    const std::vector<Vec3> points = PointsOf(lines, type);
    std::vector<double> distance; // to the nearest coordinate plane, relative to its axis
    for (const Vec3& p : points)
    {
      distance.push_back(std::min({ std::abs(p[0]) / axes[0], std::abs(p[1]) / axes[1], std::abs(p[2]) / axes[2] }));
    }
    std::sort(distance.begin(), distance.end());
    ASSERT_GT(distance.size(), 300u);
    const double median = distance[distance.size() / 2], q90 = distance[distance.size() * 9 / 10];
    std::printf("ellipsoid %s: %zu points in %d lines; distance to a coordinate plane: median %.4f, 90%% %.4f, max %.4f\n",
      inward ? "valleys" : "ridges", points.size(), lines.NumberOfLines(), median, q90, distance.back());
    EXPECT_LT(median, 0.005);
    EXPECT_LT(q90, 0.015);
    EXPECT_EQ(CountLines(lines, inward ? LineType::Ridge : LineType::Valley), 0);
  }
}

TEST(LineDrawing, TorusSuggestiveContoursEndOnContours)
{
  const Mesh m = test::Torus(2.0, 1.0, 240, 120, 0.0, 1);
  const LineDrawingGeometry geo = Geometry(m);
  LineDrawingOptions o;
  o.Draw[int(LineType::Boundary)] = o.Draw[int(LineType::Crease)] = false;
  o.SuggestiveThreshold = 0.0;
  o.SuggestiveAngle = 0.0;
  const LineSet lines = DrawLines(geo, Orthographic(Vec3(0, -1, -0.8).normalized()), o);
  const double edge = 2 * M_PI * 1.0 / 120;
  // DeCarlo et al.: suggestive contours meet the contours.  An end is either
  // on a contour or where D_r kappa_r falls to the threshold (here 0: the
  // strength there is 0), where the zero set of kappa_r goes on as no line.
  int onContour = 0, atThreshold = 0, unexplained = 0;
  for (Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    if (lines.Type[l] != static_cast<std::uint8_t>(LineType::SuggestiveContour) || lines.Closed[l])
    {
      continue;
    }
    for (Index k : { lines.Offsets[l], lines.Offsets[l + 1] - 1 })
    {
      const Index id = lines.Connectivity[k];
      if (DistanceToLines(lines, LineType::Contour, Point(lines.Points.data(), id)) < 2 * edge)
      {
        ++onContour;
      }
      else if (std::abs(lines.PointStrength[id]) < 1e-9)
      {
        ++atThreshold;
      }
      else
      {
        ++unexplained;
      }
    }
  }
  std::printf("torus: %d contours (%d closed), %d suggestive contours: %d ends on a contour, %d where D_r kappa_r = 0, "
              "%d other\n",
    CountLines(lines, LineType::Contour), CountLines(lines, LineType::Contour, true),
    CountLines(lines, LineType::SuggestiveContour), onContour, atThreshold, unexplained);
  EXPECT_GE(onContour, 2);
  EXPECT_EQ(unexplained, 0);
  EXPECT_EQ(CountLines(lines, LineType::Contour), CountLines(lines, LineType::Contour, true))
    << "contours of a closed smooth surface are closed";
}

TEST(LineDrawing, CadCreasesGetNoCurvatureLines)
{
  // fandisk from the regression image's side: at its creases the curvature
  // estimates see the crease, and suggestive contours and ridges followed
  // them.  With AvoidCreases (default) the curvature lines leave the
  // triangles at crease vertices; the contours and creases stay the same.
  std::string error;
  const Mesh m = test::ReadMesh("fandisk.off", error);
  ASSERT_EQ(error, "");
  const LineDrawingGeometry geo = Geometry(m);
  double edge = 0.0; // the mean edge length (fandisk is closed: each edge twice)
  for (std::size_t c = 0; c < geo.Triangles.size(); ++c)
  {
    const Index a = geo.Triangles[c], b = geo.Triangles[c % 3 == 2 ? c - 2 : c + 1];
    edge += (Point(geo.Points.data(), a) - Point(geo.Points.data(), b)).norm() / geo.Triangles.size();
  }
  LineDrawingOptions o;
  o.Draw[int(LineType::Ridge)] = o.Draw[int(LineType::Valley)] = true;
  const LineView view = Orthographic(-Vec3(1, 0.6, 0.8).normalized());
  const LineSet avoiding = DrawLines(geo, view, o);
  o.AvoidCreases = false;
  const LineSet plain = DrawLines(geo, view, o);
  const auto nearCreases = [&](const LineSet& lines, LineType type) {
    int near = 0;
    for (const Vec3& p : PointsOf(lines, type))
    {
      near += DistanceToLines(lines, LineType::Crease, p) < 1.5 * edge;
    }
    return near;
  };
  for (LineType type : { LineType::SuggestiveContour, LineType::Ridge, LineType::Valley })
  {
    std::printf("type %d: points within 1.5 edges of a crease %d -> %d (of %zu -> %zu)\n", int(type),
      nearCreases(plain, type), nearCreases(avoiding, type), PointsOf(plain, type).size(),
      PointsOf(avoiding, type).size());
  }
  // Measured: suggestive-contour points 156 -> 45 (all of them within 1.5
  // mean edge lengths of a crease: the 45 left lie along the concave
  // cylinder, on triangles without a crease vertex), ridge points 666 -> 0,
  // valley points 153 -> 0 (all of them creases drawn again).
  EXPECT_LE(PointsOf(avoiding, LineType::SuggestiveContour).size(),
    0.35 * PointsOf(plain, LineType::SuggestiveContour).size());
  EXPECT_GT(nearCreases(plain, LineType::Ridge) + nearCreases(plain, LineType::Valley), 500);
  EXPECT_EQ(nearCreases(avoiding, LineType::Ridge) + nearCreases(avoiding, LineType::Valley), 0);
  EXPECT_EQ(PointsOf(avoiding, LineType::Contour).size(), PointsOf(plain, LineType::Contour).size());
  EXPECT_EQ(PointsOf(avoiding, LineType::Crease).size(), PointsOf(plain, LineType::Crease).size());
}

TEST(LineDrawing, MinimumLengthDropsShortCurvatureLinesOfAScan)
{
  // bunny00, a raw scan, from the demo's front: its noise breaks the
  // suggestive contours, ridges and valleys into short pieces and draws
  // small contour loops around its bumps.  With MinimumLength 2 every such
  // polyline left (contours too) is at least two feature sizes long (its
  // length summed over its points, closed ones around), the short ones are
  // gone, every long one stays, and boundaries are untouched.
  const LineDrawingGeometry geo = ScanGeometry();
  LineDrawingOptions o = CurvatureLines();
  const LineView view = ScanFront();
  const LineSet all = DrawLines(geo, view, o);
  o.MinimumLength = 2.0;
  const LineSet kept = DrawLines(geo, view, o);
  const double shortest = 2.0 * geo.AutomaticFeatureSize();
  const auto lengths = PolylineLengths;
  for (LineType type : { LineType::Contour, LineType::SuggestiveContour, LineType::Ridge, LineType::Valley })
  {
    const std::vector<double> before = lengths(all, type), after = lengths(kept, type);
    const auto longEnough = std::count_if(before.begin(), before.end(), [&](double x) { return x >= shortest; });
    std::printf("type %d: %zu polylines -> %zu (%ld of them at least 2 feature sizes long)\n", int(type),
      before.size(), after.size(), static_cast<long>(longEnough));
    EXPECT_EQ(static_cast<std::ptrdiff_t>(after.size()), longEnough) << int(type);
    if (type != LineType::Contour)
    {
      EXPECT_LT(after.size(), before.size() / 2) << int(type); // mostly short pieces on a scan
    }
    EXPECT_GT(after.size(), 0u) << int(type);
    for (double x : after)
    {
      EXPECT_GE(x, shortest) << int(type);
    }
  }
  EXPECT_EQ(PointsOf(kept, LineType::Boundary), PointsOf(all, LineType::Boundary));
}

TEST(LineDrawing, HysteresisJoinsTheBrokenCurvatureLinesOfAScan)
{
  // bunny00 from the demo's front.  With HysteresisRatio 0.5 the curvature
  // lines are traced down to half their thresholds and kept where they pass
  // the full one somewhere: every such polyline has a point past the full
  // threshold and none below the half; every piece drawn without
  // hysteresis lies on a line drawn with it; and the lines are fewer and
  // at least 1.4x longer on average (measured: suggestive contours 1.5x,
  // ridges 2.4x, valleys 1.8x), since the noise no longer breaks them
  // wherever it dips below the threshold.
  const LineDrawingGeometry geo = ScanGeometry();
  LineDrawingOptions o = CurvatureLines();
  const LineView view = ScanFront();
  const LineSet plain = DrawLines(geo, view, o);
  o.HysteresisRatio = 0.5;
  const LineSet joined = DrawLines(geo, view, o);
  const double size = geo.AutomaticFeatureSize();
  const auto summary = [&](const LineSet& lines, LineType type, double threshold, bool check) {
    for (Index l = 0; check && l < lines.NumberOfLines(); ++l)
    {
      double peak = -1e300, low = 1e300;
      for (Index k = lines.Offsets[l]; lines.Type[l] == static_cast<std::uint8_t>(type) && k < lines.Offsets[l + 1]; ++k)
      {
        peak = std::max(peak, lines.PointStrength[lines.Connectivity[k]]);
        low = std::min(low, lines.PointStrength[lines.Connectivity[k]]);
      }
      if (lines.Type[l] == static_cast<std::uint8_t>(type))
      {
        EXPECT_GE(peak, threshold) << int(type);
        EXPECT_GE(low, 0.5 * threshold - 1e-9) << int(type);
      }
    }
    const std::vector<double> lengths = PolylineLengths(lines, type);
    return std::make_pair(static_cast<int>(lengths.size()), std::accumulate(lengths.begin(), lengths.end(), 0.0));
  };
  const double thresholds[3] = { o.SuggestiveThreshold, o.RidgeThreshold, o.RidgeThreshold };
  const LineType types[3] = { LineType::SuggestiveContour, LineType::Ridge, LineType::Valley };
  for (int t = 0; t < 3; ++t)
  {
    const auto before = summary(plain, types[t], thresholds[t], false);
    const auto after = summary(joined, types[t], thresholds[t], true);
    std::printf("type %d: %d polylines, mean length %.3f feature sizes -> %d, %.3f\n", int(types[t]), before.first,
      before.second / before.first / size, after.first, after.second / after.first / size);
    EXPECT_LT(after.first, before.first) << int(types[t]);
    EXPECT_GT(after.second / after.first, 1.4 * before.second / before.first) << int(types[t]);
    EXPECT_GT(after.second, before.second) << int(types[t]);
    // Every point drawn without hysteresis is on a line drawn with it (on
    // one of its pieces: the plain pieces are parts of the longer ones).
    std::vector<std::pair<Vec3, Vec3>> pieces;
    for (Index l = 0; l < joined.NumberOfLines(); ++l)
    {
      for (Index k = joined.Offsets[l] + 1; joined.Type[l] == static_cast<std::uint8_t>(types[t]) &&
           k < joined.Offsets[l + 1]; ++k)
      {
        pieces.emplace_back(Point(joined.Points.data(), joined.Connectivity[k - 1]),
          Point(joined.Points.data(), joined.Connectivity[k]));
      }
    }
    double worst = 0.0;
    for (const Vec3& p : PointsOf(plain, types[t]))
    {
      double nearest = 1e300;
      for (const auto& [a, b] : pieces)
      {
        const double along = std::clamp((p - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
        nearest = std::min(nearest, (p - (a + along * (b - a))).norm());
      }
      worst = std::max(worst, nearest);
    }
    EXPECT_LT(worst, 1e-9 * size) << int(types[t]);
  }
  for (LineType type : { LineType::Contour, LineType::Boundary })
  {
    EXPECT_EQ(PointsOf(joined, type), PointsOf(plain, type)) << int(type);
  }
}

TEST(LineDrawing, SmoothedFieldsKeepTheShapesLinesOnTheSurface)
{
  // Curvature smoothing (the fields of a faired copy, 0.5 feature sizes).
  // A sphere's faired copy is a smaller sphere, so its contour stays the
  // great circle, and the lines lie on the surface itself (|p| = 1 within
  // the chords' sag, as without smoothing).  bunny00, a raw scan: the
  // suggestive contours of its noise go (at least half of the pieces),
  // while the contours, the shape's own lines, stay within a feature size
  // of those of the surface itself.  The copy is faired at the scale of
  // its length by a power of two: 2^300 times the points give 2^300 times
  // the copy, bit for bit.
  const Mesh m = test::OctahedronSphere(5);
  const MeshTopology topology = m.Topology(0);
  FieldSmoothingOptions smoothing;
  smoothing.Amount = 4.0; // (a copy well inside the chords' sag: the test can tell)
  LineDrawingGeometry sphere;
  sphere.Build(topology, m.Points.data(), 0, nullptr, smoothing);
  ASSERT_TRUE(sphere.Smoothed) << sphere.SmoothingWarning;
  const Vec3 d = Vec3(1, 2, 3).normalized();
  const std::vector<Vec3> contour = PointsOf(DrawLines(sphere, Orthographic(d), LineDrawingOptions{}), LineType::Contour);
  double offPlane = 0.0, offSphere = 0.0, shrunk = 0.0;
  for (const Vec3& p : contour)
  {
    offPlane = std::max(offPlane, std::abs(p.dot(d)));
    offSphere = std::max(offSphere, 1.0 - p.norm());
  }
  for (Index v = 0; v < sphere.NumberOfVertices(); ++v)
  {
    shrunk = std::max(shrunk, 1.0 - Point(sphere.FairedPoints.data(), v).norm());
  }
  std::printf("smoothed sphere: %zu contour points, worst |p.d| %.5f, 1 - |p| %.5f; the copy shrank by %.5f\n",
    contour.size(), offPlane, offSphere, shrunk);
  EXPECT_GT(contour.size(), 100u);
  EXPECT_LT(offPlane, 0.01);
  EXPECT_LT(offSphere, 0.002);    // on the triangles (the chords' sag), not on the copy
  EXPECT_GT(shrunk, 2 * offSphere);

  std::vector<double> huge(m.Points.begin(), m.Points.end());
  for (double& x : huge)
  {
    x = std::ldexp(x, 300);
  }
  std::string warning;
  const std::vector<double> a = FairedCopy(topology, m.Points.data(), 0.05, 0, nullptr, warning);
  const std::vector<double> b = FairedCopy(topology, huge.data(), std::ldexp(0.05, 300), 0, nullptr, warning);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    ASSERT_EQ(std::ldexp(a[k], 300), b[k]) << k;
  }

  const LineDrawingGeometry raw = ScanGeometry();
  std::string error;
  const Mesh scan = test::ReadMesh("bunny00.off", error);
  LineDrawingGeometry smoothed;
  smoothing.Amount = 0.5;
  smoothed.Build(scan.Topology(0), scan.Points.data(), 0, nullptr, smoothing);
  LineDrawingOptions o = CurvatureLines();
  o.MinimumLength = 0.0;
  o.HysteresisRatio = 1.0;
  const LineSet before = DrawLines(raw, ScanFront(), o), after = DrawLines(smoothed, ScanFront(), o);
  const Index pieces[2] = { CountLines(before, LineType::SuggestiveContour),
    CountLines(after, LineType::SuggestiveContour) };
  std::vector<double> near;
  for (const Vec3& p : PointsOf(after, LineType::Contour))
  {
    near.push_back(DistanceToLines(before, LineType::Contour, p) / raw.AutomaticFeatureSize());
  }
  std::sort(near.begin(), near.end());
  const double within = near[near.size() * 9 / 10];
  std::printf("bunny00: %d suggestive contour pieces -> %d smoothed; 90%% of its contours' points within %.2f "
              "feature sizes of the raw ones (median %.2f)\n",
    int(pieces[0]), int(pieces[1]), within, near[near.size() / 2]);
  EXPECT_LT(2 * pieces[1], pieces[0]);
  EXPECT_LT(within, 1.0);
}
