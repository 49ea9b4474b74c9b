#include "Mesh/SurfaceRepair.h"

#include "Mesh/Geometry.h"
#include "Mesh/MeshMeasures.h"
#include "Support/DisjointSets.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

namespace beltrami
{

namespace
{

/// The distance below which two boundary points count as one: a small
/// fraction of the extent, or a few units in the last place of the
/// coordinates' type (float data computed in float).
template <typename T>
double CoincidenceTolerance(const MeshTopology& topology, const T* points)
{
  const Eigen::AlignedBox3d box = UsedPointsBox(topology, points);
  if (box.isEmpty())
  {
    return 0.0;
  }
  const double largest = std::max(box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff());
  return std::max(NearlyCoincident * box.diagonal().norm(),
    8.0 * static_cast<double>(std::numeric_limits<T>::epsilon()) * largest);
}

} // namespace

template <typename T>
std::vector<Index> CoincidentBoundaryPoints(const MeshTopology& topology, const T* points, Index& merged)
{
  merged = 0;
  const auto at = [points](Index v) {
    const T* x = points + 3 * static_cast<std::size_t>(v);
    return Vec3(x[0], x[1], x[2]);
  };
  const double tolerance = CoincidenceTolerance(topology, points);
  // The boundary points in cells of the tolerance's size: near points are in
  // the same cell or a neighbouring one.
  using Cell = std::array<std::int64_t, 3>;
  std::map<Cell, std::vector<Index>> cells;
  const auto cellOf = [tolerance](const Vec3& x) {
    return Cell{ static_cast<std::int64_t>(std::floor(x[0] / tolerance)),
      static_cast<std::int64_t>(std::floor(x[1] / tolerance)), static_cast<std::int64_t>(std::floor(x[2] / tolerance)) };
  };
  const bool finiteCells = tolerance > 0.0 && std::isfinite(tolerance);
  for (Index v = 0; finiteCells && v < topology.NumberOfVertices(); ++v)
  {
    if ((topology.VertexFlags(v) & VertexBoundary) != 0 && at(v).allFinite() &&
      (at(v).cwiseAbs().array() / tolerance < 1e15).all())
    {
      cells[cellOf(at(v))].push_back(v);
    }
  }
  // Near points joined (union-find, the lowest id the root).
  std::vector<Index> merge(static_cast<std::size_t>(topology.NumberOfVertices()));
  std::iota(merge.begin(), merge.end(), Index(0));
  for (const auto& [cell, members] : cells)
  {
    for (const Index v : members)
    {
      for (int n = 0; n < 27; ++n)
      {
        const Cell near{ cell[0] + n % 3 - 1, cell[1] + n / 3 % 3 - 1, cell[2] + n / 9 - 1 };
        const auto found = cells.find(near);
        for (const Index w : found == cells.end() ? std::vector<Index>() : found->second)
        {
          if (w > v && (at(v) - at(w)).norm() <= tolerance)
          {
            const Index a = FindRoot(merge, v), b = FindRoot(merge, w);
            merge[std::max(a, b)] = std::min(a, b);
          }
        }
      }
    }
  }
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    merge[v] = FindRoot(merge, v);
    merged += merge[v] != v;
  }
  return merged ? merge : std::vector<Index>();
}

template std::vector<Index> CoincidentBoundaryPoints<float>(const MeshTopology&, const float*, Index&);
template std::vector<Index> CoincidentBoundaryPoints<double>(const MeshTopology&, const double*, Index&);

namespace
{

/// Whether the ends a and b of edge e (of two triangles) share no neighbour
/// but the two vertices opposite it.
bool LinkConditionHolds(const MeshTopology& topology, std::int64_t e, Index a, Index b)
{
  const MeshTopology::EdgeTable& edges = topology.Edges();
  const Index opposite[2] = { topology.CornerVertex(edges.OppositeCorners[2 * e]),
    topology.CornerVertex(edges.OppositeCorners[2 * e + 1]) };
  const Index* na = edges.Neighbors.data() + edges.NeighborOffsets[a];
  const Index* ea = edges.Neighbors.data() + edges.NeighborOffsets[a + 1];
  const Index* nb = edges.Neighbors.data() + edges.NeighborOffsets[b];
  const Index* eb = edges.Neighbors.data() + edges.NeighborOffsets[b + 1];
  int common = 0;
  while (na != ea && nb != eb) // (the rings are ascending)
  {
    if (*na < *nb)
    {
      ++na;
    }
    else if (*nb < *na)
    {
      ++nb;
    }
    else
    {
      if (*na != opposite[0] && *na != opposite[1])
      {
        return false;
      }
      ++common;
      ++na;
      ++nb;
    }
  }
  return common == 2 && opposite[0] != opposite[1];
}

} // namespace

