// The anisotropic remesh (Remeshing/RemeshMetric and the remesher with a
// metric): the metric from the curvature tensor on a cylinder and a plane,
// remeshes stretched along the directions of least curvature, measured in
// the metric (edge lengths, angles) and in 3D (alignment with the principal
// directions, the two-sided deviation against the isotropic remesh of the
// same count), the metric's scale, and the error-driven mode.
#include "Mesh/SurfaceDistance.h"
#include "Remeshing/RemeshMetric.h"
#include "Remeshing/SurfaceRemeshing.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace beltrami;

namespace
{

Eigen::Matrix3d Full(const double* t)
{
  Eigen::Matrix3d m;
  m << t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2];
  return m;
}

/// A surface with its atlas for the remesher.
struct Surface
{
  test::Mesh Mesh;
  MeshTopology Topology;
  AtlasResult Atlas;
  explicit Surface(test::Mesh mesh)
    : Mesh(std::move(mesh)), Topology(Mesh.Topology()),
      Atlas(BuildAtlas(Topology, Mesh.Points.data(), RemeshingAtlasOptions()))
  {
  }
  const double* Points() const { return Mesh.Points.data(); }
};

/// The largest of the remesh's two deviations (fractions of the diagonal).
double Deviation(const RemeshResult& r)
{
  return std::max(r.DeviationToInput, r.DeviationFromInput);
}

/// An ellipsoid of semi-axes (1, 1, 3): the octahedral sphere stretched.
test::Mesh Ellipsoid()
{
  test::Mesh m = test::OctahedronSphere(6);
  for (Index v = 0; v < m.NumberOfVertices(); ++v)
  {
    m.Points[3 * v + 2] *= 3.0;
  }
  return m;
}

/// The mean angle (degrees) between the remesh edges of a surface of
/// revolution about z, in the tangent plane, and the nearer of its
/// principal directions (the meridian and the circle around the axis),
/// over the edges where the ratio of the principal curvatures exceeds 3:
/// the cylinder of radius 1 (c = 0) or the spheroid of semi-axes (1, 1, c),
/// where the ratio is sin^2 b + c^2 cos^2 b at reduced latitude b.
double MeanDeviationFromThePrincipalDirections(const RemeshResult& r, double c = 0.0)
{
  double sum = 0.0;
  int count = 0;
  for (std::size_t t = 0; t < r.Triangles.size(); t += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 a = Point(r.Points.data(), r.Triangles[t + k]), b = Point(r.Points.data(), r.Triangles[t + (k + 1) % 3]);
      const Vec3 m = 0.5 * (a + b);
      if (c > 0.0)
      {
        const double sine = std::clamp(m[2] / c, -1.0, 1.0);
        if (sine * sine + c * c * (1.0 - sine * sine) <= 3.0)
        {
          continue;
        }
      }
      const Vec3 n = Vec3(m[0], m[1], c > 0.0 ? m[2] / (c * c) : 0.0).normalized();
      const Vec3 around = Vec3(-m[1], m[0], 0.0).normalized();
      Vec3 d = b - a;
      d = (d - d.dot(n) * n).normalized();
      const double toCircle = std::acos(std::min(1.0, std::abs(d.dot(around)))) * 180.0 / M_PI;
      sum += std::min(toCircle, 90.0 - toCircle);
      ++count;
    }
  }
  return sum / std::max(1, count);
}

} // namespace

TEST(AnisotropicRemeshing, CylinderMetricIsThePrincipalCurvaturesWithTheAnisotropyCapped)
{
  // Radius 1: kappa 1 around, 0 along, so the metric is 1 around and
  // 1 / 6^2 along (MaximumAnisotropy 6), its density 1 / 6.
  const test::Mesh cylinder = test::Cylinder(1.0, 4.0, 200, 160);
  const MeshTopology topology = cylinder.Topology();
  const MetricResult metric = CurvatureMetric(topology, cylinder.Points.data(), MetricOptions());
  ASSERT_EQ(metric.Warning, "");
  int checked = 0;
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    const Vec3 p = Point(cylinder.Points.data(), v);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(Full(&metric.Metric[6 * v]));
    // (Ascending: the normal's 0, then along, then around.)
    EXPECT_NEAR(eigen.eigenvalues()[0], 0.0, 1e-9);
    EXPECT_NEAR(eigen.eigenvalues()[2], 1.0, 0.02) << v;
    EXPECT_NEAR(eigen.eigenvalues()[1] / eigen.eigenvalues()[2], 1.0 / 36.0, 1e-9) << v;
    EXPECT_LT(std::abs(eigen.eigenvectors().col(2)[2]), 1e-3) << v; // around: within 0.06 deg of the circle
    EXPECT_NEAR(std::abs(eigen.eigenvectors().col(1)[2]), 1.0, 1e-6) << v;
    EXPECT_NEAR(MetricDensity(&metric.Metric[6 * v]), eigen.eigenvalues()[2] / 6.0, 1e-9) << v;
    checked += p[2] > 0.0 && p[2] < 4.0; // (the boundary rings take their neighbours')
  }
  EXPECT_GT(checked, 30000);
}

