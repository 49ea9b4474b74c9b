// The triangle grid of the distances between surfaces (every nearest
// triangle as found by testing all of them, with and without a bound on
// the search) and the points inside a closed surface's cavities.
#include "TestMeshes.h"

#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceDistance.h"

#include <gtest/gtest.h>

#include <random>

using namespace beltrami;

TEST(TriangleGrid, FindsTheNearestTriangleAsEveryTriangleWithinAnyBound)
{
  // Points in and around a sphere of 258 vertices (and far off it): the
  // grid's distance is the least over all triangles; bounded by a distance
  // a little above or below it, the search finds that triangle or none.
  const test::Mesh sphere = test::OctahedronSphere(3);
  const std::size_t triangles = sphere.Triangles.size() / 3;
  const TriangleGrid grid(sphere.Points.data(), sphere.Triangles.data(), triangles, 2);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
  int bounded = 0;
  for (int k = 0; k < 2000; ++k)
  {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
    double least = HUGE_VAL, w[3];
    for (std::size_t t = 0; t < triangles; ++t)
    {
      const Index* c = sphere.Triangles.data() + 3 * t;
      least = std::min(least,
        ClosestPointOnTriangle(p, sphere.Point(c[0]), sphere.Point(c[1]), sphere.Point(c[2]), w));
    }
    least = std::sqrt(least);
    double distance = 0.0;
    const Index nearest = grid.Nearest(p, distance);
    ASSERT_GE(nearest, 0);
    EXPECT_NEAR(distance, least, 1e-12);
    double within = 0.0;
    EXPECT_EQ(grid.Nearest(p, within, 1.01 * least + 1e-9), nearest);
    EXPECT_NEAR(within, least, 1e-12);
    EXPECT_EQ(grid.Nearest(p, within, 0.99 * least), -1);
    EXPECT_EQ(within, 0.99 * least);
    bounded += least > 0.0;
  }
  EXPECT_GT(bounded, 1900);
  double distance = 0.0;
  EXPECT_EQ(grid.Nearest(Vec3(100.0, -50.0, 20.0), distance), grid.Nearest(Vec3(100.0, -50.0, 20.0), distance, 1e3));
  EXPECT_EQ(grid.Nearest(Vec3(HUGE_VAL, 0.0, 0.0), distance), -1);
  EXPECT_EQ(distance, HUGE_VAL);
}

TEST(CavityPoints, OneInsideEachInnerWallFacingInwards)
{
  // A hollow ball: a sphere with one of half its radius inside, facing
  // inwards (the void's wall), its point inside the small sphere and off
  // its surface; the same inner sphere facing outwards (a solid within a
  // solid), a lone sphere, and a lone inner wall have none.
  const test::Mesh outer = test::OctahedronSphere(3);
  test::Mesh inner = test::OctahedronSphere(3, 0.5);
  const test::Mesh solids = test::Merged(outer, inner, Vec3::Zero());
  for (std::size_t t = 0; t < inner.Triangles.size(); t += 3)
  {
    std::swap(inner.Triangles[t + 1], inner.Triangles[t + 2]);
  }
  const test::Mesh hollow = test::Merged(outer, inner, Vec3(0.1, 0.0, 0.0));
  const std::vector<Vec3> cavities = CavityPoints(hollow.Topology(), hollow.Points.data());
  ASSERT_EQ(cavities.size(), 1u);
  const double radius = (cavities[0] - Vec3(0.1, 0.0, 0.0)).norm();
  EXPECT_LT(radius, 0.5 * 0.97);
  EXPECT_GT(radius, 0.3);
  EXPECT_TRUE(CavityPoints(solids.Topology(), solids.Points.data()).empty());
  EXPECT_TRUE(CavityPoints(outer.Topology(), outer.Points.data()).empty());
  EXPECT_TRUE(CavityPoints(inner.Topology(), inner.Points.data()).empty());
}
