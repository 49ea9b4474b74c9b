// The editable mesh of the remesher (Mesh/HalfEdgeMesh): conversion from and
// to MeshTopology, edge flips (orientation, refusals, invariants over many
// random flips), vertex moves, chart extraction with a vertex map.
#include "TestMeshes.h"

#include "Mesh/HalfEdgeMesh.h"

#include <gtest/gtest.h>

#include <random>

namespace beltrami
{
namespace
{

/// A small mesh from its points and triangles (3 ids each).
test::Mesh Small(std::initializer_list<Eigen::Vector3d> points, std::initializer_list<Index> triangles)
{
  test::Mesh m;
  for (const Eigen::Vector3d& p : points)
  {
    m.AddPoint(p);
  }
  m.Triangles.assign(triangles);
  return m;
}

HalfEdgeMesh Build(const test::Mesh& m)
{
  HalfEdgeMesh mesh;
  std::string error;
  EXPECT_TRUE(HalfEdgeMesh::FromTopology(m.Topology(), m.Points.data(), mesh, error)) << error;
  return mesh;
}

/// The faces as sorted vertex triples, ignoring order and rotation.
std::vector<std::array<Index, 3>> FaceSet(const HalfEdgeMesh& mesh)
{
  std::vector<std::array<Index, 3>> faces;
  for (Index f = 0; f < mesh.NumberOfFaces(); ++f)
  {
    std::array<Index, 3> t{ mesh.Triangles()[3 * f], mesh.Triangles()[3 * f + 1], mesh.Triangles()[3 * f + 2] };
    std::sort(t.begin(), t.end());
    faces.push_back(t);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

TEST(HalfEdgeMesh, RoundTripKeepsTheTrianglesAndTheRings)
{
  const test::Mesh sphere = test::OctahedronSphere(3);
  const MeshTopology topo = sphere.Topology();
  const HalfEdgeMesh mesh = Build(sphere);
  EXPECT_EQ(mesh.CheckConsistency(), "");
  ASSERT_EQ(mesh.NumberOfFaces(), topo.NumberOfTriangles());
  for (Index h = 0; h < mesh.NumberOfHalfEdges(); ++h)
  {
    EXPECT_EQ(mesh.Triangles()[h], topo.TriangleList()[h]);
    EXPECT_FALSE(mesh.IsBoundary(h)); // closed
  }
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    EXPECT_EQ(mesh.Valence(v), topo.Valence(v));
  }
  const MeshTopology back = mesh.ToTopology();
  EXPECT_EQ(back.Summary().EulerCharacteristic, 2);
  EXPECT_TRUE(back.Summary().IsManifold() && back.Summary().IsOriented() && back.Summary().IsClosed());
}

TEST(HalfEdgeMesh, BoundaryVerticesAreAnchoredOnTheBoundary)
{
  const test::Mesh patch = test::FlatIrregular(8, 3);
  const MeshTopology topo = patch.Topology();
  const HalfEdgeMesh mesh = Build(patch);
  EXPECT_EQ(mesh.CheckConsistency(), "");
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    const bool boundary = (topo.VertexFlags(v) & VertexBoundary) != 0;
    EXPECT_EQ(mesh.IsBoundaryVertex(v), boundary) << v;
    EXPECT_EQ(mesh.Valence(v), topo.Valence(v) + (boundary ? 1 : 0)) << v; // corners vs neighbours
    if (boundary)
    {
      // The boundary half-edge leaving v goes where MeshTopology's boundary walk goes.
      EXPECT_EQ(mesh.Head(mesh.OutgoingHalfEdge(v)), topo.BoundaryNext(v));
    }
  }
}

TEST(HalfEdgeMesh, FlipTurnsTheDiagonalOfAQuadAndRefusesWhatItCannot)
{
  HalfEdgeMesh mesh = Build(Small({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } }, { 0, 1, 2, 0, 2, 3 }));
  const Index diagonal = mesh.FindHalfEdge(0, 2);
  ASSERT_GE(diagonal, 0);
  EXPECT_FALSE(mesh.CanFlip(mesh.FindHalfEdge(0, 1))); // boundary
  ASSERT_TRUE(mesh.FlipEdge(diagonal));
  EXPECT_EQ(mesh.CheckConsistency(), "");
  EXPECT_LT(mesh.FindHalfEdge(0, 2), 0);
  EXPECT_LT(mesh.FindHalfEdge(2, 0), 0);
  const Index h13 = mesh.FindHalfEdge(1, 3), h31 = mesh.FindHalfEdge(3, 1);
  ASSERT_GE(h13, 0);
  ASSERT_GE(h31, 0);
  EXPECT_EQ(mesh.Twin(h13), h31);
  for (Index f = 0; f < 2; ++f) // both faces still face +z
  {
    const Vec3 a = mesh.Position(mesh.Triangles()[3 * f]), b = mesh.Position(mesh.Triangles()[3 * f + 1]),
               c = mesh.Position(mesh.Triangles()[3 * f + 2]);
    EXPECT_GT((b - a).cross(c - a).z(), 0.0);
  }
  // A tetrahedron: every flip would create an edge that exists.
  HalfEdgeMesh closed =
    Build(Small({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } }, { 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3 }));
  for (Index h = 0; h < closed.NumberOfHalfEdges(); ++h)
  {
    EXPECT_FALSE(closed.FlipEdge(h));
  }
  EXPECT_EQ(closed.CheckConsistency(), "");
  // A disk whose quad (0, 1, 2), (1, 0, 3) has its other diagonal 2-3 on
  // the boundary (its one half-edge runs 3 -> 2): the flip would make it
  // an edge of three faces.  (Met while stitching a pleat of folded caps.)
  HalfEdgeMesh strip = Build(Small({ { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, 1, 0 }, { 0.5, -1, 0 }, { 1.5, 0, 1 } },
    { 0, 1, 2, 1, 0, 3, 2, 1, 4, 1, 3, 4, 4, 3, 2 }));
  ASSERT_GE(strip.FindHalfEdge(3, 2), 0);
  ASSERT_LT(strip.FindHalfEdge(2, 3), 0);
  EXPECT_FALSE(strip.CanFlip(strip.FindHalfEdge(0, 1)));
  EXPECT_FALSE(strip.FlipEdge(strip.FindHalfEdge(0, 1)));
  EXPECT_EQ(strip.CheckConsistency(), "");
}

