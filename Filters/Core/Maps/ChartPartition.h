// Beltrami core: the partition of a triangle surface into disk-like charts
// (thesis section 4.2.1, after Eck et al.: approximate Voronoi regions).
//
// Seeds are spread over every connected component by area, then moved once
// to the centres of their regions (a Lloyd step along the dual graph:
// triangles joined across their manifold edges, at the distance of their
// centroids); every triangle joins the nearest seed (a multi-source
// Dijkstra, so each region is connected).  A region that is
// not a topological disk (Euler characteristic 1 and one boundary loop: a
// band around a handle, a closed component, a region that touches itself at
// a vertex) is split in two along the same distances from its two most
// distant triangles, until every chart is a disk.
#pragma once

#include "Mesh/MeshTopology.h"
#include "Support/LargeBuffer.h"

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace beltrami
{

/// The triangles of a surface joined across their edges used by exactly two
/// triangles (the dual graph): 3 neighbours per triangle (-1: none, across a
/// boundary, non-manifold or cut edge) and the distances of the centroids.
/// Cut edges (seams, feature edges) are never crossed: every region, split
/// and chart has them on its boundary.
struct DualGraph
{
  LargeVector<Index> Neighbors;   ///< 3 per triangle
  LargeVector<double> Distances;  ///< 3 per triangle
  LargeVector<double> Areas;      ///< 3D area per triangle
  std::vector<std::pair<Index, Index>> Cuts; ///< the triangle pairs across cut edges, both ways, sorted

  /// cut (optional): 1 per edge of topology.Edges() that charts must not cross.
  DualGraph(const MeshTopology& topology, const double* points, const std::vector<std::uint8_t>* cut = nullptr);
  Index NumberOfTriangles() const { return static_cast<Index>(Areas.size()); }
};

/// The triangles of one chart as a mesh of their own, with its topology
/// (built once: the disk check and the chart's map share it).
struct ChartMesh
{
  std::vector<Index> Triangles; ///< ids in the surface, ascending
  std::vector<Index> Vertices;  ///< chart vertex -> surface vertex, ascending
  IndexArray Corners;           ///< 3 per chart triangle, chart vertex ids
  std::shared_ptr<const MeshTopology> Topology; ///< of Corners
};

/// The chart mesh of `triangles` (ids of `topology`).
ChartMesh ExtractChart(const MeshTopology& topology, std::vector<Index> triangles);

/// True when the triangles of `chart` form a topological disk: manifold,
/// oriented, one boundary loop, Euler characteristic 1.
bool IsDisk(const ChartMesh& chart, std::string* why = nullptr);

/// True when a cut edge of `graph` lies inside `chart` (its two triangles
/// in the chart: a seam or feature that ends inside the chart).
bool HasCutInside(const DualGraph& graph, const ChartMesh& chart);

/// The edges (of topology.Edges()) between triangles of different labels
/// (one per triangle): the seams of a segmentation.
std::vector<std::uint8_t> EdgesBetweenLabels(const MeshTopology& topology, const std::vector<int>& label);

/// Seeds for `count` charts (at least one per connected component of the
/// dual graph, the rest shared by area), spread by area and moved once to
/// the centres of their regions; `label` (optional): each triangle's
/// nearest seed (GrowRegions' result).
std::vector<Index> ChooseSeeds(
  const DualGraph& graph, int count, std::vector<int>* label = nullptr, int numThreads = 0);

/// label[t] = the index (in `seeds`) of the nearest seed along the dual
/// graph (one multi-source Dijkstra); -1 where no seed reaches.  distance:
/// the distance to it (optional).
std::vector<int> GrowRegions(
  const DualGraph& graph, const std::vector<Index>& seeds, std::vector<double>* distance = nullptr);

/// Moves every triangle that touches its own region by at most one edge and
/// another region by two (an ear of a jagged region boundary: on a square
/// chart boundary its three corners would be collinear) to that region,
/// `passes` times at most.  (A region can lose its connectivity or its disk
/// shape when it is thin: the partition checks every chart after.)
void SmoothRegionBoundaries(const DualGraph& graph, std::vector<int>& label, int passes = 4);

/// Splits `triangles` (a connected set) in two: seeds at the triangle
/// farthest from its first triangle and the one farthest from that; the
/// halves are the regions grown from them.  Either half may be empty only
/// when `triangles` has one triangle.  Where they are an `annulus` (a tube)
/// at least four times longer than its girth, the second seed is instead
/// the triangle on the first one's rim that is farthest from it, across the
/// tube: the halves are the tube cut along its length, two disks or parts
/// split again (the ends' seeds cut it into shorter tubes, again and again:
/// a knotted tube of 12,000 triangles went into 401 disks, now 266).  Of the
/// corpus and the generated shapes, only the needle has such a tube (its 4
/// regions went into 100 disks, now 6; the remesher's atlas of it has 66
/// charts, was 160).
std::vector<std::vector<Index>> SplitRegion(
  const DualGraph& graph, const std::vector<Index>& triangles, bool annulus = false);

/// `region` (connected) as disks without a cut inside: kept when it is one, else split
/// (SplitRegion, as an annulus where it is one) until every part is; the disks are appended to `disks`.
/// False with `error` when a single triangle is no disk.
bool SplitIntoDisks(const MeshTopology& topology, const DualGraph& graph, std::vector<Index> region,
  std::vector<ChartMesh>& disks, std::string& error);

/// The area-balanced refinement of section 4.2.4: every pair of
/// neighbouring charts whose areas differ by more than `ratio` is merged and
/// split again at the median of its area along a level line of d_a - d_b
/// (the distances from the union's two most distant triangles), so both
/// halves carry the same area and the seam is smooth; kept only where both
/// halves are disks.  At most `rounds` rounds, each chart once per round
/// (disjoint pairs in parallel).
void BalanceChartAreas(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double ratio = 1.5, int rounds = 8, int numThreads = 0);

/// Splits every chart larger than `maximumArea` (SplitRegion, then into
/// disks, boundaries smoothed) until none is; a single triangle larger than
/// that stays (the count of such charts is returned).  False with `error`
/// as SplitIntoDisks.
bool SplitLargeCharts(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double maximumArea, std::string& error, int& oversized, int numThreads = 0);

/// The partition: every triangle of `topology` in exactly one disk-like
/// chart.  `count`: the number of initial regions
/// (splits add more); `balance`: BalanceChartAreas after; the regions are
/// split into disks on `numThreads` threads (0: all).  False with
/// `error` when the surface is not manifold and oriented (no chart of it
/// could be a disk).
bool PartitionIntoCharts(const MeshTopology& topology, const DualGraph& graph, int count,
  std::vector<ChartMesh>& charts, std::string& error, bool balance = true, int numThreads = 0);

} // namespace beltrami
