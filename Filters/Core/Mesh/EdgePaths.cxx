// Beltrami core: shortest paths along mesh edges.
#include "Mesh/EdgePaths.h"

#include "Mesh/Geometry.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace beltrami
{
std::vector<Index> ShortestEdgePath(const MeshTopology& topology, const double* points, Index from, Index to)
{
  const Index n = topology.NumberOfVertices();
  if (from < 0 || to < 0 || from >= n || to >= n)
  {
    return {};
  }
  const MeshTopology::VertexGraph& edges = topology.Graph();
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<Index> previous(n, -1);
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  distance[from] = 0.0;
  queue.push({ 0.0, from });
  while (!queue.empty())
  {
    const auto [d, v] = queue.top();
    queue.pop();
    if (v == to)
    {
      break;
    }
    if (d > distance[v])
    {
      continue; // a stale entry
    }
    for (std::int64_t k = edges.NeighborOffsets[v]; k < edges.NeighborOffsets[v + 1]; ++k)
    {
      const Index w = edges.Neighbors[k];
      const double through = d + (Point(points, w) - Point(points, v)).norm();
      if (through < distance[w])
      {
        distance[w] = through;
        previous[w] = v;
        queue.push({ through, w });
      }
    }
  }
  if (from != to && previous[to] < 0)
  {
    return {};
  }
  std::vector<Index> path{ to };
  while (path.back() != from)
  {
    path.push_back(previous[path.back()]);
  }
  std::reverse(path.begin(), path.end());
  return path;
}
} // namespace beltrami
