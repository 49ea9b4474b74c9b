// Beltrami core, private to Maps: the pieces of ChartPartition.cxx that the
// partition's later stages (ChartRefinement.cxx: charts split into disks,
// smoothed, balanced, kept below a size) use too.
#pragma once

#include "Maps/ChartPartition.h"

#include <utility>
#include <vector>

namespace beltrami
{
namespace detail
{

/// The one Dijkstra of the partition: from `sources` (local ids; source k
/// labelled k) over a set of triangles with local ids - region[k] the
/// triangle of local id k, localOf[t] the local id of t (-1 outside); both
/// empty: every triangle, local = global - each triangle's distance along the
/// dual graph to the nearest source and that source's label.
void NearestWithin(const DualGraph& graph, const std::vector<Index>& region, const std::vector<Index>& localOf,
  const std::vector<Index>& sources, std::vector<double>& distance, std::vector<int>* label);

/// The calling thread's triangle -> local id map of one region (NearestWithin's
/// localOf: region[k] -> k, -1 elsewhere) while it lives, one at a time per
/// thread: made once per thread at the graph's size and -1 again after each
/// use, so a region costs its own size, not the surface's (regions are split
/// and measured on several threads at once).  `region` must outlive it
/// unchanged.
class RegionIds
{
public:
  RegionIds(const DualGraph& graph, const std::vector<Index>& region);
  ~RegionIds();
  RegionIds(const RegionIds&) = delete;
  RegionIds& operator=(const RegionIds&) = delete;
  const std::vector<Index>& Of() const { return Ids; }

private:
  std::vector<Index>& Ids;
  const std::vector<Index>& Region;
};

/// The two triangles of a region (local ids) farthest apart along it: the
/// farthest from `start`, and the farthest from that one (fromA: the
/// distances from the first).
std::pair<Index, Index> FarthestPair(const DualGraph& graph, const std::vector<Index>& region,
  const std::vector<Index>& localOf, Index start, std::vector<double>& fromA);

/// A disk without a cut inside: what every chart must be.
bool IsChart(const DualGraph& graph, const ChartMesh& chart);

} // namespace detail
} // namespace beltrami