TEST(AnisotropicRemeshing, FlatSurfaceGetsAnIsotropicUniformMetric)
{
  // A plane's curvatures are round-off: the metric is the floor's,
  // isotropic and the same everywhere (not noise's directions and ratios).
  const test::Mesh plane = test::FlatIrregular(30, 7);
  const MeshTopology topology = plane.Topology();
  const MetricResult metric = CurvatureMetric(topology, plane.Points.data(), MetricOptions());
  const double density = MetricDensity(&metric.Metric[0]);
  EXPECT_GT(density, 0.0);
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(Full(&metric.Metric[6 * v]));
    EXPECT_NEAR(eigen.eigenvalues()[1], eigen.eigenvalues()[2], 1e-9 * eigen.eigenvalues()[2]) << v;
    EXPECT_NEAR(MetricDensity(&metric.Metric[6 * v]), density, 1e-9 * density) << v;
  }
}

TEST(AnisotropicRemeshing, RemeshesAreStretchedAlongTheLeastCurvedDirectionsAndCloser)
{
  // The cylinder and an ellipsoid at 2,000 vertices: edges of unit length
  // and triangles near equilateral in the metric, the edges along the
  // principal directions (the axis or meridian and the circle around it)
  // where the principal curvatures' ratio exceeds 3, and both closer to
  // the input than the isotropic remesh of the same count.
  struct Case
  {
    const char* Name;
    test::Mesh Mesh;
    double Closer; ///< the anisotropic deviation at most this share of the isotropic
    double Axis;   ///< the spheroid's semi-axis along z (0: the cylinder)
  };
  const Case cases[] = { { "cylinder", test::Cylinder(1.0, 4.0, 200, 160), 0.5, 0.0 },
    { "ellipsoid", Ellipsoid(), 0.7, 3.0 } };
  for (const Case& c : cases)
  {
    const Surface surface(c.Mesh);
    ASSERT_EQ(surface.Atlas.Error, "") << c.Name;
    const MetricResult metric = CurvatureMetric(surface.Topology, surface.Points(), MetricOptions());
    RemeshOptions options;
    options.NumberOfVertices = 2000;
    const RemeshResult isotropic = RemeshSurface(surface.Topology, surface.Points(), surface.Atlas, nullptr, options);
    options.Metric = metric.Metric.data();
    const RemeshResult r = RemeshSurface(surface.Topology, surface.Points(), surface.Atlas, nullptr, options);
    ASSERT_EQ(r.Error, "") << c.Name;
    ASSERT_EQ(isotropic.Error, "") << c.Name;
    EXPECT_EQ(r.Points.size(), 3u * 2000u) << c.Name;
    const MetricQuality q = MeasureInMetric(
      surface.Topology, surface.Points(), r.GradedMetric.data(), r.Points, r.Triangles, r.SourceTriangle,
      r.SourceBarycentric);
    std::printf("%s at 2000: in the metric median edge %.3f, %.1f%% within 20%% of 1, smallest angle %.1f, mean "
                "smallest %.1f, %.2f%% below 30; deviation %.4f%% (isotropic %.4f%%)\n",
      c.Name, q.MedianEdgeLength, 100.0 * q.EdgesWithin20Percent, q.MinimumAngle, q.MeanMinimumAngle,
      100.0 * q.TrianglesBelow30, 100.0 * Deviation(r), 100.0 * Deviation(isotropic));
    EXPECT_NEAR(q.MedianEdgeLength, 1.0, 0.1) << c.Name;
    EXPECT_GE(q.EdgesWithin20Percent, 0.9) << c.Name;
    EXPECT_GE(q.MeanMinimumAngle, 50.0) << c.Name;
    EXPECT_LE(q.TrianglesBelow30, 0.01) << c.Name;
    EXPECT_LE(Deviation(r), c.Closer * Deviation(isotropic)) << c.Name;
    // Where the ratio of the principal curvatures exceeds 3.  A lattice
    // aligned with the metric (one edge of three along the strongest
    // direction) deviates by atan(tan(30 deg) / r) on the other two, r the
    // metric's edge ratio: on the cylinder r = 6 (the cap), 3.7 deg on
    // average; on the ellipsoid r = sqrt(ratio), 3 at the equator and 1.7
    // where the ratio is 3, 8.3 deg on average over that band.  The
    // isotropic remesh's edges about 22.5 (random).  Measured 10.5 and
    // 15.0, the short edges most: a turn f of the lattice in the metric
    // turns them by atan(r tan f) in 3D (17 deg for f = 3 deg at r = 6),
    // and the lattice's defects (a vertex in six of valence 5 or 7) turn
    // it that much.  The atlas's seams do not count (the cylinder in 1 to
    // 31 charts: 10.1-10.5); pulling to the lattice in every round instead
    // of half brings 9.2 and 13.2 with triangles below 30 degrees.
    const double aligned = MeanDeviationFromThePrincipalDirections(r, c.Axis);
    const double random = MeanDeviationFromThePrincipalDirections(isotropic, c.Axis);
    std::printf("  edges' mean deviation from the principal directions %.1f deg (isotropic %.1f)\n", aligned, random);
    EXPECT_LE(aligned, c.Axis > 0.0 ? 16.0 : 12.0) << c.Name;
    EXPECT_GE(random, 18.0) << c.Name;
  }
}

