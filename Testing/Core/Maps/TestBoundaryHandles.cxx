// Boundary handles moved through a kept boundary basis (thesis section
// 5.4.2, interactive use): one handle translates its loop and the map, two
// handles interpolate their displacements by arc length, the map is the one
// a solve with that boundary gives, and bad handles are refused.
#include "Maps/BoundaryHandles.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace beltrami;

namespace
{
test::Mesh ReadMesh(const std::string& name)
{
  std::string error;
  test::Mesh m = test::ReadMesh(name, error);
  EXPECT_EQ(error, "");
  return m;
}

/// A disk, its circle parameterization and the boundary basis kept.
struct Kept
{
  explicit Kept(const std::string& name)
    : Mesh(ReadMesh(name))
    , Topology(Mesh.Topology())
  {
    ParameterizationOptions o;
    o.Boundary = ParameterizationBoundary::Circle;
    o.KeepBoundaryBasis = true;
    Result = Parameterize(Topology, Mesh.Points.data(), o);
    EXPECT_EQ(Result.Error, "");
    EXPECT_TRUE(Result.Basis);
  }
  test::Mesh Mesh;
  MeshTopology Topology;
  ParameterizationResult Result;
};

BoundaryHandle Handle(Index v, double u, double w)
{
  BoundaryHandle h;
  h.Vertex = v;
  h.Target[0] = u;
  h.Target[1] = w;
  return h;
}

double Length(const test::Mesh& m, Index a, Index b)
{
  double s = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    s += (m.Points[3 * a + d] - m.Points[3 * b + d]) * (m.Points[3 * a + d] - m.Points[3 * b + d]);
  }
  return std::sqrt(s);
}
} // namespace

TEST(BoundaryHandles, OneHandleTranslatesTheMap)
{
  const Kept k("patch-01.off");
  const std::vector<Index> loop = k.Topology.BoundaryLoops().at(0);
  const std::vector<double>& uv0 = k.Result.UV;
  const Index v = loop[loop.size() / 3];
  std::vector<double> uv;
  ASSERT_EQ(MoveBoundaryHandles(k.Topology, k.Mesh.Points.data(), *k.Result.Basis, uv0,
              { Handle(v, uv0[2 * v] + 0.3, uv0[2 * v + 1] - 0.1) }, uv), "");
  double error = 0.0;
  for (Index i = 0; i < k.Mesh.NumberOfVertices(); ++i)
  {
    error = std::max({ error, std::abs(uv[2 * i] - uv0[2 * i] - 0.3), std::abs(uv[2 * i + 1] - uv0[2 * i + 1] + 0.1) });
  }
  EXPECT_LT(error, 1e-10); // the harmonic map reproduces a translation of its boundary
  std::vector<double> same;
  ASSERT_EQ(MoveBoundaryHandles(k.Topology, k.Mesh.Points.data(), *k.Result.Basis, uv0, {}, same), "");
  for (std::size_t i = 0; i < same.size(); ++i)
  {
    ASSERT_NEAR(same[i], uv0[i], 1e-10);
  }
}

TEST(BoundaryHandles, TwoHandlesInterpolateByArcLengthAndMatchASolve)
{
  const Kept k("patch-01.off");
  const std::vector<Index> loop = k.Topology.BoundaryLoops().at(0);
  const std::vector<double>& uv0 = k.Result.UV;
  const std::size_t h = loop.size() / 2; // handles at loop[0] and loop[h]
  const Index a = loop[0], b = loop[h];
  const double da[2] = { 0.2, 0.0 }, db[2] = { 0.0, -0.25 };
  std::vector<double> uv;
  ASSERT_EQ(MoveBoundaryHandles(k.Topology, k.Mesh.Points.data(), *k.Result.Basis, uv0,
              { Handle(a, uv0[2 * a] + da[0], uv0[2 * a + 1] + da[1]),
                Handle(b, uv0[2 * b] + db[0], uv0[2 * b + 1] + db[1]) },
              uv),
    "");
  // Between the handles, the displacement goes from da to db with the arc length.
  double along = 0.0, span = 0.0, worst = 0.0;
  for (std::size_t j = 0; j < h; ++j)
  {
    span += Length(k.Mesh, loop[j], loop[j + 1]);
  }
  for (std::size_t j = 0; j <= h; ++j)
  {
    const double t = along / span;
    for (int d = 0; d < 2; ++d)
    {
      const double expected = uv0[2 * loop[j] + d] + (1 - t) * da[d] + t * db[d];
      worst = std::max(worst, std::abs(uv[2 * loop[j] + d] - expected));
    }
    along += j < h ? Length(k.Mesh, loop[j], loop[j + 1]) : 0.0;
  }
  EXPECT_LT(worst, 1e-12);
  // The map is the parameterization with that boundary given.
  ParameterizationOptions given;
  given.Boundary = ParameterizationBoundary::Given;
  given.GivenUV = uv.data();
  const ParameterizationResult solved = Parameterize(k.Topology, k.Mesh.Points.data(), given);
  ASSERT_EQ(solved.Error, "");
  double difference = 0.0;
  for (std::size_t i = 0; i < uv.size(); ++i)
  {
    difference = std::max(difference, std::abs(uv[i] - solved.UV[i]));
  }
  EXPECT_LT(difference, 1e-9);
}

TEST(BoundaryHandles, BadHandlesAreRefused)
{
  const Kept k("patch-01.off");
  Index inner = 0;
  while (!k.Topology.IsInterior(inner))
  {
    ++inner;
  }
  const Index edge = k.Topology.BoundaryLoops().at(0).at(0);
  std::vector<double> uv{ 7.0 };
  const auto move = [&](BoundaryHandle h) {
    return MoveBoundaryHandles(k.Topology, k.Mesh.Points.data(), *k.Result.Basis, k.Result.UV, { h }, uv);
  };
  EXPECT_NE(move(Handle(inner, 0.5, 0.5)).find("not a point of the fixed boundary"), std::string::npos);
  EXPECT_NE(move(Handle(-3, 0.5, 0.5)).find("not a point of the fixed boundary"), std::string::npos);
  EXPECT_NE(move(Handle(k.Mesh.NumberOfVertices(), 0.5, 0.5)).find("not a point"), std::string::npos);
  EXPECT_NE(move(Handle(edge, std::nan(""), 0.5)).find("not finite"), std::string::npos);
  EXPECT_EQ(uv, std::vector<double>{ 7.0 }); // untouched
}
