// Beltrami core: the fidelity rounds' move on an optimised remesh: the
// vertex nearest to an input vertex (or a point of an input edge) the
// remesh leaves far moved onto it and fixed there, the vertices around it
// settled by stitching rounds (PinNearestVertices).
#include "Remeshing/RemeshOptimizer.h"

#include <algorithm>

namespace beltrami
{

/// The rings around a vertex moved onto a far input vertex that the
/// stitching rounds after settle.
constexpr int PinnedRings = 3;

namespace detail
{

Index Optimizer::PinNear(const PinTarget& target)
{
  const Vec3 p = target.Vertex >= 0 ? Point(Points, target.Vertex)
                                    : SurfacePoint(Topology, Points, target.Triangle, target.W.data());
  std::vector<std::pair<double, Index>> candidates; // (squared distance, vertex)
  for (Index h = 3 * target.Face; h < 3 * target.Face + 3; ++h)
  {
    M.ForEachOutgoing(M.Tail(h), [&](Index g) {
      for (const Index v : { M.Tail(g), M.Head(g) })
      {
        if (Moves[v] == Free)
        {
          candidates.push_back({ (M.Position(v) - p).squaredNorm(), v });
        }
      }
    });
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (const auto& [distance, v] : candidates)
  {
    if (PinAt(v, target))
    {
      return v;
    }
  }
  return -1;
}

bool Optimizer::PinAt(Index v, const PinTarget& target)
{
  const Vec3 normal = FanNormal(v);
  const auto place = [&](Index triangle, const double* w) {
    double moved = 0.0;
    if (!Place(v, triangle, w, moved, &normal, 0.0))
    {
      return false;
    }
    Moves[v] = Fixed;
    R.Kind[v] = SampleKind::Tip;
    R.Path[v] = -1;
    return true;
  };
  if (target.Vertex < 0)
  {
    return place(target.Triangle, target.W.data());
  }
  for (const Index* c = Topology.CornersBegin(target.Vertex); c != Topology.CornersEnd(target.Vertex); ++c)
  {
    double w[3] = { 0.0, 0.0, 0.0 };
    w[*c % 3] = 1.0;
    if (place(*c / 3, w))
    {
      return true;
    }
  }
  return false;
}

} // namespace detail

namespace
{

/// The vertices within `rings` edges of `seeds` (flags per vertex).
std::vector<std::uint8_t> RingsAround(const HalfEdgeMesh& mesh, std::vector<Index> seeds, int rings)
{
  std::vector<std::uint8_t> within(mesh.NumberOfVertices(), 0);
  for (const Index v : seeds)
  {
    within[v] = 1;
  }
  for (int ring = 0; ring < rings; ++ring)
  {
    std::vector<Index> next;
    for (const Index v : seeds)
    {
      mesh.ForEachOutgoing(v, [&](Index h) {
        for (const Index u : { mesh.Head(h), mesh.Tail(HalfEdgeMesh::Prev(h)) })
        {
          if (!within[u])
          {
            within[u] = 1;
            next.push_back(u);
          }
        }
      });
    }
    seeds = std::move(next);
  }
  return within;
}

} // namespace

PinnedVertices PinNearestVertices(Remesh& remesh, const MeshTopology& topology, const double* points,
  const AtlasResult& atlas, const SurfaceSamples& samples, const std::vector<PinTarget>& targets,
  const RemeshOptimizationOptions& options, int rounds)
{
  detail::Optimizer optimizer(
    remesh, topology, points, atlas, samples, options.Importance, options.Metric, options.Cache);
  optimizer.NumberOfThreads = options.NumberOfThreads;
  optimizer.OverRelaxation = std::max(1.0, options.OverRelaxation);
  optimizer.BeginStitching(options.FeatureEdges);
  std::vector<Index> moved;
  PinnedVertices out;
  std::vector<std::uint8_t> taken(remesh.Mesh.NumberOfVertices(), 0); // moved in this call
  for (const PinTarget& target : targets)
  {
    const HalfEdgeMesh& mesh = remesh.Mesh;
    const Index face = target.Face;
    if (target.Vertex >= 0 && (taken[mesh.Tail(3 * face)] || taken[mesh.Tail(3 * face + 1)] ||
                                taken[mesh.Tail(3 * face + 2)]))
    {
      continue; // (a vertex of the face moved already: the next round measures again)
    }
    const Index v = optimizer.PinNear(target);
    if (v < 0)
    {
      out.Unreached += target.Vertex >= 0;
      continue;
    }
    moved.push_back(v);
    taken[v] = 1;
    if (target.Vertex >= 0)
    {
      out.Reached.push_back(target.Vertex);
    }
    else
    {
      ++out.ReachedPoints;
    }
  }
  if (moved.empty())
  {
    return out;
  }
  optimizer.Active = RingsAround(remesh.Mesh, moved, PinnedRings);
  RemeshOptimizationStatistics stats;
  for (int i = 0; i < rounds; ++i)
  {
    optimizer.OptimizationRound(stats);
  }
  optimizer.SwapSlivers();
  optimizer.MendSlivers(20.0);
  return out;
}

} // namespace beltrami
