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

std::vector<Index> IntegrateAcross(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, const std::vector<double>& rest, Index start, Index first, std::vector<double>& v,
  std::vector<std::uint8_t>& known, std::vector<std::uint8_t>& visited, std::vector<Index>* triangles)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const auto midpoint = [&](Index c) -> Vec3 { // (a Vec3, not an expression of temporaries)
    return 0.5 * (Point(points, tri[MeshTopology::Next(c)]) + Point(points, tri[MeshTopology::Prev(c)]));
  };
  known[first] = 1;
  visited[start] = 1;
  std::vector<Index> queue(1, start), members(1, first);
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
  if (triangles)
  {
    triangles->swap(queue);
  }
  return members;
}

std::vector<double> IntegrateStreamFunction(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, VectorFieldBoundary boundary, const std::vector<double>& rest)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index nt = topo.NumberOfTriangles();
  std::vector<double> v(static_cast<std::size_t>(edges.NumberOfEdges()), 0.0);
  std::vector<std::uint8_t> known(v.size(), 0), visited(nt, 0);
  const auto onBoundary = [&](Index e) { return edges.FaceCount[e] == 1; };
  std::vector<Index> queue;
  // One component from triangle `start`, v known at its edge `first`.
  const auto integrate = [&](Index start, Index first, bool fixed) {
    const std::vector<Index> members = IntegrateAcross(topo, points, f, graph, rest, start, first, v, known, visited, &queue);
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

} // namespace beltrami::detail
