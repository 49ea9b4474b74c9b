// The shared mesh-topology builder: classification, edges, loops.
#include "TestMeshes.h"

#include "Mesh/MeshTopology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace beltrami;

TEST(MeshTopology, ClosedSphere)
{
  const test::Mesh m = test::OctahedronSphere(2);
  const MeshTopology topo = m.Topology();
  const TopologySummary& s = topo.Summary();
  EXPECT_EQ(s.NumberOfVertices, 66);
  EXPECT_EQ(s.NumberOfTriangles, 128);
  EXPECT_EQ(s.NumberOfEdges, 192);
  EXPECT_EQ(s.EulerCharacteristic, 2);
  EXPECT_TRUE(s.IsClosed() && s.IsManifold() && s.IsOriented());
  EXPECT_EQ(s.NumberOfBoundaryLoops, 0);
  EXPECT_EQ(topo.CountComponents(), 1);
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    EXPECT_TRUE(topo.IsInterior(v));
  }
  EXPECT_NE(topo.Describe().find("genus 0"), std::string::npos) << topo.Describe();
}

TEST(MeshTopology, EdgeTableIsConsistent)
{
  const test::Mesh m = test::Torus(1, 0.3, 12, 7, 0.2, 1);
  const MeshTopology topo = m.Topology(3);
  const auto& edges = topo.Edges();
  EXPECT_EQ(edges.NumberOfEdges(), topo.Summary().NumberOfEdges);
  EXPECT_EQ(topo.Summary().EulerCharacteristic, 0);
  std::set<std::pair<Index, Index>> seen;
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index a = edges.Vertices[2 * e], b = edges.Vertices[2 * e + 1];
    EXPECT_LT(a, b);
    EXPECT_TRUE(seen.emplace(a, b).second);
    EXPECT_EQ(edges.FaceCount[e], 2);
    for (int k = 0; k < 2; ++k)
    {
      // The opposite corner's triangle holds the edge, and its vertex is not on it.
      const Index c = edges.OppositeCorners[2 * e + k];
      ASSERT_GE(c, 0);
      const Index o = topo.CornerVertex(c);
      const Index j = topo.CornerVertex(MeshTopology::Next(c));
      const Index l = topo.CornerVertex(MeshTopology::Prev(c));
      EXPECT_TRUE(o != a && o != b);
      EXPECT_EQ(std::make_pair(std::min(j, l), std::max(j, l)), std::make_pair(a, b));
    }
  }
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    for (std::int64_t s = edges.NeighborOffsets[v]; s < edges.NeighborOffsets[v + 1]; ++s)
    {
      const std::int64_t e = edges.NeighborEdges[s];
      const Index n = edges.Neighbors[s];
      EXPECT_EQ(std::make_pair(std::min(v, n), std::max(v, n)),
        std::make_pair(edges.Vertices[2 * e], edges.Vertices[2 * e + 1]));
    }
  }
}

