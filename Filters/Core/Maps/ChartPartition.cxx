#include "Maps/ChartPartition.h"

#include "Mesh/Geometry.h"
#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>
#include <numeric>
#include <queue>
#include <tuple>

namespace beltrami
{

DualGraph::DualGraph(const MeshTopology& topology, const double* points, const std::vector<std::uint8_t>* cut)
{
  const Index nt = topology.NumberOfTriangles();
  const IndexArray& tri = topology.TriangleList();
  Neighbors.assign(3 * static_cast<std::size_t>(nt), -1);
  Distances.assign(3 * static_cast<std::size_t>(nt), 0.0);
  Areas.resize(nt);
  std::vector<Vec3> centroid(nt);
  for (Index t = 0; t < nt; ++t)
  {
    const Vec3 a = Point(points, tri[3 * t]), b = Point(points, tri[3 * t + 1]), c = Point(points, tri[3 * t + 2]);
    centroid[t] = (a + b + c) / 3.0;
    Areas[t] = 0.5 * (b - a).cross(c - a).norm();
  }
  const MeshTopology::EdgeTable& edges = topology.Edges();
  const auto link = [&](Index from, Index to) {
    for (int k = 0; k < 3; ++k)
    {
      if (Neighbors[3 * from + k] < 0)
      {
        Neighbors[3 * from + k] = to;
        Distances[3 * from + k] = (centroid[from] - centroid[to]).norm();
        return;
      }
    }
  };
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
    if (edges.FaceCount[e] != 2 || c0 < 0 || c1 < 0)
    {
      continue;
    }
    if (cut && (*cut)[e])
    {
      Cuts.emplace_back(c0 / 3, c1 / 3);
      Cuts.emplace_back(c1 / 3, c0 / 3);
      continue;
    }
    link(c0 / 3, c1 / 3);
    link(c1 / 3, c0 / 3);
  }
  std::sort(Cuts.begin(), Cuts.end());
}

std::vector<std::uint8_t> EdgesBetweenLabels(const MeshTopology& topology, const std::vector<int>& label)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  std::vector<std::uint8_t> seam(edges.NumberOfEdges(), 0);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
    seam[e] = c0 >= 0 && c1 >= 0 && label[c0 / 3] != label[c1 / 3];
  }
  return seam;
}

ChartMesh ExtractChart(const MeshTopology& topology, std::vector<Index> triangles)
{
  ChartMesh chart;
  std::sort(triangles.begin(), triangles.end());
  chart.Triangles = std::move(triangles);
  const IndexArray& tri = topology.TriangleList();
  for (Index t : chart.Triangles)
  {
    chart.Vertices.insert(chart.Vertices.end(), { tri[3 * t], tri[3 * t + 1], tri[3 * t + 2] });
  }
  std::sort(chart.Vertices.begin(), chart.Vertices.end());
  chart.Vertices.erase(std::unique(chart.Vertices.begin(), chart.Vertices.end()), chart.Vertices.end());
  chart.Corners.resize(3 * chart.Triangles.size());
  for (std::size_t k = 0; k < chart.Triangles.size(); ++k)
  {
    for (int c = 0; c < 3; ++c)
    {
      const Index v = tri[3 * chart.Triangles[k] + c];
      chart.Corners[3 * k + c] = static_cast<Index>(
        std::lower_bound(chart.Vertices.begin(), chart.Vertices.end(), v) - chart.Vertices.begin());
    }
  }
  chart.Topology = std::make_shared<const MeshTopology>(static_cast<Index>(chart.Vertices.size()), chart.Corners, 1);
  return chart;
}

bool IsDisk(const ChartMesh& chart, std::string* why)
{
  const TopologySummary& s = chart.Topology->Summary();
  const bool disk = s.IsManifold() && s.IsOriented() && s.NumberOfBoundaryLoops == 1 && s.EulerCharacteristic == 1;
  if (!disk && why)
  {
    *why = chart.Topology->Describe();
  }
  return disk;
}

