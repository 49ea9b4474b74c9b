#include "Mesh/VectorFieldsDetail.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>

namespace beltrami::detail
{

bool NoHarmonicFields(const MeshTopology& topo, const std::vector<Index>& component, Index degenerate)
{
  const TopologySummary& s = topo.Summary();
  if (!s.IsManifold() || !s.IsOriented() || degenerate > 0)
  {
    return false;
  }
  const MeshTopology::EdgeTable& edges = topo.Edges();
  std::vector<std::int64_t> euler(component.size(), 0); // by component id
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    euler[component[v]] += topo.Valence(v) > 0;
  }
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    --euler[component[edges.Vertices[2 * e]]];
  }
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    ++euler[component[topo.TriangleList()[3 * static_cast<std::int64_t>(t)]]];
  }
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (component[v] == v && topo.Valence(v) > 0 && euler[v] != 2 && euler[v] != 1)
    {
      return false;
    }
  }
  return true;
}

bool ClosedWithoutDegenerateTriangles(const MeshTopology& topo, Index degenerate)
{
  const TopologySummary& s = topo.Summary();
  return s.IsClosed() && s.IsManifold() && s.IsOriented() && degenerate == 0;
}

std::vector<double> IntegrateStreamFunction(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, VectorFieldBoundary boundary, const std::vector<double>& rest)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const Index nt = topo.NumberOfTriangles();
  std::vector<double> v(static_cast<std::size_t>(edges.NumberOfEdges()), 0.0);
  std::vector<std::uint8_t> known(v.size(), 0), visited(nt, 0);
  const auto midpoint = [&](Index c) -> Vec3 { // (a Vec3, not an expression of temporaries)
    return 0.5 * (Point(points, tri[MeshTopology::Next(c)]) + Point(points, tri[MeshTopology::Prev(c)]));
  };
  const auto onBoundary = [&](Index e) { return edges.FaceCount[e] == 1; };
  std::vector<Index> queue, members;
  // One component from triangle `start`, v known at its edge `first`.
  const auto integrate = [&](Index start, Index first, bool fixed) {
    known[first] = 1;
    visited[start] = 1;
    queue.assign(1, start);
    members.assign(1, first);
    for (std::size_t q = 0; q < queue.size(); ++q)
    {
      const std::int64_t t = queue[q];
      const Vec3 n(&f.Normals[3 * t]);
      const Vec3 gradient = -n.cross(Vec3(&rest[3 * t]));
      Index from = static_cast<Index>(3 * t);
      while (!known[graph.TriangleEdges[from]])
      {
        ++from;
      }
      for (Index c = static_cast<Index>(3 * t); c < 3 * t + 3; ++c)
      {
        const Index e = graph.TriangleEdges[c];
        if (!known[e])
        {
          v[e] = v[graph.TriangleEdges[from]] + gradient.dot(midpoint(c) - midpoint(from));
          known[e] = 1;
          members.push_back(e);
        }
        for (int s = 0; s < 2; ++s)
        {
          const Index corner = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + s];
          if (corner >= 0 && !visited[corner / 3])
          {
            visited[corner / 3] = 1;
            queue.push_back(corner / 3);
          }
        }
      }
    }
    double sum = 0.0, mass = 0.0; // over the component (the lumped mass: a third of each triangle per edge)
    for (const Index t : queue)
    {
      for (Index c = 3 * t; c < 3 * t + 3; ++c)
      {
        sum += f.Areas[t] / 3.0 * v[graph.TriangleEdges[c]];
        mass += f.Areas[t] / 3.0;
      }
    }
    for (const Index e : members)
    {
      v[e] = fixed ? (onBoundary(e) ? 0.0 : v[e]) : v[e] - sum / mass;
    }
  };
  for (Index t = 0; boundary == VectorFieldBoundary::TangentDivergenceFree && t < nt; ++t)
  {
    for (Index c = 3 * t; c < 3 * t + 3 && !visited[t]; ++c)
    {
      if (onBoundary(graph.TriangleEdges[c]))
      {
        integrate(t, graph.TriangleEdges[c], true);
      }
    }
  }
  for (Index t = 0; t < nt; ++t)
  {
    if (!visited[t])
    {
      integrate(t, graph.TriangleEdges[3 * static_cast<std::int64_t>(t)], false);
    }
  }
  return v;
}

