#include "Maps/ParameterizationSystem.h"

#include "Mesh/Laplacian.h"
#include "Mesh/RingGeometry.h"

#include <Eigen/Geometry>

namespace beltrami::detail
{

/// The per-vertex system rows lambda M^A + mu h^2 M^chi (unknown = vertex).
RowMatrix VertexSystem(const MeshTopology& topo, const double* points, double lambda, double mu,
  int threads, Index& degenerate)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const Index n = topo.NumberOfVertices();
  GraphLaplacian conformal, authalic;
  if (lambda != 0.0)
  {
    AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, conformal, threads);
    degenerate = conformal.DegenerateTriangles;
  }
  double h2 = 0.0;
  if (mu != 0.0)
  {
    AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Authalic, authalic, threads);
    degenerate = authalic.DegenerateTriangles;
    h2 = ParallelSum(edges.NumberOfEdges(), 1, threads, [&](std::int64_t b, std::int64_t e, double* sum) {
      for (std::int64_t k = b; k < e; ++k)
      {
        *sum += (Point(points, edges.Vertices[2 * k]) - Point(points, edges.Vertices[2 * k + 1])).squaredNorm();
      }
    })[0] / std::max<std::int64_t>(1, edges.NumberOfEdges());
  }
  RowMatrix m;
  m.Offsets.resize(static_cast<std::size_t>(n) + 1);
  for (Index i = 0; i <= n; ++i)
  {
    m.Offsets[i] = edges.NeighborOffsets[i] + i; // the neighbours and the diagonal
  }
  m.Columns.resize(m.Offsets[n]);
  m.Values.resize(m.Offsets[n]);
  ParallelFor(n, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      std::int64_t out = m.Offsets[i];
      double diagonal = 0.0;
      const std::int64_t diagonalAt = out++;
      for (std::int64_t k = edges.NeighborOffsets[i]; k < edges.NeighborOffsets[i + 1]; ++k)
      {
        double w = 0.0;
        if (lambda != 0.0)
        {
          w += lambda * 4.0 * conformal.Weights[k]; // cot a + cot b
        }
        if (mu != 0.0)
        {
          w += mu * h2 * authalic.Weights[k];
        }
        m.Columns[out] = edges.Neighbors[k];
        m.Values[out++] = -w;
        diagonal += w;
      }
      m.Columns[diagonalAt] = i;
      m.Values[diagonalAt] = diagonal;
    }
  });
  return m;
}

/// The coupled rows of the natural conformal map (eq. 5.7, halved):
/// unknowns 2i (u) and 2i+1 (v):  S (x) I_2  -  (1/2) Hess(signed area).
RowMatrix NaturalSystem(const MeshTopology& topo, const double* points, int threads,
  const std::vector<Index>& boundaryPrev, Index& degenerate)
{
  const MeshTopology::VertexGraph& edges = topo.Graph();
  const Index n = topo.NumberOfVertices();
  GraphLaplacian s;
  AssembleSurfaceLaplacian(topo, points, LaplacianWeights::Cotangent, s, threads);
  degenerate = s.DegenerateTriangles;
  RowMatrix m;
  m.Offsets.resize(2 * static_cast<std::size_t>(n) + 1);
  m.Offsets[0] = 0;
  for (Index i = 0; i < n; ++i)
  {
    const std::int64_t count =
      edges.NeighborOffsets[i + 1] - edges.NeighborOffsets[i] + 1 + (topo.BoundaryNext(i) >= 0 ? 2 : 0);
    m.Offsets[2 * i + 1] = m.Offsets[2 * i] + count;
    m.Offsets[2 * i + 2] = m.Offsets[2 * i + 1] + count;
  }
  m.Columns.resize(m.Offsets[2 * n]);
  m.Values.resize(m.Offsets[2 * n]);
  ParallelFor(n, threads, [&](std::int64_t begin, std::int64_t end) {
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      for (int d = 0; d < 2; ++d)
      {
        std::int64_t out = m.Offsets[2 * i + d];
        m.Columns[out] = 2 * i + d;
        m.Values[out++] = s.Diagonal[i];
        for (std::int64_t k = edges.NeighborOffsets[i]; k < edges.NeighborOffsets[i + 1]; ++k)
        {
          m.Columns[out] = 2 * edges.Neighbors[k] + d;
          m.Values[out++] = -s.Weights[k];
        }
        const Index next = topo.BoundaryNext(i);
        if (next >= 0)
        {
          // d/du_i of A = 1/2 R(u_prev - u_next), R(x, y) = (-y, x); halved.
          const Index prev = boundaryPrev[i];
          const double sign = d == 0 ? 1.0 : -1.0;
          m.Columns[out] = 2 * next + (1 - d);
          m.Values[out++] = -0.25 * sign;
          m.Columns[out] = 2 * prev + (1 - d);
          m.Values[out++] = 0.25 * sign;
        }
      }
    }
  });
  return m;
}

void AddConstraintRows(const ParameterizationOptions& options, bool coupled,
  std::vector<ConstraintRow>& rows)
{
  for (const PointConstraint& c : options.Constraints)
  {
    if (!coupled)
    {
      ConstraintRow row;
      for (int k = 0; k < 3; ++k)
      {
        if (c.Vertices[k] >= 0 && c.Weights[k] != 0.0)
        {
          row.Entries.emplace_back(c.Vertices[k], c.Weights[k]);
        }
      }
      row.Target = { c.Target[0], c.Target[1] };
      rows.push_back(std::move(row));
      continue;
    }
    for (int d = 0; d < 2; ++d)
    {
      ConstraintRow row;
      for (int k = 0; k < 3; ++k)
      {
        if (c.Vertices[k] >= 0 && c.Weights[k] != 0.0)
        {
          row.Entries.emplace_back(2 * c.Vertices[k] + d, c.Weights[k]);
        }
      }
      row.Target = { c.Target[d] };
      rows.push_back(std::move(row));
    }
  }
}

} // namespace beltrami::detail
