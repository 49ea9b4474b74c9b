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
