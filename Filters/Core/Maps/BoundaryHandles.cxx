// Beltrami core: boundary handles moved through a kept boundary basis.
#include "Maps/BoundaryHandles.h"

#include "Maps/BoundaryPlacement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace beltrami
{
namespace
{
/// Adds to `placed` (2 per vertex) the displacements `moved` (2 per vertex,
/// set at the handles) interpolated by arc length along the closed `loop`
/// between the handles (positions `at` in the loop, ascending) around each
/// vertex.
void FollowHandles(const std::vector<Index>& loop, const double* points, const std::vector<std::size_t>& at,
  const std::vector<double>& moved, std::vector<double>& placed)
{
  const std::vector<double> s = LoopParameter(loop, points, BoundarySpacing::ArcLength);
  const auto ahead = [&](std::size_t from, std::size_t to) { // arc length from `from` forward to `to`
    return to >= from ? s[to] - s[from] : s[to] - s[from] + 1.0;
  };
  for (std::size_t k = 0; k < loop.size(); ++k)
  {
    // The last handle at or before k (cyclically) and the one after it.
    const auto next = std::upper_bound(at.begin(), at.end(), k);
    const std::size_t before = next == at.begin() ? at.back() : *(next - 1);
    const std::size_t after = next == at.end() ? at.front() : *next;
    const double span = before == after ? 0.0 : ahead(before, after);
    const double t = span > 0.0 ? ahead(before, k) / span : 0.0;
    for (int d = 0; d < 2; ++d)
    {
      placed[2 * loop[k] + d] += (1.0 - t) * moved[2 * loop[before] + d] + t * moved[2 * loop[after] + d];
    }
  }
}
} // namespace

std::string MoveBoundaryHandles(const MeshTopology& topology, const double* points, const BoundaryBasis& basis,
  const std::vector<double>& solvedUV, const std::vector<BoundaryHandle>& handles, std::vector<double>& uv)
{
  const Index n = basis.NumberOfVertices();
  std::vector<std::uint8_t> fixed(n, 0), handled(n, 0);
  for (const Index v : basis.BoundaryVertices())
  {
    fixed[v] = 1;
  }
  std::vector<double> moved(2 * static_cast<std::size_t>(n), 0.0);
  for (const BoundaryHandle& h : handles)
  {
    if (h.Vertex < 0 || h.Vertex >= n || !fixed[h.Vertex])
    {
      return "Boundary handle on point " + std::to_string(h.Vertex) + ", which is not a point of the fixed boundary";
    }
    if (!std::isfinite(h.Target[0]) || !std::isfinite(h.Target[1]))
    {
      return "Boundary handle on point " + std::to_string(h.Vertex) + " has a target that is not finite";
    }
    handled[h.Vertex] = 1;
    moved[2 * h.Vertex] = h.Target[0] - solvedUV[2 * h.Vertex];
    moved[2 * h.Vertex + 1] = h.Target[1] - solvedUV[2 * h.Vertex + 1];
  }
  std::vector<double> placed(solvedUV);
  for (const std::vector<Index>& loop : topology.BoundaryLoops())
  {
    std::vector<std::size_t> at;
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      if (handled[loop[k]])
      {
        at.push_back(k);
      }
    }
    if (!at.empty())
    {
      FollowHandles(loop, points, at, moved, placed);
    }
  }
  std::vector<double> boundary;
  boundary.reserve(2 * basis.BoundaryVertices().size());
  for (const Index v : basis.BoundaryVertices())
  {
    boundary.push_back(placed[2 * v]);
    boundary.push_back(placed[2 * v + 1]);
  }
  uv.assign(2 * static_cast<std::size_t>(n), 0.0);
  basis.Apply(boundary.data(), uv.data());
  return {};
}
} // namespace beltrami