bool HasCutInside(const DualGraph& graph, const ChartMesh& chart)
{
  for (Index t : chart.Triangles) // ascending
  {
    auto cut = std::lower_bound(graph.Cuts.begin(), graph.Cuts.end(), std::make_pair(t, Index(-1)));
    for (; cut != graph.Cuts.end() && cut->first == t; ++cut)
    {
      if (std::binary_search(chart.Triangles.begin(), chart.Triangles.end(), cut->second))
      {
        return true;
      }
    }
  }
  return false;
}

namespace
{

/// The one Dijkstra of the partition: from `sources` (local ids; source k
/// labelled k) over a set of triangles with local ids - region[k] the
/// triangle of local id k, localOf[t] the local id of t (-1 outside); both
/// empty: every triangle, local = global - each triangle's distance along the
/// dual graph to the nearest source and that source's label.
void NearestWithin(const DualGraph& graph, const std::vector<Index>& region, const std::vector<Index>& localOf,
  const std::vector<Index>& sources, std::vector<double>& distance, std::vector<int>* label)
{
  const bool whole = region.empty();
  const std::size_t size = whole ? static_cast<std::size_t>(graph.NumberOfTriangles()) : region.size();
  distance.assign(size, std::numeric_limits<double>::infinity());
  if (label)
  {
    label->assign(size, -1);
  }
  // The queue holds 64-bit keys: the distance rounded to float (its bits
  // order like the values) above the local id.  The distances themselves
  // stay double: an entry popped a rounding early is corrected later, so
  // the result is the exact shortest distance.
  const auto key = [](double d, Index local) {
    const float f = static_cast<float>(d);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return (static_cast<std::uint64_t>(bits) << 32) | static_cast<std::uint32_t>(local);
  };
  std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<std::uint64_t>> queue;
  for (std::size_t k = 0; k < sources.size(); ++k)
  {
    distance[sources[k]] = 0.0;
    if (label)
    {
      (*label)[sources[k]] = static_cast<int>(k);
    }
    queue.push(key(0.0, sources[k]));
  }
  while (!queue.empty())
  {
    const std::uint64_t top = queue.top();
    queue.pop();
    const Index local = static_cast<Index>(top & 0xffffffffu);
    if (top > key(distance[local], local))
    {
      continue; // stale
    }
    const double d = distance[local];
    const Index t = whole ? local : region[local];
    for (int k = 0; k < 3; ++k)
    {
      const Index n = graph.Neighbors[3 * t + k];
      const Index m = n < 0 ? -1 : (whole ? n : localOf[n]);
      const double nd = d + graph.Distances[3 * t + k];
      if (m >= 0 && nd < distance[m])
      {
        distance[m] = nd;
        if (label)
        {
          (*label)[m] = (*label)[local];
        }
        queue.push(key(nd, m));
      }
    }
  }
}

/// The connected components of the dual graph, as triangle lists.
std::vector<std::vector<Index>> Components(const DualGraph& graph)
{
  const Index nt = graph.NumberOfTriangles();
  std::vector<int> component(nt, -1);
  std::vector<std::vector<Index>> components;
  for (Index start = 0; start < nt; ++start)
  {
    if (component[start] >= 0)
    {
      continue;
    }
    components.emplace_back();
    std::vector<Index>& members = components.back();
    component[start] = static_cast<int>(components.size() - 1);
    members.push_back(start);
    for (std::size_t k = 0; k < members.size(); ++k)
    {
      for (int j = 0; j < 3; ++j)
      {
        const Index n = graph.Neighbors[3 * members[k] + j];
        if (n >= 0 && component[n] < 0)
        {
          component[n] = component[start];
          members.push_back(n);
        }
      }
    }
  }
  return components;
}

} // namespace

