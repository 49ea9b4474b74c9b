// Beltrami core: the later stages of the partition into charts
// (Maps/ChartPartition.h): regions split into disks (in parallel), their
// boundaries smoothed, the area-balanced refinement of thesis section
// 4.2.4, the largest chart area, and the whole partition.
#include "Maps/ChartPartition.h"
#include "Maps/ChartPartitionDetail.h"
#include "Support/Parallel.h"

#include <algorithm>
#include <iterator>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

namespace beltrami
{

using namespace detail;

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
bool RebalancePair(const MeshTopology& topology, const DualGraph& graph, ChartMesh& first, ChartMesh& second)
{
  std::vector<Index> both = first.Triangles;
  both.insert(both.end(), second.Triangles.begin(), second.Triangles.end());
  // The union's two most distant triangles, by a double sweep from the
  // triangle of the first chart farthest from the second (a start that does
  // not depend on the order of the triangles).
  const std::size_t split = first.Triangles.size();
  std::vector<Index> ofSecond(both.size() - split);
  std::iota(ofSecond.begin(), ofSecond.end(), static_cast<Index>(split));
  std::vector<double> fromSecond, fromA, fromB;
  {
    const RegionIds ids(graph, both);
    NearestWithin(graph, both, ids.Of(), ofSecond, fromSecond, nullptr);
    const Index start =
      static_cast<Index>(std::max_element(fromSecond.begin(), fromSecond.begin() + split) - fromSecond.begin());
    const Index b = FarthestPair(graph, both, ids.Of(), start, fromA).second;
    NearestWithin(graph, both, ids.Of(), { b }, fromB, nullptr);
  }
  std::vector<std::pair<double, Index>> order(both.size()); // (d_a - d_b, triangle)
  for (std::size_t k = 0; k < both.size(); ++k)
  {
    order[k] = { fromA[k] - fromB[k], both[k] };
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
  if (!IsChart(graph, one) || !IsChart(graph, two))
  {
    return false;
  }
  first = std::move(one);
  second = std::move(two);
  return true;
}

} // namespace

void BalanceChartAreas(const MeshTopology& topology, const DualGraph& graph, std::vector<ChartMesh>& charts,
  double ratio, int rounds, int numThreads)
{
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
    // In waves: the pairs that no earlier pair still open shares a chart
    // with are rebalanced in parallel.  A pair meets its charts as the
    // serial loop would (only earlier pairs with one of them change them),
    // so the outcome is that loop's for any thread count.
    std::vector<std::uint8_t> done(charts.size(), 0);
    bool changed = false;
    while (!pairs.empty())
    {
      std::vector<std::uint8_t> busy = done;
      std::vector<std::tuple<double, int, int>> wave, later;
      for (const auto& pair : pairs)
      {
        const auto& [r, c, d] = pair;
        if (!done[c] && !done[d])
        {
          (busy[c] || busy[d] ? later : wave).push_back(pair);
          busy[c] = busy[d] = 1;
        }
      }
      std::vector<std::uint8_t> rebalanced(wave.size(), 0);
      ParallelFor(static_cast<std::int64_t>(wave.size()), numThreads, [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t k = begin; k < end; ++k)
        {
          const auto& [r, c, d] = wave[k];
          rebalanced[k] = RebalancePair(topology, graph, charts[c], charts[d]);
        }
      }, {}, 0, 1);
      for (std::size_t k = 0; k < wave.size(); ++k)
      {
        if (rebalanced[k])
        {
          done[std::get<1>(wave[k])] = done[std::get<2>(wave[k])] = 1;
          changed = true;
        }
      }
      pairs = std::move(later);
    }
    if (!changed)
    {
      break;
    }
  }
}

namespace
{

/// SplitIntoDisks on every region (in parallel): the disks of each region.
/// False with `error` as SplitIntoDisks.
bool DisksPerRegion(const MeshTopology& topology, const DualGraph& graph, std::vector<std::vector<Index>>& regions,
  std::vector<std::vector<ChartMesh>>& disks, std::string& error, int numThreads)
{
  disks.assign(regions.size(), {});
  std::vector<std::string> errors(regions.size());
  ParallelFor(static_cast<std::int64_t>(regions.size()), numThreads,
    [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t k = begin; k < end; ++k)
      {
        SplitIntoDisks(topology, graph, std::move(regions[k]), disks[k], errors[k]);
      }
    },
    {}, 0, 1);
  const auto failed = std::find_if(errors.begin(), errors.end(), [](const std::string& e) { return !e.empty(); });
  if (failed != errors.end())
  {
    error = *failed;
    return false;
  }
  return true;
}

/// The disks of every region appended to `charts`, in the regions' order.
bool DisksOf(const MeshTopology& topology, const DualGraph& graph, std::vector<std::vector<Index>>& regions,
  std::vector<ChartMesh>& charts, std::string& error, int numThreads)
{
  std::vector<std::vector<ChartMesh>> disks;
  if (!DisksPerRegion(topology, graph, regions, disks, error, numThreads))
  {
    return false;
  }
  for (std::vector<ChartMesh>& some : disks)
  {
    std::move(some.begin(), some.end(), std::back_inserter(charts));
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
    // Only the charts that lost or gained a triangle are extracted again;
    // the others keep their mesh and topology (and every chart its place).
    std::vector<int> slot(charts.size(), -1);
    std::vector<std::vector<Index>> regions;
    for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
    {
      if (label[t] != before[t])
      {
        for (const int c : { label[t], before[t] })
        {
          if (slot[c] < 0)
          {
            slot[c] = static_cast<int>(regions.size());
            regions.emplace_back();
          }
        }
      }
    }
    for (Index t = 0; t < graph.NumberOfTriangles(); ++t)
    {
      if (slot[label[t]] >= 0)
      {
        regions[slot[label[t]]].push_back(t);
      }
    }
    std::vector<std::vector<ChartMesh>> disks;
    if (!DisksPerRegion(topology, graph, regions, disks, error, numThreads))
    {
      return false;
    }
    std::vector<ChartMesh> smoothed;
    for (std::size_t c = 0; c < charts.size(); ++c)
    {
      if (slot[c] < 0)
      {
        smoothed.push_back(std::move(charts[c]));
        continue;
      }
      std::vector<ChartMesh>& some = disks[slot[c]];
      std::move(some.begin(), some.end(), std::back_inserter(smoothed));
    }
    charts = std::move(smoothed);
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
  const std::vector<Index> seeds = ChooseSeeds(graph, count, &label, numThreads);
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
    BalanceChartAreas(topology, graph, charts, 1.5, 8, numThreads);
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
