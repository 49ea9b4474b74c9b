#include "Maps/ChartPartition.h"
#include "Maps/ChartPartitionDetail.h"

#include "Mesh/Geometry.h"
#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>

namespace beltrami
{

using namespace detail;

DualGraph::DualGraph(const MeshTopology& topology, const double* points, const std::vector<std::uint8_t>* cut)
{
  const Index nt = topology.NumberOfTriangles();
  const IndexArray& tri = topology.TriangleList();
  Neighbors.assign(3 * static_cast<std::size_t>(nt), -1);
  Distances.assign(3 * static_cast<std::size_t>(nt), 0.0);
  Areas.resize(nt);
  LargeVector<Vec3> centroid(nt);
  ParallelFor(nt, topology.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    for (Index t = static_cast<Index>(begin); t < end; ++t)
    {
      const Vec3 a = Point(points, tri[3 * t]), b = Point(points, tri[3 * t + 1]), c = Point(points, tri[3 * t + 2]);
      centroid[t] = (a + b + c) / 3.0;
      Areas[t] = 0.5 * (b - a).cross(c - a).norm();
    }
  });
  // Each triangle's neighbours across its interior, uncut edges, in the
  // order of the edges' ids.
  const MeshTopology::EdgeTable& edges = topology.Edges();
  const auto joinsTwo = [&](std::int64_t e) { // an edge between two triangles
    return e >= 0 && edges.FaceCount[e] == 2 && edges.OppositeCorners[2 * e] >= 0 && edges.OppositeCorners[2 * e + 1] >= 0;
  };
  ParallelFor(nt, topology.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    for (Index t = static_cast<Index>(begin); t < end; ++t)
    {
      std::array<std::int64_t, 3> own;
      for (int k = 0; k < 3; ++k)
      {
        own[k] = edges.Find(tri[3 * t + k], tri[3 * t + (k + 1) % 3]);
      }
      std::sort(own.begin(), own.end());
      int slot = 0;
      for (const std::int64_t e : own)
      {
        if (!joinsTwo(e) || (cut && (*cut)[e]))
        {
          continue;
        }
        const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
        const Index to = c0 / 3 == t ? c1 / 3 : c0 / 3;
        Neighbors[3 * t + slot] = to;
        Distances[3 * t + slot] = (centroid[t] - centroid[to]).norm();
        ++slot;
      }
    }
  });
  for (std::int64_t e = 0; cut && e < edges.NumberOfEdges(); ++e)
  {
    if ((*cut)[e] && joinsTwo(e))
    {
      const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
      Cuts.emplace_back(c0 / 3, c1 / 3);
      Cuts.emplace_back(c1 / 3, c0 / 3);
    }
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
  // The thread's surface vertex -> chart vertex map (all -1 between uses:
  // charts are extracted on several threads at once).
  thread_local std::vector<Index> localOf;
  localOf.resize(topology.NumberOfVertices(), -1);
  for (Index t : chart.Triangles)
  {
    for (int c = 0; c < 3; ++c)
    {
      if (localOf[tri[3 * t + c]] < 0)
      {
        localOf[tri[3 * t + c]] = 0;
        chart.Vertices.push_back(tri[3 * t + c]);
      }
    }
  }
  std::sort(chart.Vertices.begin(), chart.Vertices.end());
  for (std::size_t k = 0; k < chart.Vertices.size(); ++k)
  {
    localOf[chart.Vertices[k]] = static_cast<Index>(k);
  }
  chart.Corners.resize(3 * chart.Triangles.size());
  for (std::size_t k = 0; k < chart.Triangles.size(); ++k)
  {
    for (int c = 0; c < 3; ++c)
    {
      chart.Corners[3 * k + c] = localOf[tri[3 * chart.Triangles[k] + c]];
    }
  }
  for (const Index v : chart.Vertices)
  {
    localOf[v] = -1;
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

namespace
{

/// True when pred(u) holds for a triangle u across a cut edge of t.
template <typename Predicate>
bool AnyAcrossCut(const DualGraph& graph, Index t, Predicate&& pred)
{
  auto cut = std::lower_bound(graph.Cuts.begin(), graph.Cuts.end(), std::make_pair(t, Index(-1)));
  for (; cut != graph.Cuts.end() && cut->first == t; ++cut)
  {
    if (pred(cut->second))
    {
      return true;
    }
  }
  return false;
}

/// A monotone priority queue of (key, value) pairs (a radix heap): every
/// key pushed is at least the key last popped.  Entries are kept in 33
/// buckets by the highest bit in which their key differs from that key;
/// a pop empties the first non-empty bucket into the lower ones.  Bucket 0
/// (the keys equal to the last) is a binary heap, so entries come out in
/// the order of (key, value), as from a plain priority queue.
class RadixHeap
{
public:
  bool Empty() const { return Size == 0; }

  void Push(std::uint32_t key, std::uint32_t value)
  {
    const std::uint64_t entry = (static_cast<std::uint64_t>(key) << 32) | value;
    const int b = BucketOf(key);
    Buckets[b].push_back(entry);
    if (b == 0)
    {
      std::push_heap(Buckets[0].begin(), Buckets[0].end(), std::greater<>());
    }
    ++Size;
  }

  /// The entry of the smallest key (of the smallest value among those).
  std::pair<std::uint32_t, std::uint32_t> Pop()
  {
    std::vector<std::uint64_t>& first = Buckets[0];
    if (first.empty())
    {
      int i = 1;
      while (Buckets[i].empty())
      {
        ++i;
      }
      std::vector<std::uint64_t>& from = Buckets[i];
      Last = static_cast<std::uint32_t>(*std::min_element(from.begin(), from.end()) >> 32);
      for (const std::uint64_t entry : from)
      {
        Buckets[BucketOf(static_cast<std::uint32_t>(entry >> 32))].push_back(entry);
      }
      from.clear();
      std::make_heap(first.begin(), first.end(), std::greater<>());
    }
    std::pop_heap(first.begin(), first.end(), std::greater<>());
    const std::uint64_t entry = first.back();
    first.pop_back();
    --Size;
    return { static_cast<std::uint32_t>(entry >> 32), static_cast<std::uint32_t>(entry) };
  }

private:
  std::vector<std::uint64_t> Buckets[33];
  std::uint32_t Last = 0;
  std::size_t Size = 0;

  int BucketOf(std::uint32_t key) const { return key == Last ? 0 : 32 - __builtin_clz(key ^ Last); }
};

} // namespace

bool detail::IsChart(const DualGraph& graph, const ChartMesh& chart)
{
  return IsDisk(chart) && !HasCutInside(graph, chart);
}

bool HasCutInside(const DualGraph& graph, const ChartMesh& chart)
{
  return std::any_of(chart.Triangles.begin(), chart.Triangles.end(), [&](Index t) {
    return AnyAcrossCut(graph, t, [&](Index u) {
      return std::binary_search(chart.Triangles.begin(), chart.Triangles.end(), u); // ascending
    });
  });
}

void detail::NearestWithin(const DualGraph& graph, const std::vector<Index>& region, const std::vector<Index>& localOf,
  const std::vector<Index>& sources, std::vector<double>& distance, std::vector<int>* label)
{
  const bool whole = region.empty();
  const std::size_t size = whole ? static_cast<std::size_t>(graph.NumberOfTriangles()) : region.size();
  distance.assign(size, std::numeric_limits<double>::infinity());
  if (label)
  {
    label->assign(size, -1);
  }
  // Keys are the distances rounded to float (their bits order like the
  // values; rounding is monotone, so a key pushed is never below the key
  // last popped: a radix heap serves).  The distances themselves stay
  // double: an entry popped a rounding early is corrected later, so the
  // result is the exact shortest distance.
  const auto key = [](double d) {
    const float f = static_cast<float>(d);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits;
  };
  RadixHeap queue;
  for (std::size_t k = 0; k < sources.size(); ++k)
  {
    distance[sources[k]] = 0.0;
    if (label)
    {
      (*label)[sources[k]] = static_cast<int>(k);
    }
    queue.Push(0, static_cast<std::uint32_t>(sources[k]));
  }
  while (!queue.Empty())
  {
    const auto [top, value] = queue.Pop();
    const Index local = static_cast<Index>(value);
    if (top > key(distance[local]))
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
        queue.Push(key(nd), static_cast<std::uint32_t>(m));
      }
    }
  }
}

