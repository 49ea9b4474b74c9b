#include "Mesh/HalfEdgeMesh.h"

#include <algorithm>

namespace beltrami
{

bool HalfEdgeMesh::FromTopology(
  const MeshTopology& topology, const double* points, HalfEdgeMesh& mesh, std::string& error)
{
  const TopologySummary& s = topology.Summary();
  if (!s.IsManifold() || !s.IsOriented())
  {
    error = "an editable mesh needs a manifold, consistently oriented surface; the input is: " + topology.Describe();
    return false;
  }
  const Index n = topology.NumberOfVertices();
  const IndexArray& triangles = topology.TriangleList();
  mesh.Tri.assign(triangles.begin(), triangles.end());
  mesh.Opposite.assign(mesh.Tri.size(), -1);
  mesh.VertexEdge.assign(n, -1);
  mesh.Positions.assign(points, points + 3 * static_cast<std::size_t>(n));
  // The half-edge opposite corner c is Next(c); an edge's two opposite
  // corners give the twins.
  const MeshTopology::EdgeTable& edges = topology.Edges();
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
    if (c0 >= 0 && c1 >= 0)
    {
      mesh.Opposite[Next(c0)] = Next(c1);
      mesh.Opposite[Next(c1)] = Next(c0);
    }
  }
  for (Index h = 0; h < mesh.NumberOfHalfEdges(); ++h)
  {
    if (mesh.VertexEdge[mesh.Tri[h]] < 0)
    {
      mesh.AnchorVertex(mesh.Tri[h], h);
    }
  }
  return true;
}

void HalfEdgeMesh::AnchorVertex(Index v, Index outgoing)
{
  // Clockwise: the outgoing half-edge before h is Next(Twin(h)).
  Index h = outgoing;
  for (Index left = NumberOfHalfEdges(); Opposite[h] >= 0 && left > 0; --left)
  {
    const Index before = Next(Opposite[h]);
    if (before == outgoing)
    {
      break; // interior: all the way round
    }
    h = before;
  }
  VertexEdge[v] = Opposite[h] < 0 ? h : outgoing;
}

Index HalfEdgeMesh::FindHalfEdge(Index a, Index b) const
{
  Index found = -1;
  ForEachOutgoing(a, [&](Index h) {
    if (found < 0 && Head(h) == b)
    {
      found = h;
    }
  });
  return found;
}

Index HalfEdgeMesh::Valence(Index v) const
{
  Index count = 0;
  ForEachOutgoing(v, [&](Index) { ++count; });
  return count + (IsBoundaryVertex(v) ? 1 : 0); // a boundary fan has one more neighbour than edges out
}

void HalfEdgeMesh::SetPosition(Index v, const Vec3& p)
{
  for (int d = 0; d < 3; ++d)
  {
    Positions[3 * static_cast<std::size_t>(v) + d] = p[d];
  }
}

bool HalfEdgeMesh::CanFlip(Index h) const
{
  if (h < 0 || h >= NumberOfHalfEdges() || IsBoundary(h))
  {
    return false;
  }
  // (Both ways: where c-d is an edge of the boundary, only one of its
  // half-edges exists, and the flip would make it an edge of three faces.)
  const Index c = Tri[Prev(h)], d = Tri[Prev(Opposite[h])];
  return c != d && FindHalfEdge(c, d) < 0 && FindHalfEdge(d, c) < 0;
}

bool HalfEdgeMesh::FlipEdge(Index h)
{
  if (!CanFlip(h))
  {
    return false;
  }
  const Index t = Opposite[h];
  const Index f0 = Face(h), f1 = Face(t);
  const Index a = Tail(h), b = Head(h), c = Tri[Prev(h)], d = Tri[Prev(t)];
  // The four outer twins: of c->a, b->c (face f0) and a->d, d->b (face f1).
  const Index ca = Opposite[Prev(h)], bc = Opposite[Next(h)];
  const Index ad = Opposite[Next(t)], db = Opposite[Prev(t)];
  // New faces (c, a, d) and (d, b, c): half-edges c->a, a->d, d->c and d->b, b->c, c->d.
  const Index g = 3 * f0, k = 3 * f1;
  Tri[g] = c;
  Tri[g + 1] = a;
  Tri[g + 2] = d;
  Tri[k] = d;
  Tri[k + 1] = b;
  Tri[k + 2] = c;
  const auto link = [&](Index x, Index y) {
    Opposite[x] = y;
    if (y >= 0)
    {
      Opposite[y] = x;
    }
  };
  link(g, ca);
  link(g + 1, ad);
  link(g + 2, k + 2);
  link(k, db);
  link(k + 1, bc);
  AnchorVertex(a, g + 1);
  AnchorVertex(b, k + 1);
  AnchorVertex(c, g);
  AnchorVertex(d, k);
  return true;
}