namespace
{

/// `share` triangles of a component at evenly spread fractions of its area
/// (a golden-ratio sequence over the cumulative area, in breadth-first
/// order: a spread of the whole component, the same every run).
void SpreadSeeds(const DualGraph& graph, const std::vector<Index>& members, int share, std::vector<Index>& seeds)
{
  std::vector<double> cumulative(members.size());
  double area = 0.0;
  for (std::size_t k = 0; k < members.size(); ++k)
  {
    area += graph.Areas[members[k]];
    cumulative[k] = area;
  }
  std::vector<std::uint8_t> taken(members.size(), 0);
  for (int k = 0; k < share; ++k)
  {
    const double fraction = std::fmod(0.5 + k * 0.6180339887498949, 1.0);
    std::size_t at = static_cast<std::size_t>(
      std::lower_bound(cumulative.begin(), cumulative.end(), fraction * area) - cumulative.begin());
    at = std::min(at, members.size() - 1);
    while (taken[at] && at + 1 < members.size())
    {
      ++at;
    }
    if (!taken[at])
    {
      taken[at] = 1;
      seeds.push_back(members[at]);
    }
  }
}

/// One Lloyd-like relaxation: every region's new seed is its triangle
/// farthest from the region's boundary (its centre along the surface).
std::vector<Index> CentreSeeds(const DualGraph& graph, const std::vector<int>& label, std::size_t regions)
{
  std::vector<Index> boundary;
  for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index n = graph.Neighbors[3 * t + k];
      if (n < 0 || label[n] != label[t])
      {
        boundary.push_back(t);
        break;
      }
    }
  }
  std::vector<double> inward;
  if (!boundary.empty())
  {
    GrowRegions(graph, boundary, &inward);
  }
  std::vector<Index> centre(regions, -1);
  for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
  {
    Index& c = centre[label[t]];
    if (c < 0 || (!inward.empty() && inward[t] > inward[c]))
    {
      c = t;
    }
  }
  return centre;
}

} // namespace

std::vector<Index> ChooseSeeds(const DualGraph& graph, int count, std::vector<int>* label)
{
  const std::vector<std::vector<Index>> components = Components(graph);
  const double total = std::accumulate(graph.Areas.begin(), graph.Areas.end(), 0.0);
  std::vector<Index> seeds;
  for (const std::vector<Index>& members : components)
  {
    double area = 0.0;
    for (Index t : members)
    {
      area += graph.Areas[t];
    }
    SpreadSeeds(graph, members,
      std::max(1, static_cast<int>(std::lround(count * (total > 0.0 ? area / total : 0.0)))), seeds);
  }
  std::vector<int> regions = GrowRegions(graph, seeds);
  seeds = CentreSeeds(graph, regions, seeds.size());
  regions = GrowRegions(graph, seeds);
  if (label)
  {
    *label = std::move(regions);
  }
  return seeds;
}

std::vector<int> GrowRegions(const DualGraph& graph, const std::vector<Index>& seeds, std::vector<double>* distance)
{
  std::vector<double> own;
  std::vector<int> label;
  NearestWithin(graph, {}, {}, seeds, distance ? *distance : own, &label);
  return label;
}

namespace
{

/// The two triangles of a region (local ids) farthest apart along it: the
/// farthest from `start`, and the farthest from that one.
std::pair<Index, Index> FarthestPair(const DualGraph& graph, const std::vector<Index>& region,
  const std::vector<Index>& localOf, Index start, std::vector<double>& fromA)
{
  std::vector<double> fromStart;
  NearestWithin(graph, region, localOf, { start }, fromStart, nullptr);
  const Index a = static_cast<Index>(std::max_element(fromStart.begin(), fromStart.end()) - fromStart.begin());
  NearestWithin(graph, region, localOf, { a }, fromA, nullptr);
  const Index b = static_cast<Index>(std::max_element(fromA.begin(), fromA.end()) - fromA.begin());
  return { a, b };
}

} // namespace

std::vector<std::vector<Index>> SplitRegion(const DualGraph& graph, const std::vector<Index>& triangles)
{
  std::vector<Index> localOf(graph.NumberOfTriangles(), -1);
  for (std::size_t k = 0; k < triangles.size(); ++k)
  {
    localOf[triangles[k]] = static_cast<Index>(k);
  }
  std::vector<double> fromA, distance;
  const auto [a, b] = FarthestPair(graph, triangles, localOf, 0, fromA);
  std::vector<std::vector<Index>> halves(2);
  if (a == b)
  {
    halves[0] = triangles;
    return halves;
  }
  std::vector<int> label;
  NearestWithin(graph, triangles, localOf, { a, b }, distance, &label);
  for (std::size_t k = 0; k < triangles.size(); ++k)
  {
    halves[label[k] == 1 ? 1 : 0].push_back(triangles[k]);
  }
  return halves;
}