TEST(AnisotropicRemeshing, TheMetricsScaleDoesNotChangeTheRemesh)
{
  // The remesher scales the metric to the count: any scale (a power of two
  // here, exact) gives the same remesh, bit for bit.
  const Surface surface(test::Cylinder(1.0, 4.0, 100, 80));
  const MetricResult metric = CurvatureMetric(surface.Topology, surface.Points(), MetricOptions());
  std::vector<double> scaled = metric.Metric;
  for (double& x : scaled)
  {
    x = std::ldexp(x, -80);
  }
  RemeshOptions options;
  options.NumberOfVertices = 500;
  options.Metric = metric.Metric.data();
  const RemeshResult a = RemeshSurface(surface.Topology, surface.Points(), surface.Atlas, nullptr, options);
  options.Metric = scaled.data();
  const RemeshResult b = RemeshSurface(surface.Topology, surface.Points(), surface.Atlas, nullptr, options);
  ASSERT_EQ(a.Error, "");
  EXPECT_EQ(a.Points, b.Points);
  EXPECT_EQ(a.Triangles, b.Triangles);
}

TEST(AnisotropicRemeshing, ErrorDrivenModeMeetsTheBoundWithFewerVertices)
{
  // The cylinder within 0.05% of its diagonal both ways: with the metric,
  // fewer than half the isotropic mode's vertices.
  const Surface surface(test::Cylinder(1.0, 4.0, 200, 160));
  const MetricResult metric = CurvatureMetric(surface.Topology, surface.Points(), MetricOptions());
  RemeshOptions options;
  options.NumberOfVertices = 0;
  const DeviationRemeshResult isotropic =
    RemeshToDeviation(surface.Topology, surface.Points(), surface.Atlas, nullptr, options, 5e-4);
  options.Metric = metric.Metric.data();
  const DeviationRemeshResult r = RemeshToDeviation(surface.Topology, surface.Points(), surface.Atlas, nullptr, options, 5e-4);
  std::printf("cylinder within 0.05%%: %zu vertices (isotropic %zu) in %d rounds\n", r.Remesh.Points.size() / 3,
    isotropic.Remesh.Points.size() / 3, r.Rounds);
  EXPECT_TRUE(r.Met);
  EXPECT_TRUE(isotropic.Met);
  EXPECT_LE(Deviation(r.Remesh), 5e-4);
  EXPECT_LT(r.Remesh.Points.size(), isotropic.Remesh.Points.size() / 2);
}