MeshTopology HalfEdgeMesh::ToTopology(int numThreads) const
{
  return MeshTopology(NumberOfVertices(), IndexArray(Tri.begin(), Tri.end()), numThreads);
}

bool HalfEdgeMesh::ExtractFaces(const std::vector<std::uint8_t>& keep, HalfEdgeMesh& part,
  std::vector<Index>& vertexMap, std::string& error) const
{
  std::vector<Index> newId(NumberOfVertices(), -1);
  for (Index f = 0; f < NumberOfFaces(); ++f)
  {
    if (keep[f])
    {
      for (int k = 0; k < 3; ++k)
      {
        newId[Tri[3 * f + k]] = 0;
      }
    }
  }
  vertexMap.clear();
  for (Index v = 0; v < NumberOfVertices(); ++v)
  {
    if (newId[v] == 0)
    {
      newId[v] = static_cast<Index>(vertexMap.size());
      vertexMap.push_back(v);
    }
  }
  IndexArray triangles;
  std::vector<double> points(3 * vertexMap.size());
  for (Index f = 0; f < NumberOfFaces(); ++f)
  {
    if (keep[f])
    {
      triangles.insert(triangles.end(), { newId[Tri[3 * f]], newId[Tri[3 * f + 1]], newId[Tri[3 * f + 2]] });
    }
  }
  for (std::size_t k = 0; k < vertexMap.size(); ++k)
  {
    std::copy(&Positions[3 * vertexMap[k]], &Positions[3 * vertexMap[k]] + 3, &points[3 * k]);
  }
  const MeshTopology topology(static_cast<Index>(vertexMap.size()), std::move(triangles));
  return FromTopology(topology, points.data(), part, error);
}

std::string HalfEdgeMesh::CheckConsistency() const
{
  for (Index h = 0; h < NumberOfHalfEdges(); ++h)
  {
    const Index t = Opposite[h];
    if (t >= 0 && (Opposite[t] != h || Tail(t) != Head(h) || Head(t) != Tail(h)))
    {
      return "half-edge " + std::to_string(h) + " and its twin disagree";
    }
  }
  for (Index v = 0; v < NumberOfVertices(); ++v)
  {
    const Index h = VertexEdge[v];
    if (h >= 0 && Tail(h) != v)
    {
      return "the outgoing half-edge of vertex " + std::to_string(v) + " does not start there";
    }
    // The fan closes (interior) or ends on the boundary within its faces.
    Index steps = 0, e = h;
    while (e >= 0 && steps <= NumberOfHalfEdges())
    {
      if (Tail(e) != v)
      {
        return "the fan of vertex " + std::to_string(v) + " leaves the vertex";
      }
      ++steps;
      e = RotateCounterClockwise(e);
      if (e == h)
      {
        break;
      }
    }
    if (steps > NumberOfHalfEdges())
    {
      return "the fan of vertex " + std::to_string(v) + " does not close";
    }
    if (h >= 0 && !IsBoundary(h))
    {
      // An interior anchor: turning clockwise must come back to it without
      // meeting the boundary.
      Index back = h;
      Index left = NumberOfHalfEdges();
      do
      {
        back = Opposite[back] >= 0 ? Next(Opposite[back]) : -1;
      } while (back >= 0 && back != h && left-- > 0);
      if (back < 0)
      {
        return "boundary vertex " + std::to_string(v) + " is anchored at an interior half-edge";
      }
    }
  }
  return {};
}

} // namespace beltrami