namespace
{

/// True when triangle t has a cut edge to a triangle of region `other`
/// (moving t there would put the cut inside the region).
bool CutBetween(const DualGraph& graph, Index t, const std::vector<int>& label, int other)
{
  auto cut = std::lower_bound(graph.Cuts.begin(), graph.Cuts.end(), std::make_pair(t, Index(-1)));
  for (; cut != graph.Cuts.end() && cut->first == t; ++cut)
  {
    if (label[cut->second] == other)
    {
      return true;
    }
  }
  return false;
}

} // namespace

void SmoothRegionBoundaries(const DualGraph& graph, std::vector<int>& label, int passes)
{
  for (int pass = 0; pass < passes; ++pass)
  {
    bool moved = false;
    for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
    {
      // An ear: two (or three) neighbours in one other region, at most one in its own.
      int other = -1, count = 0, own = 0;
      for (int k = 0; k < 3; ++k)
      {
        const Index n = graph.Neighbors[3 * t + k];
        if (n < 0)
        {
          continue;
        }
        if (label[n] == label[t])
        {
          ++own;
        }
        else if (other < 0 || label[n] == other)
        {
          other = label[n];
          ++count;
        }
      }
      if (own <= 1 && count >= 2 && !CutBetween(graph, t, label, other))
      {
        label[t] = other;
        moved = true;
      }
    }
    if (!moved)
    {
      break;
    }
  }
}

bool SplitIntoDisks(const MeshTopology& topology, const DualGraph& graph, std::vector<Index> region,
  std::vector<ChartMesh>& disks, std::string& error)
{
  std::vector<std::vector<Index>> pending;
  pending.push_back(std::move(region));
  while (!pending.empty())
  {
    std::vector<Index> part = std::move(pending.back());
    pending.pop_back();
    if (part.empty())
    {
      continue;
    }
    ChartMesh chart = ExtractChart(topology, part);
    if (IsDisk(chart) && !HasCutInside(graph, chart))
    {
      disks.push_back(std::move(chart));
      continue;
    }
    std::vector<std::vector<Index>> halves = SplitRegion(graph, part);
    if (halves[1].empty())
    {
      error = "A single triangle is not a disk: the surface is not manifold where it should be.";
      return false;
    }
    pending.push_back(std::move(halves[0]));
    pending.push_back(std::move(halves[1]));
  }
  return true;
}