// A vertex's edges as VertexEdges gives them (read off the fan at regular
// vertices, from the sorted half-edges elsewhere) against a count over its
// triangles: on a cylinder (boundary vertices) and meshes with a
// non-manifold edge and an inconsistent orientation.
TEST(MeshTopology, VertexEdgesAgreeWithTheirTriangles)
{
  const test::Mesh cylinder = test::Cylinder(1, 1, 9, 4);
  const MeshTopology topologies[] = { cylinder.Topology(), MeshTopology(5, { 0, 1, 2, 1, 0, 3, 0, 1, 4, 2, 1, 3 }),
    MeshTopology(4, { 0, 1, 2, 1, 2, 3, 0, 2, 3 }) };
  for (const MeshTopology& topo : topologies)
  {
    std::vector<MeshTopology::VertexEdge> edges;
    for (Index v = 0; v < topo.NumberOfVertices(); ++v)
    {
      topo.VertexEdges(v, edges);
      std::set<Index> neighbors; // v's neighbours, counted from its triangles
      for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c)
      {
        neighbors.insert(topo.CornerVertex(MeshTopology::Next(*c)));
        neighbors.insert(topo.CornerVertex(MeshTopology::Prev(*c)));
      }
      ASSERT_EQ(edges.size(), neighbors.size()) << "vertex " << v;
      // The 1-ring graph holds the same neighbours (a regular vertex's
      // count is taken from its valence).
      const MeshTopology::VertexGraph& graph = topo.Graph();
      ASSERT_EQ(graph.NeighborOffsets[v + 1] - graph.NeighborOffsets[v], static_cast<std::int64_t>(neighbors.size()));
      EXPECT_TRUE(std::equal(neighbors.begin(), neighbors.end(), graph.Neighbors.begin() + graph.NeighborOffsets[v]));
      auto expected = neighbors.begin();
      for (const MeshTopology::VertexEdge& e : edges)
      {
        EXPECT_EQ(e.Neighbor, *expected++); // ascending
        int faces = 0;
        for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c)
        {
          faces += topo.CornerVertex(MeshTopology::Next(*c)) == e.Neighbor ||
            topo.CornerVertex(MeshTopology::Prev(*c)) == e.Neighbor;
        }
        EXPECT_EQ(e.Faces, faces);
        for (int k = 0; k < 2; ++k)
        {
          if (k >= faces)
          {
            EXPECT_EQ(e.Opposite[k], -1);
            continue;
          }
          // The opposite corner is the third vertex of a triangle of the
          // edge, Local its place among v's corners.
          const Index c = e.Opposite[k];
          EXPECT_TRUE(topo.CornerVertex(c) != v && topo.CornerVertex(c) != e.Neighbor);
          const Index corner = topo.CornersBegin(v)[e.Local[k]];
          EXPECT_EQ(corner / 3, c / 3);
          EXPECT_TRUE(topo.CornerVertex(MeshTopology::Next(c)) == v || topo.CornerVertex(MeshTopology::Prev(c)) == v);
        }
        if (faces >= 2)
        {
          EXPECT_LT(e.Opposite[0], e.Opposite[1]);
        }
      }
    }
  }
}

TEST(MeshTopology, BoundaryLoopsOfAnAnnulus)
{
  const test::Mesh m = test::Cylinder(1, 1, 16, 5);
  const MeshTopology topo = m.Topology();
  const auto loops = topo.BoundaryLoops();
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].size(), 16u);
  EXPECT_EQ(loops[1].size(), 16u);
  EXPECT_EQ(topo.Summary().NumberOfBoundaryVertices, 32);
  EXPECT_EQ(topo.Summary().EulerCharacteristic, 0);
  // Consecutive loop vertices are joined by boundary edges.
  for (const auto& loop : loops)
  {
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      EXPECT_EQ(topo.BoundaryNext(loop[k]), loop[(k + 1) % loop.size()]);
    }
  }
  EXPECT_NE(topo.Describe().find("2 boundary loops"), std::string::npos);
}

TEST(MeshTopology, DetectsDefects)
{
  // Three triangles on edge (0,1): non-manifold edge.
  {
    MeshTopology t(5, { 0, 1, 2, 1, 0, 3, 0, 1, 4 });
    EXPECT_EQ(t.Summary().NumberOfNonManifoldEdges, 1);
    EXPECT_TRUE(t.VertexFlags(0) & VertexNonManifold);
    EXPECT_FALSE(t.Summary().IsManifold());
  }
  // Bowtie: two triangles sharing only vertex 0.
  {
    MeshTopology t(5, { 0, 1, 2, 0, 3, 4 });
    EXPECT_TRUE(t.VertexFlags(0) & VertexNonManifold);
    EXPECT_FALSE(t.VertexFlags(1) & VertexNonManifold);
    EXPECT_EQ(t.Summary().NumberOfNonManifoldVertices, 1);
  }
  // Inconsistent orientation across edge (1,2).
  {
    MeshTopology t(4, { 0, 1, 2, 1, 2, 3 });
    EXPECT_EQ(t.Summary().NumberOfInconsistentEdges, 1);
    EXPECT_TRUE(t.VertexFlags(1) & VertexInconsistent);
    EXPECT_FALSE(t.Summary().IsOriented());
  }
  // Duplicate triangle, isolated vertex, repeated and out-of-range ids.
  {
    MeshTopology t(6, { 0, 1, 2, 0, 1, 2, 2, 2, 3, 0, 1, 9, 1, 3, 2 });
    EXPECT_EQ(t.Summary().NumberOfDuplicateTriangles, 1);
    EXPECT_TRUE(t.VertexFlags(0) & VertexDuplicateFace);
    EXPECT_EQ(t.NumberOfDroppedTriangles(), 2);
    EXPECT_EQ(t.NumberOfTriangles(), 3);
    EXPECT_EQ(t.VertexFlags(4), VertexIsolated);
    EXPECT_EQ(t.VertexFlags(5), VertexIsolated);
    EXPECT_EQ(t.Summary().NumberOfIsolatedVertices, 2);
    EXPECT_EQ(t.OriginalTriangleIds(), (IndexArray{ 0, 1, 4 }));
  }
  // Empty input.
  {
    MeshTopology t(0, {});
    EXPECT_EQ(t.NumberOfTriangles(), 0);
    EXPECT_EQ(t.Summary().EulerCharacteristic, 0);
    EXPECT_TRUE(t.Edges().Vertices.empty());
  }
  EXPECT_THROW(MeshTopology(3, { 0, 1 }), std::invalid_argument);
}

