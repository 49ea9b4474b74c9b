// The repairs of a surface: coincident points merged, orientation made consistent.
#include "TestMeshes.h"

#include "Mesh/MeshMeasures.h"
#include "Mesh/SurfaceRepair.h"

#include <gtest/gtest.h>

#include <random>

using namespace beltrami;

namespace
{

MeshTopology TopologyOf(Index points, const IndexArray& triangles)
{
  return MeshTopology(points, triangles);
}

/// The sphere's triangles, each with its own three points (an STL soup).
test::Mesh Soup(const test::Mesh& m)
{
  test::Mesh soup;
  for (Index v : m.Triangles)
  {
    soup.Triangles.push_back(static_cast<Index>(soup.Points.size() / 3));
    soup.Points.insert(soup.Points.end(), m.Points.begin() + 3 * v, m.Points.begin() + 3 * v + 3);
  }
  return soup;
}

} // namespace

TEST(SurfaceRepair, SoupIsWeldedIntoTheClosedSphere)
{
  const test::Mesh sphere = test::OctahedronSphere(2);
  const test::Mesh soup = Soup(sphere);
  const MeshTopology apart = soup.Topology();
  ASSERT_EQ(apart.CountComponents(), apart.NumberOfTriangles());
  Index merged = 0;
  const std::vector<Index> merge = CoincidentBoundaryPoints(apart, soup.Points.data(), merged);
  ASSERT_EQ(merge.size(), soup.Points.size() / 3);
  EXPECT_EQ(merged, soup.NumberOfVertices() - sphere.NumberOfVertices());
  const MeshTopology welded = TopologyOf(soup.NumberOfVertices(), MergePoints(apart.TriangleList(), merge));
  EXPECT_TRUE(welded.Summary().IsClosed() && welded.Summary().IsManifold() && welded.Summary().IsOriented());
  EXPECT_EQ(welded.Summary().EulerCharacteristic, 2);
  EXPECT_EQ(welded.CountComponents(), 1);
  for (std::size_t p = 0; p < merge.size(); ++p) // every point merged into the lowest of its place
  {
    EXPECT_LE(merge[p], static_cast<Index>(p));
    EXPECT_EQ(merge[merge[p]], merge[p]);
  }
}

TEST(SurfaceRepair, NearlyCoincidentPointsAreWeldedAndDistinctOnesKept)
{
  // The soup's copies of a point moved by round-off (1e-14, a seam computed
  // with sines and cosines) are welded; moved by 1e-7 of the diagonal (a
  // real gap) they are not.
  const test::Mesh sphere = test::OctahedronSphere(2);
  for (const double shift : { 1e-14, 1e-7 })
  {
    test::Mesh soup = Soup(sphere);
    for (std::size_t k = 0; k < soup.Points.size(); k += 3)
    {
      soup.Points[k] += shift * static_cast<double>(k / 3); // every copy apart from the others
    }
    Index merged = 0;
    const std::vector<Index> merge = CoincidentBoundaryPoints(soup.Topology(), soup.Points.data(), merged);
    EXPECT_EQ(merged, shift < 1e-10 ? soup.NumberOfVertices() - sphere.NumberOfVertices() : 0) << shift;
  }
}

TEST(SurfaceRepair, InteriorPointsAreNeverMerged)
{
  // Two closed spheres that touch where a point of each coincides: nothing to weld.
  test::Mesh twice = test::OctahedronSphere(1);
  const Index n = twice.NumberOfVertices();
  const std::size_t t = twice.Triangles.size();
  for (Index v = 0; v < n; ++v)
  {
    twice.Points.push_back(twice.Points[3 * v] + 2.0);
    twice.Points.push_back(twice.Points[3 * v + 1]);
    twice.Points.push_back(twice.Points[3 * v + 2]);
  }
  for (std::size_t k = 0; k < t; ++k)
  {
    twice.Triangles.push_back(twice.Triangles[k] + n);
  }
  Index merged = 0;
  EXPECT_TRUE(CoincidentBoundaryPoints(twice.Topology(), twice.Points.data(), merged).empty());
  EXPECT_EQ(merged, 0);
}

