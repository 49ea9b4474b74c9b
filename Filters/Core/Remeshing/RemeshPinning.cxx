// Beltrami core: the fidelity rounds' move on an optimised remesh: the
// vertex nearest to an input vertex (or a point of an input edge) the
// remesh leaves far moved onto it and fixed there, joined by edges to the
// fixed vertices on the same input crease edge (JoinAlongInputEdges), the
// vertices around it settled by stitching rounds (PinNearestVertices).
#include "Remeshing/RemeshOptimizer.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

/// The rings around a vertex moved onto a far input vertex that the
/// stitching rounds after settle.
constexpr int PinnedRings = 3;

/// The least angle between the normals of an input edge's two triangles
/// that makes it a crease whose pinned vertices are joined along it
/// (Optimizer::JoinAlongInputEdges).
constexpr double JoinCreaseDegrees = 20.0;

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

namespace
{

/// The input vertices whose weights at v's place are not zero: one (v on
/// an input vertex), two (on an input edge) or three (inside a triangle);
/// none where v lies on no input triangle.
int Support(const MeshTopology& topology, const Remesh& r, Index v, Index* corners)
{
  int n = 0;
  for (int k = 0; k < 3 && r.Triangle[v] >= 0; ++k)
  {
    if (r.Barycentric[3 * static_cast<std::size_t>(v) + k] > 1e-9)
    {
      corners[n++] = topology.CornerVertex(3 * r.Triangle[v] + k);
    }
  }
  return n;
}

} // namespace

bool Optimizer::OnOneInputEdge(Index a, Index b) const
{
  if (Moves[a] != Fixed || Moves[b] != Fixed)
  {
    return false;
  }
  Index ca[3], cb[3];
  const int na = Support(Topology, R, a, ca), nb = Support(Topology, R, b, cb);
  if (na > 2 || nb > 2 || na == 0 || nb == 0)
  {
    return false;
  }
  // The input vertices of both together: at most two, joined by an edge.
  Index ends[4];
  int n = 0;
  for (const Index x : { ca[0], ca[na - 1], cb[0], cb[nb - 1] })
  {
    if (std::find(ends, ends + n, x) == ends + n)
    {
      ends[n++] = x;
    }
  }
  const MeshTopology::EdgeTable& edges = Topology.Edges();
  const std::int64_t e = n == 2 ? edges.Find(ends[0], ends[1]) : -1;
  if (e < 0 || edges.OppositeCorners[2 * e] < 0 || edges.OppositeCorners[2 * e + 1] < 0)
  {
    return false;
  }
  const Vec3 n0 = InputNormalOf(edges.OppositeCorners[2 * e] / 3);
  const Vec3 n1 = InputNormalOf(edges.OppositeCorners[2 * e + 1] / 3);
  return n0.dot(n1) < std::cos(JoinCreaseDegrees * 3.141592653589793 / 180.0);
}

void Optimizer::KeepEdgesAlongCreases(Index v)
{
  M.ForEachOutgoing(v, [&](Index h) {
    if (OnOneInputEdge(v, M.Head(h)))
    {
      KeptEdges.insert(EdgeKey(v, M.Head(h)));
    }
  });
}

Index Optimizer::JoinAlongInputEdges(const std::vector<Index>& pinned)
{
  Index joins = 0;
  for (const Index v : pinned)
  {
    KeepEdgesAlongCreases(v);
    std::vector<Index> across; // half-edges opposite v whose other face's far vertex is on v's input edge
    M.ForEachOutgoing(v, [&](Index h) {
      const Index g = HalfEdgeMesh::Next(h);
      if (!M.IsBoundary(g))
      {
        const Index u = M.Tail(HalfEdgeMesh::Prev(M.Twin(g)));
        if (u != v && OnOneInputEdge(v, u))
        {
          across.push_back(g);
        }
      }
    });
    for (const Index g : across)
    {
      // (An earlier join may have changed the faces: g still opposite v?)
      const Index u = M.Tail(HalfEdgeMesh::Prev(M.Twin(g)));
      if (M.Tail(HalfEdgeMesh::Prev(g)) != v || !OnOneInputEdge(v, u) || !Swappable(g) || !CanSwap(g))
      {
        continue;
      }
      const auto [before, after] = Roundnesses(g);
      if (after >= 0.5 * before)
      {
        Flip(g);
        KeptEdges.insert(EdgeKey(v, u));
        ++joins;
      }
    }
  }
  return joins;
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
  optimizer.JoinAlongInputEdges(moved);
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