template <typename T>
std::vector<Index> CollapsedEdges(const MeshTopology& topology, const T* points, Index& merged)
{
  merged = 0;
  const double tolerance = CoincidenceTolerance(topology, points);
  const MeshTopology::EdgeTable& edges = topology.Edges();
  std::vector<Index> merge(static_cast<std::size_t>(topology.NumberOfVertices()));
  std::iota(merge.begin(), merge.end(), Index(0));
  std::vector<std::uint8_t> taken(merge.size(), 0);
  const std::uint8_t topological = VertexBoundary | VertexNonManifold | VertexInconsistent | VertexDuplicateFace;
  for (std::int64_t e = 0; tolerance > 0.0 && std::isfinite(tolerance) && e < edges.NumberOfEdges(); ++e)
  {
    const Index a = edges.Vertices[2 * e], b = edges.Vertices[2 * e + 1];
    const T* x = points + 3 * static_cast<std::size_t>(a);
    const T* y = points + 3 * static_cast<std::size_t>(b);
    const Vec3 d(static_cast<double>(x[0]) - y[0], static_cast<double>(x[1]) - y[1], static_cast<double>(x[2]) - y[2]);
    const bool interior = ((topology.VertexFlags(a) | topology.VertexFlags(b)) & topological) == 0;
    if (!(d.norm() <= tolerance) || taken[a] || taken[b] || !interior || edges.FaceCount[e] != 2 ||
      !LinkConditionHolds(topology, e, a, b))
    {
      continue;
    }
    taken[a] = taken[b] = 1;
    merge[b] = a; // (a < b)
    ++merged;
  }
  return merged ? merge : std::vector<Index>();
}

template std::vector<Index> CollapsedEdges<float>(const MeshTopology&, const float*, Index&);
template std::vector<Index> CollapsedEdges<double>(const MeshTopology&, const double*, Index&);

IndexArray MergePoints(const IndexArray& triangles, const std::vector<Index>& merge)
{
  IndexArray merged(triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k)
  {
    merged[k] = merge[triangles[k]];
  }
  return merged;
}

std::vector<Index> SplitPinchedVertices(const MeshTopology& topology, IndexArray& triangles, Index& cutEdges)
{
  triangles = topology.TriangleList();
  cutEdges = 0;
  std::vector<Index> copied;
  std::vector<Index> fan; // per incident corner of one vertex: union-find over the corners
  std::vector<std::pair<Index, Index>> neighbours; // (ring vertex, corner position)
  for (Index v = 0; v < topology.NumberOfVertices(); ++v)
  {
    if (!(topology.VertexFlags(v) & VertexNonManifold))
    {
      continue;
    }
    const Index valence = topology.Valence(v);
    const Index* pairs = topology.RingPairsBegin(v);
    fan.resize(static_cast<std::size_t>(valence));
    std::iota(fan.begin(), fan.end(), Index(0));
    neighbours.clear();
    for (Index k = 0; k < valence; ++k)
    {
      neighbours.emplace_back(pairs[2 * k], k);
      neighbours.emplace_back(pairs[2 * k + 1], k);
    }
    // Two corners that share a ring vertex share the edge to it: one fan,
    // unless more triangles share it (the edge is cut).
    std::sort(neighbours.begin(), neighbours.end());
    for (std::size_t i = 0, j = 0; i < neighbours.size(); i = j)
    {
      while (j < neighbours.size() && neighbours[j].first == neighbours[i].first)
      {
        ++j;
      }
      if (j - i == 2)
      {
        fan[FindRoot(fan, neighbours[i + 1].second)] = FindRoot(fan, neighbours[i].second);
      }
      else if (j - i > 2 && v < neighbours[i].first)
      {
        ++cutEdges;
      }
    }
    // The fan of the first corner keeps v; each other fan takes a new vertex.
    std::vector<std::pair<Index, Index>> vertexOfFan; // (root, vertex)
    for (Index k = 0; k < valence; ++k)
    {
      const Index root = FindRoot(fan, k);
      auto at = std::find_if(vertexOfFan.begin(), vertexOfFan.end(), [root](const auto& f) { return f.first == root; });
      if (at == vertexOfFan.end())
      {
        const Index id = vertexOfFan.empty() ? v : topology.NumberOfVertices() + static_cast<Index>(copied.size());
        if (id != v)
        {
          copied.push_back(v);
        }
        vertexOfFan.emplace_back(root, id);
        at = vertexOfFan.end() - 1;
      }
      triangles[topology.CornersBegin(v)[k]] = at->second;
    }
  }
  return copied;
}

std::vector<Index> RepeatedTriangles(const IndexArray& triangles)
{
  const std::size_t n = triangles.size() / 3;
  std::vector<std::pair<std::array<Index, 3>, Index>> sorted(n);
  for (std::size_t t = 0; t < n; ++t)
  {
    std::array<Index, 3> v{ triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2] };
    std::sort(v.begin(), v.end());
    sorted[t] = { v, static_cast<Index>(t) };
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<Index> repeated;
  for (std::size_t k = 1; k < n; ++k)
  {
    if (sorted[k].first == sorted[k - 1].first)
    {
      repeated.push_back(sorted[k].second); // (sorted by index within equal triples: the first one stays)
    }
  }
  std::sort(repeated.begin(), repeated.end());
  return repeated;
}