namespace
{

/// The edges of a spanning forest of the surface's vertices (breadth first).
std::vector<std::uint8_t> VertexForest(const MeshTopology& topo)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  std::vector<std::uint8_t> inForest(static_cast<std::size_t>(edges.NumberOfEdges()), 0);
  std::vector<std::uint8_t> reached(static_cast<std::size_t>(topo.NumberOfVertices()), 0);
  std::vector<Index> queue;
  for (Index root = 0; root < topo.NumberOfVertices(); ++root)
  {
    if (reached[root])
    {
      continue;
    }
    reached[root] = 1;
    queue.assign(1, root);
    for (std::size_t q = 0; q < queue.size(); ++q)
    {
      const Index v = queue[q];
      for (std::int64_t k = edges.NeighborOffsets[v]; k < edges.NeighborOffsets[v + 1]; ++k)
      {
        const std::int64_t e = edges.NeighborEdges[k];
        const Index w = edges.Vertices[2 * e] == v ? edges.Vertices[2 * e + 1] : edges.Vertices[2 * e];
        if (!reached[w])
        {
          reached[w] = 1;
          inForest[e] = 1;
          queue.push_back(w);
        }
      }
    }
  }
  return inForest;
}

/// +1 where the edge opposite corner c runs along its triangle's
/// orientation (from the next corner to the one before), else -1.
double Along(const MeshTopology& topo, const EdgeGraph& graph, Index c)
{
  const std::int64_t e = graph.TriangleEdges[c];
  return topo.Edges().Vertices[2 * e] == topo.TriangleList()[MeshTopology::Next(c)] ? 1.0 : -1.0;
}

} // namespace

std::vector<std::vector<double>> HandleFields(const MeshTopology& topo, const double* points,
  const TriangleFrames& f, const EdgeGraph& graph, std::size_t most)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index nt = topo.NumberOfTriangles();
  std::vector<std::uint8_t> used = VertexForest(topo); // then also the triangles' forest
  // The triangles' forest across the other edges: each triangle's corner
  // opposite its edge to its parent (-1 at a root), in breadth-first order.
  std::vector<Index> parent(nt, -1), order;
  std::vector<std::uint8_t> seen(nt, 0);
  order.reserve(nt);
  for (Index root = 0; root < nt; ++root)
  {
    if (seen[root])
    {
      continue;
    }
    seen[root] = 1;
    const std::size_t first = order.size();
    order.push_back(root);
    for (std::size_t q = first; q < order.size(); ++q)
    {
      const Index t = order[q];
      for (Index c = 3 * t; c < 3 * t + 3; ++c)
      {
        const Index e = graph.TriangleEdges[c];
        const Index a = edges.OppositeCorners[2 * static_cast<std::int64_t>(e)];
        const Index corner = a == c ? edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + 1] : a; // across e
        if (!used[e] && !seen[corner / 3])
        {
          seen[corner / 3] = 1;
          used[e] = 1;
          parent[corner / 3] = corner;
          order.push_back(corner / 3);
        }
      }
    }
  }
  std::vector<Index> left;
  for (Index e = 0; e < static_cast<Index>(used.size()); ++e)
  {
    if (!used[e])
    {
      left.push_back(e);
    }
  }
  std::vector<std::vector<double>> fields;
  if (left.size() > most)
  {
    return fields;
  }
  const IndexArray& tri = topo.TriangleList();
  std::vector<double> form(used.size());
  for (const Index generator : left)
  {
    std::fill(form.begin(), form.end(), 0.0);
    form[generator] = 1.0;
    for (auto t = order.rbegin(); t != order.rend(); ++t) // leaves first: the edge to the parent is the unknown
    {
      if (parent[*t] < 0)
      {
        continue;
      }
      const Index up = parent[*t]; // the corner of *t opposite that edge
      double sum = 0.0;
      for (Index c = 3 * *t; c < 3 * *t + 3; ++c)
      {
        sum += c == up ? 0.0 : Along(topo, graph, c) * form[graph.TriangleEdges[c]];
      }
      form[graph.TriangleEdges[up]] = -sum * Along(topo, graph, up);
    }
    std::vector<double>& field = fields.emplace_back(3 * static_cast<std::size_t>(nt), 0.0);
    for (Index t = 0; t < nt; ++t)
    {
      const Index c = 3 * t;
      // The linear function's values at the corners: 0 at c, then along the sides.
      const double at[3] = { 0.0, Along(topo, graph, c + 2) * form[graph.TriangleEdges[c + 2]],
        Along(topo, graph, c + 2) * form[graph.TriangleEdges[c + 2]] +
          Along(topo, graph, c) * form[graph.TriangleEdges[c]] };
      if (f.Areas[t] > 0.0)
      {
        Vec3 gradient = Vec3::Zero();
        for (int k = 0; k < 3; ++k)
        {
          gradient += at[k] * Vec3(&f.Normals[3 * static_cast<std::size_t>(t)]).cross(Side(points, tri, c + k));
        }
        Store(&field[3 * static_cast<std::size_t>(t)], gradient / (2.0 * f.Areas[t]));
      }
    }
  }
  return fields;
}

} // namespace beltrami::detail