namespace
{

/// The area of a region.
double RegionArea(const DualGraph& graph, const std::vector<Index>& region)
{
  double area = 0.0;
  for (Index t : region)
  {
    area += graph.Areas[t];
  }
  return area;
}

/// Section 4.2.4 for one pair: the union of two neighbouring charts split
/// again so that both halves carry the same area, along a level line of
/// d_a - d_b (d_a, d_b: the distances along the union from its two most
/// distant triangles; the line is a smooth seam between them).  True (the pair replaced) when both halves are disks.
/// localOf: all -1 (scratch, left all -1).
bool RebalancePair(const MeshTopology& topology, const DualGraph& graph, ChartMesh& first, ChartMesh& second,
  std::vector<Index>& localOf)
{
  std::vector<Index> both = first.Triangles;
  both.insert(both.end(), second.Triangles.begin(), second.Triangles.end());
  for (std::size_t k = 0; k < both.size(); ++k)
  {
    localOf[both[k]] = static_cast<Index>(k);
  }
  // The union's two most distant triangles, by a double sweep from the
  // triangle of the first chart farthest from the second (a start that does
  // not depend on the order of the triangles).
  const std::size_t split = first.Triangles.size();
  std::vector<Index> ofSecond(both.size() - split);
  std::iota(ofSecond.begin(), ofSecond.end(), static_cast<Index>(split));
  std::vector<double> fromSecond, fromA, fromB;
  NearestWithin(graph, both, localOf, ofSecond, fromSecond, nullptr);
  const Index start =
    static_cast<Index>(std::max_element(fromSecond.begin(), fromSecond.begin() + split) - fromSecond.begin());
  const Index b = FarthestPair(graph, both, localOf, start, fromA).second;
  NearestWithin(graph, both, localOf, { b }, fromB, nullptr);
  std::vector<std::pair<double, Index>> order(both.size()); // (d_a - d_b, triangle)
  for (std::size_t k = 0; k < both.size(); ++k)
  {
    order[k] = { fromA[k] - fromB[k], both[k] };
    localOf[both[k]] = -1;
  }
  std::sort(order.begin(), order.end());
  for (std::size_t k = 0; k < both.size(); ++k)
  {
    both[k] = order[k].second;
  }
  const double half = 0.5 * RegionArea(graph, both);
  double area = 0.0;
  std::size_t cut = 0;
  while (cut < both.size() && area + 0.5 * graph.Areas[both[cut]] < half)
  {
    area += graph.Areas[both[cut++]];
  }
  if (cut == 0 || cut == both.size())
  {
    return false;
  }
  ChartMesh one = ExtractChart(topology, std::vector<Index>(both.begin(), both.begin() + cut));
  ChartMesh two = ExtractChart(topology, std::vector<Index>(both.begin() + cut, both.end()));
  if (!IsDisk(one) || !IsDisk(two) || HasCutInside(graph, one) || HasCutInside(graph, two))
  {
    return false;
  }
  first = std::move(one);
  second = std::move(two);
  return true;
}

} // namespace

void BalanceChartAreas(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double ratio, int rounds)
{
  std::vector<Index> localOf(graph.NumberOfTriangles(), -1);
  for (int round = 0; round < rounds; ++round)
  {
    std::vector<int> chartOf(graph.NumberOfTriangles(), -1);
    std::vector<double> area(charts.size());
    for (std::size_t c = 0; c < charts.size(); ++c)
    {
      area[c] = RegionArea(graph, charts[c].Triangles);
      for (Index t : charts[c].Triangles)
      {
        chartOf[t] = static_cast<int>(c);
      }
    }
    // Neighbouring pairs whose areas differ by more than `ratio`, the most
    // unequal first; each chart rebalanced once per round.
    std::vector<std::tuple<double, int, int>> pairs;
    for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index n = graph.Neighbors[3 * t + k];
        const int c = chartOf[t], d = n >= 0 ? chartOf[n] : -1;
        if (d > c && c >= 0)
        {
          const double r = std::max(area[c], area[d]) / std::max(1e-300, std::min(area[c], area[d]));
          if (r > ratio)
          {
            pairs.emplace_back(-r, c, d);
          }
        }
      }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<std::uint8_t> done(charts.size(), 0);
    bool changed = false;
    for (const auto& [r, c, d] : pairs)
    {
      if (!done[c] && !done[d] && RebalancePair(topology, graph, charts[c], charts[d], localOf))
      {
        done[c] = done[d] = 1;
        changed = true;
      }
    }
    if (!changed)
    {
      break;
    }
  }
}

namespace
{

/// SplitIntoDisks on every region (in parallel; the disks in the regions'
/// order).
bool DisksOf(const MeshTopology& topology, const DualGraph& graph, std::vector<std::vector<Index>>& regions,
  std::vector<ChartMesh>& charts, std::string& error, int numThreads)
{
  std::vector<std::vector<ChartMesh>> disks(regions.size());
  std::vector<std::string> errors(regions.size());
  ParallelFor(static_cast<std::int64_t>(regions.size()), numThreads,
    [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t k = begin; k < end; ++k)
      {
        SplitIntoDisks(topology, graph, std::move(regions[k]), disks[k], errors[k]);
      }
    },
    {}, 0, 1);
  for (std::size_t k = 0; k < regions.size(); ++k)
  {
    if (!errors[k].empty())
    {
      error = errors[k];
      return false;
    }
    std::move(disks[k].begin(), disks[k].end(), std::back_inserter(charts));
  }
  return true;
}