namespace
{

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
/// farthest from the region's boundary (its centre along the surface; the
/// first such triangle in id order).  Each region's distances come from a
/// Dijkstra within it, from its boundary triangles (those with a neighbour
/// in another region, a cut or the surface's boundary), the regions on
/// separate threads.  That is the one Dijkstra from every boundary triangle
/// over the whole surface, to the bit: a shortest path into a region
/// enters it through one of its boundary triangles, which are sources.
std::vector<Index> CentreSeeds(const DualGraph& graph, const std::vector<int>& label, std::size_t regions,
  int numThreads)
{
  std::vector<std::vector<Index>> members(regions); // ascending ids
  for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
  {
    members[label[t]].push_back(t);
  }
  std::vector<Index> centre(regions, -1);
  ParallelFor(static_cast<std::int64_t>(regions), numThreads, [&](std::int64_t begin, std::int64_t end) {
    std::vector<Index> sources;
    std::vector<double> inward;
    for (std::int64_t r = begin; r < end; ++r)
    {
      const std::vector<Index>& region = members[r];
      const detail::RegionIds ids(graph, region);
      sources.clear();
      for (std::size_t k = 0; k < region.size(); ++k)
      {
        for (int j = 0; j < 3; ++j)
        {
          const Index n = graph.Neighbors[3 * region[k] + j];
          if (n < 0 || label[n] != static_cast<int>(r))
          {
            sources.push_back(static_cast<Index>(k));
            break;
          }
        }
      }
      if (!sources.empty())
      {
        NearestWithin(graph, region, ids.Of(), sources, inward, nullptr);
      }
      std::size_t best = 0;
      for (std::size_t k = 1; k < region.size() && !sources.empty(); ++k)
      {
        best = inward[k] > inward[best] ? k : best;
      }
      centre[r] = region.empty() ? -1 : region[best];
    }
  }, {}, 0, 1);
  return centre;
}

} // namespace