namespace
{

/// Union-find over the triangles that also keeps, for every triangle, whether
/// its orientation is opposite to that of its set's root.
class OrientationSets
{
public:
  explicit OrientationSets(Index n)
    : Parent(n)
    , Parity(n, 0)
    , Broken(n, 0)
    , Open(n, 0)
  {
    std::iota(Parent.begin(), Parent.end(), Index(0));
  }
  /// The root of t; `parity` gets t's orientation relative to it (1: opposite).
  Index Find(Index t, std::uint8_t& parity)
  {
    parity = 0;
    Index root = t;
    while (Parent[root] != root)
    {
      parity ^= Parity[root];
      root = Parent[root];
    }
    // Path compression: every triangle on the way points at the root.
    std::uint8_t p = parity;
    while (Parent[t] != root)
    {
      const Index next = Parent[t];
      const std::uint8_t step = Parity[t];
      Parent[t] = root;
      Parity[t] = p;
      p ^= step;
      t = next;
    }
    return root;
  }
  /// Joins a and b, whose orientations must differ when `opposite`.
  void Join(Index a, Index b, std::uint8_t opposite)
  {
    std::uint8_t pa, pb;
    const Index ra = Find(a, pa), rb = Find(b, pb);
    if (ra == rb)
    {
      Broken[ra] |= static_cast<std::uint8_t>((pa ^ pb) != opposite);
      return;
    }
    Parent[rb] = ra;
    Parity[rb] = pa ^ pb ^ opposite;
    Broken[ra] |= Broken[rb];
    Open[ra] |= Open[rb];
  }
  void MarkOpen(Index t)
  {
    std::uint8_t p;
    Open[Find(t, p)] = 1;
  }
  bool IsBroken(Index root) const { return Broken[root] != 0; }
  bool IsOpen(Index root) const { return Open[root] != 0; }

private:
  std::vector<Index> Parent;
  std::vector<std::uint8_t> Parity, Broken, Open;
};

} // namespace

OrientationRepair OrientConsistently(const MeshTopology& topology, const double* points, IndexArray& triangles)
{
  triangles = topology.TriangleList();
  OrientationRepair repair;
  const Index n = topology.NumberOfTriangles();
  const MeshTopology::EdgeTable& edges = topology.Edges();
  OrientationSets sets(n);
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c1 = edges.OppositeCorners[2 * e], c2 = edges.OppositeCorners[2 * e + 1];
    if (edges.FaceCount[e] != 2)
    {
      sets.MarkOpen(c1 / 3); // a boundary or non-manifold edge: no enclosed volume
      continue;
    }
    // Agreeing neighbours run along their common edge in opposite directions.
    const bool agree =
      topology.CornerVertex(MeshTopology::Next(c1)) == topology.CornerVertex(MeshTopology::Prev(c2));
    sets.Join(c1 / 3, c2 / 3, agree ? 0 : 1);
  }
  // Per root: triangles agreeing with it, disagreeing, and the enclosed volume
  // as they would be turned to agree with it.
  std::vector<std::uint8_t> parity(n);
  std::vector<Index> root(n);
  std::vector<Index> same(n, 0), opposite(n, 0);
  std::vector<double> volume(n, 0.0);
  for (Index t = 0; t < n; ++t)
  {
    root[t] = sets.Find(t, parity[t]);
    ++(parity[t] ? opposite : same)[root[t]];
    if (points && !sets.IsOpen(root[t]) && !sets.IsBroken(root[t]))
    {
      const Vec3 o = Point(points, triangles[3 * static_cast<std::size_t>(root[t])]);
      const Index* v = triangles.data() + 3 * static_cast<std::size_t>(t);
      const double six = (Point(points, v[0]) - o).dot((Point(points, v[1]) - o).cross(Point(points, v[2]) - o));
      volume[root[t]] += parity[t] ? -six : six;
    }
  }
  for (Index t = 0; t < n; ++t)
  {
    const Index r = root[t];
    if (sets.IsBroken(r))
    {
      repair.NonOrientableComponents += r == t;
      continue;
    }
    if (opposite[r] == 0)
    {
      continue; // a component that was consistent already stays as it is
    }
    // The root's orientation is kept when it faces out (closed) or is the majority's.
    const bool closedByVolume = points && !sets.IsOpen(r) && volume[r] != 0.0;
    const bool keepRoot = closedByVolume ? volume[r] > 0.0 : same[r] >= opposite[r];
    if (parity[t] == (keepRoot ? 1 : 0))
    {
      std::swap(triangles[3 * static_cast<std::size_t>(t) + 1], triangles[3 * static_cast<std::size_t>(t) + 2]);
      ++repair.FlippedTriangles;
    }
  }
  return repair;
}

} // namespace beltrami