TEST(MeshTopology, ThreadCountDoesNotChangeTheTopology)
{
  const test::Mesh m = test::Torus(1, 0.3, 150, 60, 0.3, 4);
  const MeshTopology a = m.Topology(1), b = m.Topology(4);
  EXPECT_EQ(a.VertexFlagArray(), b.VertexFlagArray());
  EXPECT_EQ(a.Edges().Vertices, b.Edges().Vertices);
  EXPECT_EQ(a.Edges().OppositeCorners, b.Edges().OppositeCorners);
  EXPECT_EQ(a.Edges().NeighborEdges, b.Edges().NeighborEdges);
}

TEST(MeshTopology, RingPairsAndThreadsOnALargeMesh)
{
  // Above 2^18 corners the corner lists are built by several threads, each
  // owning a range of vertices; the result must be the same as on one.
  const test::Mesh m = test::Torus(1, 0.3, 400, 120, 0.2, 5);
  const MeshTopology a = m.Topology(1), b = m.Topology(3);
  ASSERT_GT(a.TriangleList().size(), std::size_t(1) << 18);
  EXPECT_EQ(a.VertexFlagArray(), b.VertexFlagArray());
  EXPECT_EQ(a.Summary().NumberOfEdges, b.Summary().NumberOfEdges);
  EXPECT_EQ(a.Summary().EulerCharacteristic, 0);
  for (Index v = 0; v < a.NumberOfVertices(); ++v)
  {
    ASSERT_EQ(a.Valence(v), b.Valence(v));
    const Index* pa = a.RingPairsBegin(v);
    const Index* pb = b.RingPairsBegin(v);
    const Index* cb = b.CornersBegin(v);
    for (const Index* c = a.CornersBegin(v); c != a.CornersEnd(v); ++c, ++cb, pa += 2, pb += 2)
    {
      ASSERT_EQ(*c, *cb);
      ASSERT_EQ(a.CornerVertex(*c), v);
      ASSERT_EQ(pa[0], a.CornerVertex(MeshTopology::Next(*c)));
      ASSERT_EQ(pa[1], a.CornerVertex(MeshTopology::Prev(*c)));
      ASSERT_EQ(pa[0], pb[0]);
      ASSERT_EQ(pa[1], pb[1]);
    }
  }
}

TEST(MeshTopology, FansOfEveryValence)
{
  // A closed fan (a double pyramid over an n-gon) for n = 3 .. 40: the apex
  // is regular (the sort-free check for valence <= 32, the general one
  // above); one flipped triangle makes it inconsistent, one removed
  // triangle a boundary vertex.
  for (Index n = 3; n <= 40; ++n)
  {
    std::vector<Index> closed;
    for (Index k = 0; k < n; ++k)
    {
      closed.insert(closed.end(), { n, k, (k + 1) % n });     // upper apex n
      closed.insert(closed.end(), { n + 1, (k + 1) % n, k }); // lower apex n + 1
    }
    const MeshTopology topo(n + 2, IndexArray(closed.begin(), closed.end()));
    EXPECT_TRUE(topo.IsInterior(n)) << n;
    EXPECT_EQ(topo.Summary().EulerCharacteristic, 2) << n;
    EXPECT_EQ(topo.Summary().NumberOfEdges, 3 * n) << n;

    std::vector<Index> flipped = closed;
    std::swap(flipped[1], flipped[2]);
    const MeshTopology f(n + 2, IndexArray(flipped.begin(), flipped.end()));
    EXPECT_TRUE(f.VertexFlags(n) & VertexInconsistent) << n;

    std::vector<Index> open(closed.begin() + 6, closed.end());
    const MeshTopology o(n + 2, IndexArray(open.begin(), open.end()));
    EXPECT_TRUE(o.VertexFlags(n) & VertexBoundary) << n;
  }
}