TEST(HalfEdgeMesh, ManyRandomFlipsKeepEveryInvariant)
{
  const test::Mesh sphere = test::OctahedronSphere(3);
  HalfEdgeMesh mesh = Build(sphere);
  std::mt19937 rng(11);
  std::uniform_int_distribution<Index> pick(0, mesh.NumberOfHalfEdges() - 1);
  int flipped = 0;
  for (int k = 0; k < 2000; ++k)
  {
    flipped += mesh.FlipEdge(pick(rng));
  }
  EXPECT_GT(flipped, 1000);
  EXPECT_EQ(mesh.CheckConsistency(), "");
  const MeshTopology topo = mesh.ToTopology();
  const TopologySummary& s = topo.Summary();
  EXPECT_EQ(s.EulerCharacteristic, 2);
  EXPECT_TRUE(s.IsManifold() && s.IsOriented() && s.IsClosed());
  EXPECT_EQ(topo.NumberOfTriangles(), mesh.NumberOfFaces());
  std::int64_t valenceSum = 0;
  for (Index v = 0; v < mesh.NumberOfVertices(); ++v)
  {
    EXPECT_EQ(mesh.Valence(v), topo.Valence(v));
    valenceSum += mesh.Valence(v);
  }
  EXPECT_EQ(valenceSum, 2 * s.NumberOfEdges);
  // Each flip is undone by flipping the new edge.
  for (int k = 0; k < 200; ++k)
  {
    const Index h = pick(rng);
    const Index c = mesh.Tail(HalfEdgeMesh::Prev(h)), d = mesh.Tail(HalfEdgeMesh::Prev(mesh.Twin(h)));
    const auto faces = FaceSet(mesh);
    if (mesh.FlipEdge(h))
    {
      const Index e = mesh.FindHalfEdge(c, d);
      ASSERT_GE(e, 0);
      ASSERT_TRUE(mesh.FlipEdge(e));
      EXPECT_EQ(FaceSet(mesh), faces);
    }
  }
  EXPECT_EQ(mesh.CheckConsistency(), "");
}

TEST(HalfEdgeMesh, MovesKeepTheConnectivityAndChartsComeOutWithAVertexMap)
{
  const test::Mesh sphere = test::OctahedronSphere(3);
  HalfEdgeMesh mesh = Build(sphere);
  const std::vector<Index> before = mesh.Triangles();
  mesh.SetPosition(0, 2.0 * mesh.Position(0));
  EXPECT_EQ(mesh.Triangles(), before);
  EXPECT_DOUBLE_EQ(mesh.Position(0).norm(), 2.0);
  // The upper hemisphere (faces whose centroid has z > 0) is a disk.
  std::vector<std::uint8_t> keep(mesh.NumberOfFaces());
  Index kept = 0;
  for (Index f = 0; f < mesh.NumberOfFaces(); ++f)
  {
    const Vec3 c = mesh.Position(before[3 * f]) + mesh.Position(before[3 * f + 1]) + mesh.Position(before[3 * f + 2]);
    keep[f] = c.z() > 0.0;
    kept += keep[f];
  }
  HalfEdgeMesh chart;
  std::vector<Index> map;
  std::string error;
  ASSERT_TRUE(mesh.ExtractFaces(keep, chart, map, error)) << error;
  EXPECT_EQ(chart.CheckConsistency(), "");
  EXPECT_EQ(chart.NumberOfFaces(), kept);
  EXPECT_TRUE(std::is_sorted(map.begin(), map.end()));
  for (Index v = 0; v < chart.NumberOfVertices(); ++v)
  {
    EXPECT_EQ(chart.Position(v), mesh.Position(map[v]));
  }
  const MeshTopology disk = chart.ToTopology();
  EXPECT_EQ(disk.Summary().EulerCharacteristic, 1);
  EXPECT_EQ(disk.Summary().NumberOfBoundaryLoops, 1);
  // Two faces that touch at one vertex only are no manifold chart.
  std::vector<std::uint8_t> bowtie(mesh.NumberOfFaces(), 0);
  const Index v = before[0];
  // Two faces of v's fan that are not neighbours share v alone.
  std::vector<Index> fan;
  mesh.ForEachOutgoing(v, [&](Index h) { fan.push_back(HalfEdgeMesh::Face(h)); });
  ASSERT_GE(fan.size(), 4u);
  bowtie[fan[0]] = bowtie[fan[2]] = 1;
  EXPECT_FALSE(mesh.ExtractFaces(bowtie, chart, map, error));
  EXPECT_NE(error.find("manifold"), std::string::npos) << error;
}

TEST(HalfEdgeMesh, NonManifoldInputIsRefused)
{
  const test::Mesh fin = // three triangles on one edge
    Small({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 } }, { 0, 1, 2, 1, 0, 3, 0, 1, 4 });
  HalfEdgeMesh mesh;
  std::string error;
  EXPECT_FALSE(HalfEdgeMesh::FromTopology(fin.Topology(), fin.Points.data(), mesh, error));
  EXPECT_NE(error.find("manifold"), std::string::npos) << error;
}

} // namespace
} // namespace beltrami