/// The boundaries of splits are as jagged as the first regions' were (ears:
/// triangles with two edges on the chart's boundary, flat on a square's
/// side): SmoothRegionBoundaries on the charts, and what that leaves no disk
/// split again (SplitIntoDisks), twice at most.
bool SmoothCharts(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  std::string& error, int numThreads)
{
  for (int round = 0; round < 2; ++round)
  {
    std::vector<int> before(graph.NumberOfTriangles());
    for (std::size_t c = 0; c < charts.size(); ++c)
    {
      for (Index t : charts[c].Triangles)
      {
        before[t] = static_cast<int>(c);
      }
    }
    std::vector<int> label = before;
    SmoothRegionBoundaries(graph, label);
    if (label == before)
    {
      break;
    }
    std::vector<std::vector<Index>> regions(charts.size());
    for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
    {
      regions[label[t]].push_back(t);
    }
    charts.clear();
    if (!DisksOf(topology, graph, regions, charts, error, numThreads))
    {
      return false;
    }
  }
  return true;
}

} // namespace

namespace
{

/// Splits the charts larger than `maximumArea` until none is (single
/// triangles apart: counted in `oversized`).
bool SplitUntilSmallEnough(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double maximumArea, std::string& error, int& oversized, int numThreads)
{
  while (true)
  {
    std::vector<ChartMesh> kept;
    std::vector<std::vector<Index>> halves;
    oversized = 0;
    for (ChartMesh& chart : charts)
    {
      const bool large = RegionArea(graph, chart.Triangles) > maximumArea;
      if (large && chart.Triangles.size() > 1)
      {
        for (std::vector<Index>& half : SplitRegion(graph, chart.Triangles))
        {
          halves.push_back(std::move(half));
        }
        continue;
      }
      oversized += large;
      kept.push_back(std::move(chart));
    }
    charts = std::move(kept);
    if (halves.empty())
    {
      return true;
    }
    if (!DisksOf(topology, graph, halves, charts, error, numThreads))
    {
      return false;
    }
  }
}

} // namespace

bool SplitLargeCharts(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double maximumArea, std::string& error, int& oversized, int numThreads)
{
  // The splits' boundaries are smoothed, which can move an ear back over
  // the limit: split again; the last round is not smoothed.
  for (int round = 0;; ++round)
  {
    if (!SplitUntilSmallEnough(topology, graph, charts, maximumArea, error, oversized, numThreads))
    {
      return false;
    }
    if (round == 3)
    {
      return true;
    }
    if (!SmoothCharts(topology, graph, charts, error, numThreads))
    {
      return false;
    }
    if (std::none_of(charts.begin(), charts.end(), [&](const ChartMesh& c) {
          return c.Triangles.size() > 1 && RegionArea(graph, c.Triangles) > maximumArea;
        }))
    {
      return true;
    }
  }
}

bool PartitionIntoCharts(const MeshTopology& topology, const DualGraph& graph, int count,
  std::vector<ChartMesh>& charts, std::string& error, bool balance, int numThreads)
{
  charts.clear();
  const TopologySummary& s = topology.Summary();
  if (!s.IsManifold() || !s.IsOriented())
  {
    error = "An atlas needs a manifold, consistently oriented surface; the input has " + topology.Describe();
    return false;
  }
  std::vector<int> label;
  const std::vector<Index> seeds = ChooseSeeds(graph, count, &label);
  SmoothRegionBoundaries(graph, label);
  std::vector<std::vector<Index>> regions(seeds.size());
  for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
  {
    regions[label[t]].push_back(t);
  }
  if (!DisksOf(topology, graph, regions, charts, error, numThreads))
  {
    return false;
  }
  if (!SmoothCharts(topology, graph, charts, error, numThreads))
  {
    return false;
  }
  if (balance)
  {
    BalanceChartAreas(topology, graph, charts);
    if (!SmoothCharts(topology, graph, charts, error, numThreads))
    {
      return false;
    }
  }
  std::sort(charts.begin(), charts.end(),
    [](const ChartMesh& x, const ChartMesh& y) { return x.Triangles.front() < y.Triangles.front(); });
  return true;
}

} // namespace beltrami