TEST(SurfaceRepair, EdgesOfZeroLengthAreCollapsedWhereTheSurfaceStaysManifold)
{
  // Two edges collapsed in place (one end moved onto the other): each pair
  // of points becomes one, the two triangles of no area beside the edge go,
  // and the sphere stays a closed manifold of Euler characteristic 2.  Two
  // spheres that touch at a coincident point share no edge: not merged.
  test::Mesh m = test::OctahedronSphere(3);
  const Index a = m.Triangles[0], b = m.Triangles[1];
  const Index c = m.Triangles[3 * 40], d = m.Triangles[3 * 40 + 2];
  ASSERT_TRUE(a != c && a != d && b != c && b != d);
  m.SetPoint(std::max(a, b), m.Point(std::min(a, b)));
  m.SetPoint(std::max(c, d), m.Point(std::min(c, d)));
  Index merged = 0;
  const std::vector<Index> merge = CollapsedEdges(m.Topology(), m.Points.data(), merged);
  ASSERT_EQ(merged, 2);
  EXPECT_EQ(merge[std::max(a, b)], std::min(a, b));
  EXPECT_EQ(merge[std::max(c, d)], std::min(c, d));
  const MeshTopology joined(m.NumberOfVertices(), MergePoints(m.Topology().TriangleList(), merge));
  EXPECT_EQ(joined.NumberOfTriangles(), m.Topology().NumberOfTriangles() - 4);
  EXPECT_TRUE(joined.Summary().IsManifold());
  EXPECT_EQ(joined.Summary().EulerCharacteristic, 2);
  EXPECT_EQ(joined.Summary().NumberOfBoundaryEdges, 0);

  test::Mesh twice = test::OctahedronSphere(1);
  const Index n = twice.NumberOfVertices();
  twice = test::Merged(twice, twice, { 2.0, 0.0, 0.0 });
  ASSERT_EQ(twice.NumberOfVertices(), 2 * n);
  EXPECT_TRUE(CollapsedEdges(twice.Topology(), twice.Points.data(), merged).empty());
}

TEST(SurfaceRepair, HalfFlippedSphereFacesOutwards)
{
  for (const bool inside : { false, true })
  {
    test::Mesh m = test::OctahedronSphere(3);
    std::mt19937 random(7);
    for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
    {
      if (inside || random() % 2) // every triangle turned: consistent, facing in (left as it is)
      {
        std::swap(m.Triangles[t + 1], m.Triangles[t + 2]);
      }
    }
    const MeshTopology before = m.Topology();
    IndexArray triangles;
    const OrientationRepair repair = OrientConsistently(before, m.Points.data(), triangles);
    const MeshTopology after = TopologyOf(m.NumberOfVertices(), triangles);
    EXPECT_TRUE(after.Summary().IsOriented());
    EXPECT_EQ(repair.NonOrientableComponents, 0);
    const double volume = EnclosedVolume(after, m.Points.data());
    if (inside)
    {
      EXPECT_FALSE(repair.Changed()); // a consistent component is left alone
      EXPECT_LT(volume, 0.0);
    }
    else
    {
      EXPECT_GT(repair.FlippedTriangles, 0);
      EXPECT_NEAR(volume, EnclosedVolume(test::OctahedronSphere(3).Topology(), m.Points.data()), 1e-12);
      EXPECT_GT(volume, 4.0);
    }
  }
}

TEST(SurfaceRepair, OpenSurfaceKeepsItsMajorityAndMoebiusIsLeft)
{
  test::Mesh disk = test::FlatIrregular(8, 3);
  std::swap(disk.Triangles[1], disk.Triangles[2]); // one triangle against the rest
  IndexArray triangles;
  const MeshTopology before = disk.Topology();
  ASSERT_FALSE(before.Summary().IsOriented());
  const OrientationRepair repair = OrientConsistently(before, disk.Points.data(), triangles);
  EXPECT_EQ(repair.FlippedTriangles, 1);
  EXPECT_EQ(triangles[0], disk.Triangles[0]);
  EXPECT_EQ(triangles[1], disk.Triangles[2]); // the odd one turned back
  EXPECT_TRUE(TopologyOf(disk.NumberOfVertices(), triangles).Summary().IsOriented());

  // A Moebius strip: a band of 2n triangles closed with a half twist.
  test::Mesh band;
  const int n = 12;
  for (int k = 0; k < n; ++k)
  {
    const double a = 2.0 * M_PI * k / n;
    for (const double s : { -0.3, 0.3 })
    {
      const double w = s * std::cos(a / 2.0);
      band.Points.insert(band.Points.end(), { (1.0 + w) * std::cos(a), (1.0 + w) * std::sin(a), s * std::sin(a / 2.0) });
    }
  }
  for (int k = 0; k < n; ++k)
  {
    const Index a = 2 * k, b = 2 * k + 1;
    const Index c = k + 1 < n ? 2 * k + 2 : 1, d = k + 1 < n ? 2 * k + 3 : 0; // the twist swaps the sides
    band.Triangles.insert(band.Triangles.end(), { a, c, b, b, c, d });
  }
  const MeshTopology strip = band.Topology();
  const OrientationRepair none = OrientConsistently(strip, band.Points.data(), triangles);
  EXPECT_EQ(none.NonOrientableComponents, 1);
  EXPECT_FALSE(none.Changed());
}

