#include "Mesh/Laplacian.h"

#include "Mesh/RingGeometry.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

namespace beltrami
{

void GraphLaplacian::ApplyStiffness(const double* x, double* y, int columns, int numThreads) const
{
  ApplyGraphStiffness(
    NumberOfVertices, Offsets, Neighbors, Weights.data(), Diagonal.data(), x, y, columns, numThreads);
}

namespace
{

void Resize(GraphLaplacian& l, Index n, const std::int64_t* offsets, const Index* neighbors)
{
  l.NumberOfVertices = n;
  l.Offsets = offsets;
  l.Neighbors = neighbors;
  l.Weights.assign(static_cast<std::size_t>(offsets[n]), 0.0);
  l.Diagonal.assign(n, 0.0);
  l.Mass.assign(n, 0.0);
  l.DegenerateTriangles = 0;
}

/// Umbrella / inverse-length weights for a vertex and its neighbours.
template <int N>
void EdgeLengthWeights(GraphLaplacian& l, const double* points, LaplacianWeights weights, Index i)
{
  const VecN<N> xi = LoadPoint<N>(points, N, i);
  double diag = 0.0, mass = 0.0;
  for (std::int64_t k = l.Offsets[i]; k < l.Offsets[i + 1]; ++k)
  {
    double c = 1.0;
    if (weights == LaplacianWeights::Umbrella)
    {
      mass += 1.0;
    }
    else
    {
      const double length = (LoadPoint<N>(points, N, l.Neighbors[k]) - xi).norm();
      c = length > 0.0 ? 1.0 / length : 0.0; // coincident points: no coupling
      mass += 0.5 * length;
    }
    l.Weights[k] = c;
    diag += c;
  }
  l.Diagonal[i] = diag;
  l.Mass[i] = weights == LaplacianWeights::Umbrella ? mass : (std::isfinite(mass) ? mass : 0.0);
}

template <int N>
void AssembleSurface(const MeshTopology& topo, const double* points,
  LaplacianWeights weights, GraphLaplacian& l, int numThreads)
{
  const MeshTopology::VertexGraph& edges = topo.Graph();
  const Index n = topo.NumberOfVertices();
  Resize(l, n, edges.NeighborOffsets.data(), edges.Neighbors.data());
  std::atomic<Index> degenerate{ 0 };
  ParallelFor(n, numThreads, [&](std::int64_t begin, std::int64_t end) {
    Index nDegenerate = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      if (weights == LaplacianWeights::Umbrella || weights == LaplacianWeights::InverseEdgeLength)
      {
        EdgeLengthWeights<N>(l, points, weights, i);
        continue;
      }
      const std::int64_t first = l.Offsets[i], last = l.Offsets[i + 1];
      const auto entry = [&](Index j) {
        return std::lower_bound(l.Neighbors + first, l.Neighbors + last, j) - l.Neighbors;
      };
      PrefetchRing(topo, points, N, i);
      const VecN<N> xi = LoadPoint<N>(points, N, i);
      double mass = 0.0;
      ForEachRingCorner<N>(topo, points, N, i, xi, [&](const CornerGeometry<N>& g) {
        if (g.Degenerate)
        {
          nDegenerate += g.Corner % 3 == 0; // each triangle counted once
          return;
        }
        if (weights == LaplacianWeights::Authalic)
        {
          // Eq. 5.6: the angle at x_j weighs edge (i, j), the angle at x_k edge (i, k).
          l.Weights[entry(g.J)] += g.CotJ / g.AA;
          l.Weights[entry(g.K)] += g.CotK / g.BB;
          return;
        }
        // Edge (i, j) is opposite x_k, edge (i, k) opposite x_j (eq. 3.13: c = cot / 4 each).
        l.Weights[entry(g.J)] += 0.25 * g.CotK;
        l.Weights[entry(g.K)] += 0.25 * g.CotJ;
        mass += g.MixedArea;
      });
      l.FinishRow(i, mass);
    }
    degenerate += nDegenerate;
  });
  l.DegenerateTriangles = degenerate;
}

} // namespace

void AssembleSurfaceLaplacian(const MeshTopology& topo, const double* points,
  LaplacianWeights weights, GraphLaplacian& l, int numThreads)
{
  AssembleSurface<3>(topo, points, weights, l, numThreads);
}

void AssembleSurfaceLaplacian(const MeshTopology& topo, const double* points, int dimension,
  LaplacianWeights weights, GraphLaplacian& l, int numThreads)
{
  switch (dimension)
  {
    case 3: AssembleSurface<3>(topo, points, weights, l, numThreads); break;
    case 4: AssembleSurface<4>(topo, points, weights, l, numThreads); break;
    case 5: AssembleSurface<5>(topo, points, weights, l, numThreads); break;
    case 6: AssembleSurface<6>(topo, points, weights, l, numThreads); break;
    case 7: AssembleSurface<7>(topo, points, weights, l, numThreads); break;
    case 8: AssembleSurface<8>(topo, points, weights, l, numThreads); break;
    default: throw std::invalid_argument("AssembleSurfaceLaplacian: dimension must be 3 to 8");
  }
}

