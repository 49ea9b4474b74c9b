#include "Remeshing/RemeshOptimizer.h"

#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <queue>

namespace beltrami::detail
{

double Roundness(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const double perimeter = (b - a).norm() + (c - b).norm() + (a - c).norm();
  const double area = 0.5 * (b - a).cross(c - a).norm();
  return perimeter > 0.0 ? area / (perimeter * perimeter) * (36.0 / std::sqrt(3.0)) : 0.0;
}

double LargestCosine(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 ab = (b - a).normalized(), bc = (c - b).normalized(), ca = (a - c).normalized();
  return std::max({ -ab.dot(ca), -bc.dot(ab), -ca.dot(bc) });
}
/// The flip of h's edge (faces (a, b, c), (b, a, d) -> (c, a, d), (d, b, c))
/// keeps both new faces positively oriented in the chart.
bool Optimizer::FlipKeepsCharts(Index h) const
{
  const Index t = M.Twin(h);
  const double *a = UVAt(h), *b = UVAt(HalfEdgeMesh::Next(h)), *c = UVAt(HalfEdgeMesh::Prev(h));
  const double* d = UVAt(HalfEdgeMesh::Prev(t));
  const double scale = std::abs(Cross2(a, b, c)) + std::abs(Cross2(b, a, d));
  return Cross2(c, a, d) > 1e-6 * scale && Cross2(d, b, c) > 1e-6 * scale;
}

bool Folded(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb, const Vec3& nc)
{
  return na.dot(nb) > 0.5 && nb.dot(nc) > 0.5 && nc.dot(na) > 0.5 && !((b - a).cross(c - a).dot(na + nb + nc) > 0.0);
}

/// The folded faces of h's edge (faces (a, b, c), (b, a, d)), or of the
/// two after its flip ((c, a, d), (d, b, c)).
int Optimizer::FoldsOfFlip(Index h, bool flipped) const
{
  const Index t = M.Twin(h);
  const Index a = M.Tail(h), b = M.Head(h), c = M.Tail(HalfEdgeMesh::Prev(h)), d = M.Tail(HalfEdgeMesh::Prev(t));
  const Vec3 pa = M.Position(a), pb = M.Position(b), pc = M.Position(c), pd = M.Position(d);
  const Vec3 &na = InputNormals[a], &nb = InputNormals[b], &nc = InputNormals[c], &nd = InputNormals[d];
  return flipped ? Folded(pc, pa, pd, nc, na, nd) + Folded(pd, pb, pc, nd, nb, nc)
                 : Folded(pa, pb, pc, na, nb, nc) + Folded(pb, pa, pd, nb, na, nd);
}

/// The flip of h's edge does not fold the surface: the new faces' normals
/// are within 60 degrees of the old ones' mean and neither is folded
/// (Folded); where one of the old faces is folded, the flip folds fewer.
bool Optimizer::FlipKeepsSurface(Index h) const
{
  const int before = FoldsOfFlip(h, false), after = FoldsOfFlip(h, true);
  if (before > 0)
  {
    return after < before;
  }
  const Index t = M.Twin(h);
  const Vec3 pa = M.Position(M.Tail(h)), pb = M.Position(M.Head(h));
  const Vec3 pc = M.Position(M.Tail(HalfEdgeMesh::Prev(h))), pd = M.Position(M.Tail(HalfEdgeMesh::Prev(t)));
  const Vec3 mean = ((pb - pa).cross(pc - pa) + (pa - pb).cross(pd - pb)).normalized();
  const Vec3 n0 = (pa - pc).cross(pd - pc).normalized(), n1 = (pb - pd).cross(pc - pd).normalized();
  return after == 0 && n0.dot(mean) > 0.5 && n1.dot(mean) > 0.5;
}

Index Optimizer::VertexOnEdge(Index h) const
{
  const Vec3 a = M.Position(M.Tail(h)), b = M.Position(M.Head(h));
  for (const Index g : { HalfEdgeMesh::Prev(h), HalfEdgeMesh::Prev(M.Twin(h)) })
  {
    const Index c = M.Tail(g);
    const Vec3 ca = a - M.Position(c), cb = b - M.Position(c);
    if (ca.dot(cb) < -0.99985 * ca.norm() * cb.norm())
    {
      return c;
    }
  }
  return -1;
}

void Optimizer::Flip(Index h)
{
  const Index t = M.Twin(h);
  const Index a = M.Tail(h), b = M.Head(h), c = M.Tail(HalfEdgeMesh::Prev(h)), d = M.Tail(HalfEdgeMesh::Prev(t));
  if (Stitching && KeptEdges.count(EdgeKey(a, b)))
  {
    const Index through = VertexOnEdge(h);
    if (through >= 0)
    {
      KeptEdges.erase(EdgeKey(a, b));
      KeptEdges.insert(EdgeKey(a, through));
      KeptEdges.insert(EdgeKey(through, b));
      Moves[through] = Moves[through] == Free ? Fixed : Moves[through]; // (the line now runs through it)
    }
  }
  const double uv[4][2] = { { UVAt(h)[0], UVAt(h)[1] },
    { UVAt(HalfEdgeMesh::Next(h))[0], UVAt(HalfEdgeMesh::Next(h))[1] },
    { UVAt(HalfEdgeMesh::Prev(h))[0], UVAt(HalfEdgeMesh::Prev(h))[1] },
    { UVAt(HalfEdgeMesh::Prev(t))[0], UVAt(HalfEdgeMesh::Prev(t))[1] } };
  const Index g = 3 * (h / 3), k = 3 * (t / 3);
  M.FlipEdge(h); // faces (c, a, d) at g and (d, b, c) at k
  Recolour.insert(Recolour.end(), { a, b, c, d });
  const int order[6] = { 2, 0, 3, 3, 1, 2 };
  for (int i = 0; i < 6; ++i)
  {
    const Index corner = i < 3 ? g + i : k + i - 3;
    R.CornerUV[2 * corner] = uv[order[i]][0];
    R.CornerUV[2 * corner + 1] = uv[order[i]][1];
  }
  --Valence[a];
  --Valence[b];
  ++Valence[c];
  ++Valence[d];
}

/// The smaller area/perimeter^2 ratio of h's two faces (in 3D, or in the
/// metric) before and after the flip of h's edge.
std::pair<double, double> Optimizer::Roundnesses(Index h) const
{
  const auto [a, b, c, d] = Quad(h);
  return { std::min(Roundness(a, b, c), Roundness(b, a, d)), std::min(Roundness(c, a, d), Roundness(d, b, c)) };
}

/// With Active set: the edges with an active end, each once (the half of
/// smaller index, as the sweep takes it), ascending.
std::vector<Index> Optimizer::ActiveHalfEdges() const
{
  std::vector<Index> edges;
  for (Index v = 0; v < M.NumberOfVertices(); ++v)
  {
    if (Active[v])
    {
      M.ForEachOutgoing(v, [&](Index h) {
        for (const Index e : { h, HalfEdgeMesh::Prev(h) }) // (v's edges in h's face)
        {
          if (M.Twin(e) >= 0)
          {
            edges.push_back(std::min(e, M.Twin(e)));
          }
        }
      });
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

/// One sweep of swaps over the edges in order (each interior edge once, as
/// its half of smaller index): an edge is swapped where it is Swappable,
/// wanted(h) holds (a test of its two faces and their vertices' valences)
/// and then accept(h).  Swappable and wanted are evaluated for every edge
/// at once (in parallel; with Active set, for the edges with an active end)
/// on the mesh before the sweep, and again for an edge when its turn comes
/// if a swap of this sweep replaced one of its faces or changed a valence
/// there: the swaps of the plain serial sweep, for any thread count.  With
/// Active set, the sweep visits only the edges it may swap (those tested,
/// and those of the faces a swap changed, kept in a heap): the same swaps
/// as a sweep over all, where a fidelity round moved a few vertices (a
/// sweep over the 300,000 edges of a 100,000-vertex remesh took 6 ms,
/// three sweeps a round).
template <typename Wanted, typename Accept>
std::int64_t Optimizer::SwapWhere(Wanted&& wanted, Accept&& accept)
{
  const bool all = Active.empty();
  const std::vector<Index> listed = all ? std::vector<Index>() : ActiveHalfEdges();
  const std::int64_t count = all ? M.NumberOfHalfEdges() : static_cast<std::int64_t>(listed.size());
  std::vector<std::uint8_t> first(static_cast<std::size_t>(count), 0);
  ParallelFor(count, NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const Index h = all ? static_cast<Index>(i) : listed[i];
      first[i] = M.Twin(h) > h && (all || Active[M.Tail(h)] || Active[M.Head(h)]) && Swappable(h) && wanted(h);
    }
  }, {}, 0, 4096);
  // A swap changes its two faces and the valences of their four vertices:
  // every face around those is marked (an edge's two faces hold its quad).
  std::vector<std::uint8_t> changed(M.NumberOfFaces(), 0);
  std::priority_queue<Index, std::vector<Index>, std::greater<Index>> later; // (with Active: marked faces' edges)
  std::int64_t swaps = 0;
  const auto visit = [&](Index h, bool tested) {
    const Index t = M.Twin(h);
    const bool redo = t > h && (changed[h / 3] || changed[t / 3]);
    if (!(t > h && (tested || redo)) || !((redo ? Swappable(h) && wanted(h) : true) && accept(h)))
    {
      return;
    }
    const Index quad[4] = { M.Tail(h), M.Head(h), M.Tail(HalfEdgeMesh::Prev(h)), M.Tail(HalfEdgeMesh::Prev(t)) };
    Flip(h);
    for (const Index v : quad)
    {
      M.ForEachOutgoing(v, [&](Index g) {
        changed[g / 3] = 1;
        for (Index e = 3 * (g / 3); !all && e < 3 * (g / 3) + 3; ++e)
        {
          for (const Index x : { e, M.Twin(e) })
          {
            if (x > h)
            {
              later.push(x);
            }
          }
        }
      });
    }
    ++swaps;
  };
  if (all)
  {
    for (Index h = 0; h < count; ++h)
    {
      visit(h, first[h] != 0);
    }
    return swaps;
  }
  std::size_t i = 0;
  for (Index previous = -1; i < listed.size() || !later.empty();)
  {
    const bool fromList = i < listed.size() && (later.empty() || listed[i] <= later.top());
    const Index h = fromList ? listed[i] : later.top();
    const bool tested = fromList && first[i];
    fromList ? static_cast<void>(++i) : later.pop();
    if (h != previous)
    {
      visit(h, tested);
    }
    previous = h;
  }
  return swaps;
}

/// Swaps edges wherever that lowers the sum of squared deviations of the
/// four valences from their targets (section 4.4.2) without halving the
/// smaller area/perimeter^2 ratio of the two triangles (else the shape
/// swaps and these would undo each other round after round, and a sliver
/// could be left by the last one).
/// Target's boundary valences from the current triangles.  With 4 on every
/// boundary vertex, the corners of jagged rims (90 or 270 degrees) kept
/// their neighbours' valences off 6: elephant-with-holes at 10k 75.2% of
/// valence 6, now 78.6%.
void Optimizer::UpdateBoundaryTargets()
{
  BoundaryTarget.assign(M.NumberOfVertices(), 4);
  for (Index v = 0; v < M.NumberOfVertices(); ++v)
  {
    if (!M.IsBoundaryVertex(v))
    {
      continue;
    }
    double angle = 0.0;
    M.ForEachOutgoing(v, [&](Index h) {
      const Vec3 p = M.Position(v), a = M.Position(M.Head(h)), b = M.Position(M.Tail(HalfEdgeMesh::Prev(h)));
      angle += std::atan2((a - p).cross(b - p).norm(), (a - p).dot(b - p));
    });
    BoundaryTarget[v] = std::max(2, 1 + static_cast<int>(std::lround(angle * 3.0 / 3.141592653589793)));
  }
}

std::int64_t Optimizer::SwapForValence()
{
  UpdateBoundaryTargets();
  const auto fewerDeviations = [&](Index h) {
    const Index a = M.Tail(h), b = M.Head(h);
    const Index c = M.Tail(HalfEdgeMesh::Prev(h)), d = M.Tail(HalfEdgeMesh::Prev(M.Twin(h)));
    const auto dev = [&](Index v, int change) {
      const double x = Valence[v] + change - Target(v);
      return x * x;
    };
    return dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1) < dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
  };
  return SwapWhere(fewerDeviations, [&](Index h) {
    if (!CanSwap(h))
    {
      return false;
    }
    const auto [roundBefore, roundAfter] = Roundnesses(h);
    return roundAfter >= 0.5 * roundBefore;
  });
}

/// Swaps edges wherever that raises the smaller area/perimeter^2 ratio of
/// the two triangles (in 3D).
std::int64_t Optimizer::SwapForShape()
{
  const auto rounder = [&](Index h) {
    const auto [before, after] = Roundnesses(h);
    return after > before * 1.01;
  };
  return SwapWhere(rounder, [&](Index h) { return CanSwap(h); });
}

/// Swaps the edges of triangles with an angle below 30 degrees wherever
/// that raises the smaller area/perimeter^2 ratio: after the last
/// relaxation, which can leave such a triangle (a vertex slid along a
/// path) where a swap mends it, without undoing the valence swaps
/// elsewhere.
std::int64_t Optimizer::SwapSlivers()
{
  const double cos30 = 0.5 * std::sqrt(3.0);
  const auto mends = [&](Index h) {
    const auto [a, b, c, d] = Quad(h);
    if (std::max(LargestCosine(a, b, c), LargestCosine(b, a, d)) <= cos30)
    {
      return false;
    }
    const auto [before, after] = Roundnesses(h);
    return after > before * 1.01;
  };
  return SwapWhere(mends, [&](Index h) { return CanSwap(h); });
}

/// Swaps the edges of folded faces (Folded) wherever that folds fewer.
std::int64_t Optimizer::SwapFolds()
{
  return SwapWhere([&](Index h) { return FoldsOfFlip(h, false) > 0; }, [&](Index h) { return CanSwap(h); });
}

namespace
{

/// The smallest colour none of v's neighbours below v has (`colour`, -1
/// where none): the greedy colour of v in id order.
int LowestFreeColour(const HalfEdgeMesh& mesh, const std::vector<int>& colour, Index v)
{
  std::uint64_t taken = 0; // bit k: colour k taken by a neighbour (more than 64: first free beyond)
  std::vector<int> above; // neighbours' colours beyond 63 (rare)
  mesh.ForEachOutgoing(v, [&](Index h) {
    for (const Index x : { mesh.Head(h), mesh.Tail(HalfEdgeMesh::Prev(h)) }) // (the previous: boundary fans)
    {
      const int c = x < v ? colour[x] : -1;
      if (c >= 64)
      {
        above.push_back(c);
      }
      else if (c >= 0)
      {
        taken |= std::uint64_t(1) << c;
      }
    }
  });
  int c = 0;
  while (c < 64 && (taken >> c & 1))
  {
    ++c;
  }
  while (c >= 64 && std::find(above.begin(), above.end(), c) != above.end())
  {
    ++c;
  }
  return c;
}

} // namespace

/// The vertices by colour (greedy, in id order): no two neighbours share
/// one, so the moves of a colour touch disjoint faces and run in parallel
/// (Gauss-Seidel by colours: the same result for any thread count).  After
/// the first, only the vertices whose neighbours a swap changed
/// (Recolour) are coloured again, in id order, and those above them whose
/// neighbours below changed colour: each vertex's colour depends on its
/// neighbours below it only, so the colours are those of colouring all.
void Optimizer::ColourVertices()
{
  const Index n = M.NumberOfVertices();
  bool changed = Colour.size() != static_cast<std::size_t>(n);
  if (changed)
  {
    Colour.assign(n, -1);
    for (Index v = 0; v < n; ++v)
    {
      Colour[v] = LowestFreeColour(M, Colour, v);
    }
  }
  else
  {
    // (A mark per vertex, swept upwards: a vertex marks only those above it.)
    Pending.resize(n, 0);
    Index from = n;
    for (const Index v : Recolour)
    {
      Pending[v] = 1;
      from = std::min(from, v);
    }
    for (Index v = from; v < n; ++v)
    {
      v = static_cast<Index>(std::find(Pending.begin() + v, Pending.end(), std::uint8_t(1)) - Pending.begin());
      if (v == n)
      {
        break;
      }
      Pending[v] = 0;
      const int c = LowestFreeColour(M, Colour, v);
      if (c == Colour[v])
      {
        continue;
      }
      Colour[v] = c;
      changed = true;
      M.ForEachOutgoing(v, [&](Index h) {
        for (const Index x : { M.Head(h), M.Tail(HalfEdgeMesh::Prev(h)) })
        {
          Pending[x] = x > v ? 1 : Pending[x];
        }
      });
    }
  }
  Recolour.clear();
  if (!changed)
  {
    return;
  }
  const int colours = 1 + *std::max_element(Colour.begin(), Colour.end());
  ColourOffsets.assign(colours + 1, 0);
  for (Index v = 0; v < n; ++v)
  {
    ++ColourOffsets[Colour[v] + 1];
  }
  for (int c = 0; c < colours; ++c)
  {
    ColourOffsets[c + 1] += ColourOffsets[c];
  }
  ColourVerticesList.resize(n);
  std::vector<std::int64_t> next(ColourOffsets.begin(), ColourOffsets.end() - 1);
  for (Index v = 0; v < n; ++v)
  {
    ColourVerticesList[next[Colour[v]]++] = v;
  }
}

} // namespace beltrami::detail