TEST(SurfaceRepair, RepeatedTrianglesAreFoundInAnyOrderAndTheFirstKept)
{
  // Three faces of a tetrahedron, {0, 1, 2} repeated three times (twice
  // turned) and {1, 2, 3} once turned: the repeats are found, never the
  // first of each; the tetrahedron's four faces have none.
  const IndexArray triangles = { 0, 2, 1, 0, 1, 3, 0, 1, 2, 1, 2, 3, 2, 1, 0, 1, 3, 2, 0, 2, 1 };
  EXPECT_EQ(RepeatedTriangles(triangles), (std::vector<Index>{ 2, 4, 5, 6 }));
  EXPECT_TRUE(RepeatedTriangles({ 0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3 }).empty());
  EXPECT_TRUE(RepeatedTriangles({}).empty());
}

TEST(SurfaceRepair, PinchedVerticesAreSplitOneVertexPerFan)
{
  // Two fans of two triangles each meet at vertex 0 only (a bowtie of
  // quads), and a third fan touches it too: vertex 0 becomes three, one per
  // fan, and the surface is manifold; the other vertices keep their ids.
  const IndexArray bowtie = { 0, 1, 2, 0, 2, 3, 0, 4, 5, 0, 5, 6, 7, 8, 0 };
  const MeshTopology pinched = TopologyOf(9, bowtie);
  ASSERT_EQ(pinched.Summary().NumberOfNonManifoldVertices, 1);
  IndexArray split;
  Index cut = -1;
  const std::vector<Index> copied = SplitPinchedVertices(pinched, split, cut);
  EXPECT_EQ(copied, (std::vector<Index>{ 0, 0 }));
  EXPECT_EQ(cut, 0);
  const IndexArray expected = { 0, 1, 2, 0, 2, 3, 9, 4, 5, 9, 5, 6, 7, 8, 10 };
  EXPECT_EQ(std::vector<Index>(split.begin(), split.end()), std::vector<Index>(expected.begin(), expected.end()));
  const MeshTopology repaired = TopologyOf(11, split);
  EXPECT_TRUE(repaired.Summary().IsManifold());
  EXPECT_EQ(repaired.CountComponents(), 3);
  EXPECT_EQ(repaired.Summary().NumberOfBoundaryLoops, 3);
  // A manifold surface is left as it is.
  EXPECT_TRUE(SplitPinchedVertices(TopologyOf(4, { 0, 1, 2, 0, 2, 3 }), split, cut).empty());
}

TEST(SurfaceRepair, EdgesOfThreeTrianglesAreCut)
{
  // A fin: edge 0-1 in three triangles, and a fourth triangle joined to the
  // first across edge 1-2.  The edge is cut and its ends split: three
  // manifold pieces, the first two triangles still joined.
  const IndexArray fin = { 0, 1, 2, 1, 0, 3, 0, 1, 4, 2, 1, 5 };
  const MeshTopology folded = TopologyOf(6, fin);
  ASSERT_EQ(folded.Summary().NumberOfNonManifoldEdges, 1);
  IndexArray split;
  Index cut = 0;
  const std::vector<Index> copied = SplitPinchedVertices(folded, split, cut);
  EXPECT_EQ(cut, 1);
  EXPECT_EQ(copied, (std::vector<Index>{ 0, 0, 1, 1 }));
  const MeshTopology repaired = TopologyOf(10, split);
  EXPECT_TRUE(repaired.Summary().IsManifold());
  EXPECT_EQ(repaired.CountComponents(), 3);
  EXPECT_EQ(repaired.Summary().NumberOfBoundaryLoops, 3);
}