namespace
{

/// The edges of triangle t's corners' opposite sides (EdgeGraph::TriangleEdges)
/// that are not e, ascending and without repeats, into `out`; returns how many.
int EdgeNeighbors(const MeshTopology::EdgeTable& edges, const IndexArray& triangleEdges,
  Index e, Index out[4])
{
  int n = 0;
  for (int side = 0; side < 2; ++side)
  {
    const Index c = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + side];
    if (c < 0)
    {
      continue;
    }
    for (const Index other : { MeshTopology::Next(c), MeshTopology::Prev(c) })
    {
      out[n++] = triangleEdges[other];
    }
  }
  std::sort(out, out + n);
  n = static_cast<int>(std::unique(out, out + n) - out);
  return static_cast<int>(std::remove(out, out + n, e) - out);
}

} // namespace

void EdgeGraph::Build(const MeshTopology& topo, bool neighbors)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  TriangleEdges.assign(tri.size(), -1);
  ParallelFor(static_cast<std::int64_t>(tri.size()), topo.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t c = begin; c < end; ++c)
    {
      const Index corner = static_cast<Index>(c);
      TriangleEdges[c] = static_cast<Index>(
        edges.Find(tri[MeshTopology::Next(corner)], tri[MeshTopology::Prev(corner)]));
    }
  });
  if (!neighbors)
  {
    return;
  }
  Offsets.assign(static_cast<std::size_t>(ne) + 1, 0);
  Index row[4];
  for (Index e = 0; e < ne; ++e)
  {
    Offsets[e + 1] = Offsets[e] + EdgeNeighbors(edges, TriangleEdges, e, row);
  }
  Neighbors.assign(static_cast<std::size_t>(Offsets[ne]), 0);
  ParallelFor(ne, topo.NumberOfThreads(), [&](std::int64_t begin, std::int64_t end) {
    Index local[4];
    for (Index e = static_cast<Index>(begin); e < end; ++e)
    {
      std::copy(local, local + EdgeNeighbors(edges, TriangleEdges, e, local), Neighbors.data() + Offsets[e]);
    }
  });
}

void AssembleNonconformingLaplacian(const MeshTopology& topo, const EdgeGraph& graph, const double* points,
  GraphLaplacian& l, int numThreads)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const IndexArray& tri = topo.TriangleList();
  const Index ne = static_cast<Index>(edges.NumberOfEdges());
  Resize(l, ne, graph.Offsets.data(), graph.Neighbors.data());
  ParallelFor(ne, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (Index e = static_cast<Index>(begin); e < end; ++e)
    {
      const Index* first = l.Neighbors + l.Offsets[e];
      const Index* last = l.Neighbors + l.Offsets[e + 1];
      const auto entry = [&](Index f) { return std::lower_bound(first, last, f) - l.Neighbors; };
      double mass = 0.0;
      for (int side = 0; side < 2; ++side)
      {
        const Index c = edges.OppositeCorners[2 * static_cast<std::int64_t>(e) + side];
        if (c < 0)
        {
          continue;
        }
        const Index next = MeshTopology::Next(c), prev = MeshTopology::Prev(c);
        const CornerGeometry<3> g =
          MakeCornerGeometry<3>(points, 3, LoadPoint<3>(points, 3, tri[c]), c, tri[next], tri[prev]);
        if (g.Degenerate)
        {
          continue;
        }
        // The edge opposite next(c) meets e at prev(c), the one opposite prev(c) at next(c).
        l.Weights[entry(graph.TriangleEdges[next])] += g.CotK;
        l.Weights[entry(graph.TriangleEdges[prev])] += g.CotJ;
        mass += g.TwiceArea / 6.0;
      }
      l.FinishRow(e, mass);
    }
  });
}

void CurveGraph::Build(Index n, const std::vector<std::vector<Index>>& loops,
  const std::vector<std::vector<Index>>& chains)
{
  std::vector<std::vector<Index>> adjacency(n);
  const auto link = [&](Index a, Index b) {
    if (a != b)
    {
      adjacency[a].push_back(b);
      adjacency[b].push_back(a);
    }
  };
  for (const auto& loop : loops)
  {
    for (std::size_t k = 0; loop.size() >= 3 && k < loop.size(); ++k)
    {
      link(loop[k], loop[(k + 1) % loop.size()]);
    }
  }
  for (const auto& chain : chains)
  {
    for (std::size_t k = 0; k + 1 < chain.size(); ++k)
    {
      link(chain[k], chain[k + 1]);
    }
  }
  Offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  Neighbors.clear();
  for (Index v = 0; v < n; ++v)
  {
    auto& a = adjacency[v];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    Neighbors.insert(Neighbors.end(), a.begin(), a.end());
    Offsets[v + 1] = static_cast<std::int64_t>(Neighbors.size());
  }
}

void AssembleCurveLaplacian(
  const CurveGraph& graph, const double* points, LaplacianWeights weights, GraphLaplacian& l)
{
  const Index n = static_cast<Index>(graph.Offsets.size()) - 1;
  Resize(l, n, graph.Offsets.data(), graph.Neighbors.data());
  for (Index i = 0; i < n; ++i)
  {
    EdgeLengthWeights<3>(l, points, weights == LaplacianWeights::Umbrella
        ? LaplacianWeights::Umbrella : LaplacianWeights::InverseEdgeLength, i);
  }
}

} // namespace beltrami