std::vector<Index> ChooseSeeds(const DualGraph& graph, int count, std::vector<int>* label, int numThreads)
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
  seeds = CentreSeeds(graph, regions, seeds.size(), numThreads);
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

std::vector<Index>& ThreadRegionIds()
{
  thread_local std::vector<Index> ids;
  return ids;
}

} // namespace

detail::RegionIds::RegionIds(const DualGraph& graph, const std::vector<Index>& region)
  : Ids(ThreadRegionIds())
  , Region(region)
{
  Ids.resize(graph.NumberOfTriangles(), -1);
  for (std::size_t k = 0; k < Region.size(); ++k)
  {
    Ids[Region[k]] = static_cast<Index>(k);
  }
}

detail::RegionIds::~RegionIds()
{
  for (const Index t : Region)
  {
    Ids[t] = -1;
  }
}

std::pair<Index, Index> detail::FarthestPair(const DualGraph& graph, const std::vector<Index>& region,
  const std::vector<Index>& localOf, Index start, std::vector<double>& fromA)
{
  std::vector<double> fromStart;
  NearestWithin(graph, region, localOf, { start }, fromStart, nullptr);
  const Index a = static_cast<Index>(std::max_element(fromStart.begin(), fromStart.end()) - fromStart.begin());
  NearestWithin(graph, region, localOf, { a }, fromA, nullptr);
  const Index b = static_cast<Index>(std::max_element(fromA.begin(), fromA.end()) - fromA.begin());
  return { a, b };
}

/// A tube (annulus) at least this many times longer than its girth is cut
/// along its length (SplitRegion).
constexpr double LongTubeRatio = 4.0;

std::vector<std::vector<Index>> SplitRegion(const DualGraph& graph, const std::vector<Index>& triangles, bool annulus)
{
  const detail::RegionIds ids(graph, triangles);
  const std::vector<Index>& localOf = ids.Of();
  std::vector<double> fromA, distance;
  auto [a, b] = FarthestPair(graph, triangles, localOf, 0, fromA);
  std::vector<std::vector<Index>> halves(2);
  if (a == b)
  {
    halves[0] = triangles;
    return halves;
  }
  if (annulus)
  {
    // a and b at the tube's two ends: the rim triangle on a's side farthest
    // from a lies across the tube from it, and the two halves nearer each
    // are the tube cut along its length.
    std::vector<double> fromB;
    NearestWithin(graph, triangles, localOf, { b }, fromB, nullptr);
    Index across = -1;
    for (std::size_t k = 0; k < triangles.size(); ++k)
    {
      const Index* n = &graph.Neighbors[3 * static_cast<std::int64_t>(triangles[k])];
      const bool rim = std::any_of(n, n + 3, [&](Index u) { return u < 0 || localOf[u] < 0; });
      if (rim && fromA[k] < fromB[k] && (across < 0 || fromA[k] > fromA[across]))
      {
        across = static_cast<Index>(k);
      }
    }
    // Only a tube much longer than round (its length at least
    // LongTubeRatio times its girth, twice the way across): a shorter one's
    // halves along are disks soon enough.
    if (across >= 0 && across != a && fromA[b] >= LongTubeRatio * 2.0 * fromA[across])
    {
      b = across;
    }
  }
  std::vector<int> label;
  NearestWithin(graph, triangles, localOf, { a, b }, distance, &label);
  for (std::size_t k = 0; k < triangles.size(); ++k)
  {
    halves[label[k] == 1 ? 1 : 0].push_back(triangles[k]);
  }
  return halves;
}

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
      // (never into the region across a cut edge of t: the cut would be inside it)
      if (own <= 1 && count >= 2 && !AnyAcrossCut(graph, t, [&](Index u) { return label[u] == other; }))
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
    if (IsChart(graph, chart))
    {
      disks.push_back(std::move(chart));
      continue;
    }
    const TopologySummary& shape = chart.Topology->Summary();
    std::vector<std::vector<Index>> halves = SplitRegion(graph, part,
      shape.IsManifold() && shape.NumberOfBoundaryLoops == 2 && shape.EulerCharacteristic == 0);
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

} // namespace beltrami
