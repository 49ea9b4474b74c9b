// The triangle tree of the visibility rays: every segment query answered as
// by testing all the triangles, and the tree built on several threads
// answering as the one built on one.
#include "TestMeshes.h"

#include "Mesh/TriangleTree.h"

#include <gtest/gtest.h>

#include <random>

using namespace beltrami;

namespace
{

/// Whether segment o + t d, 0 < t < 1, passes through triangle abc (the
/// plain test, no slack).
bool Crosses(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 n = (b - a).cross(c - a);
  const double den = n.dot(d);
  if (std::abs(den) < 1e-300)
  {
    return false;
  }
  const double t = n.dot(a - o) / den;
  if (!(t > 1e-9 && t < 1.0))
  {
    return false;
  }
  const Vec3 p = o + t * d;
  return n.dot((b - a).cross(p - a)) >= 0.0 && n.dot((c - b).cross(p - b)) >= 0.0 &&
    n.dot((a - c).cross(p - c)) >= 0.0;
}

} // namespace

TEST(TriangleTree, AnswersAsEveryTriangleWhateverTheThreads)
{
  // bunny00 (75k triangles): 1000 random segments between points of its
  // box, far from any triangle's edge or not; the tree's answer against all
  // the triangles tested one by one (a ray that passes within 1e-9 of an
  // edge may differ: none of these), and trees built on 1, 2 and 4 threads
  // give the same answers.
  std::string error;
  const test::Mesh m = test::ReadMesh("bunny00.off", error);
  ASSERT_EQ(error, "");
  const std::size_t triangles = m.Triangles.size() / 3;
  const TriangleTree one(m.Points.data(), m.Triangles.data(), triangles, 1);
  const TriangleTree two(m.Points.data(), m.Triangles.data(), triangles, 2);
  const TriangleTree four(m.Points.data(), m.Triangles.data(), triangles, 4);
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < m.Points.size() / 3; ++i)
  {
    lo = lo.cwiseMin(m.Point(static_cast<Index>(i)));
    hi = hi.cwiseMax(m.Point(static_cast<Index>(i)));
  }
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto somewhere = [&]() {
    return Vec3(lo[0] + unit(random) * (hi[0] - lo[0]), lo[1] + unit(random) * (hi[1] - lo[1]),
      lo[2] + unit(random) * (hi[2] - lo[2]));
  };
  int blocked = 0;
  const auto none = [](Index) { return false; };
  for (int k = 0; k < 1000; ++k)
  {
    const Vec3 o = somewhere(), d = somewhere() - o;
    bool brute = false;
    for (std::size_t t = 0; t < triangles && !brute; ++t)
    {
      const Index* v = m.Triangles.data() + 3 * t;
      brute = Crosses(o, d, Point(m.Points.data(), v[0]), Point(m.Points.data(), v[1]), Point(m.Points.data(), v[2]));
    }
    const bool a = one.Blocks(o, d, 1e-9, none);
    ASSERT_EQ(a, brute) << k;
    ASSERT_EQ(two.Blocks(o, d, 1e-9, none), a) << k;
    ASSERT_EQ(four.Blocks(o, d, 1e-9, none), a) << k;
    blocked += a;
  }
  std::printf("%d of 1000 segments blocked\n", blocked);
  EXPECT_GT(blocked, 100);
  EXPECT_LT(blocked, 900);
}
