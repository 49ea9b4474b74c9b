#include "Mesh/Tetrahedra.h"

#include "Solvers/Partition.h"

#include "Support/LargeBuffer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numeric>

namespace beltrami
{

namespace
{
double Dot(const double* a, const double* b, int n)
{
  double s = 0.0;
  for (int k = 0; k < n; ++k)
  {
    s += a[k] * b[k];
  }
  return s;
}
} // namespace

TetrahedronTerms Tetrahedron(const double* p0, const double* p1, const double* p2,
  const double* p3, int dimension)
{
  double e[3][9];
  const double* q[3] = { p1, p2, p3 };
  for (int s = 0; s < 3; ++s)
  {
    for (int k = 0; k < dimension; ++k)
    {
      e[s][k] = q[s][k] - p0[k];
    }
  }
  return TetrahedronFromGram(Dot(e[0], e[0], dimension), Dot(e[1], e[1], dimension),
    Dot(e[2], e[2], dimension), Dot(e[0], e[1], dimension), Dot(e[0], e[2], dimension),
    Dot(e[1], e[2], dimension));
}

TetrahedralMesh::TetrahedralMesh(Index numberOfVertices, std::vector<Index> tetrahedra, int numThreads)
  : NumVertices(std::max<Index>(numberOfVertices, 0))
{
  // Keep the valid tetrahedra.
  std::size_t out = 0;
  for (std::size_t t = 0; t + 3 < tetrahedra.size(); t += 4)
  {
    const Index* v = &tetrahedra[t];
    bool ok = true;
    for (int a = 0; a < 4 && ok; ++a)
    {
      ok = v[a] >= 0 && v[a] < NumVertices;
      for (int b = 0; b < a && ok; ++b)
      {
        ok = v[a] != v[b];
      }
    }
    if (!ok)
    {
      ++Dropped;
      continue;
    }
    std::copy(v, v + 4, &tetrahedra[out]);
    out += 4;
  }
  tetrahedra.resize(out);
  Tets = std::move(tetrahedra);
  const std::size_t nt = Tets.size() / 4;

  // Tetrahedra of every vertex (CSR, ascending tetrahedron ids).
  IncidentOffsets.assign(static_cast<std::size_t>(NumVertices) + 1, 0);
  for (Index v : Tets)
  {
    ++IncidentOffsets[v + 1];
  }
  std::partial_sum(IncidentOffsets.begin(), IncidentOffsets.end(), IncidentOffsets.begin());
  Incident.resize(Tets.size());
  {
    std::vector<std::int64_t> cursor(IncidentOffsets.begin(), IncidentOffsets.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
    {
      for (int a = 0; a < 4; ++a)
      {
        Incident[cursor[Tets[4 * t + a]]++] = static_cast<Index>(t);
      }
    }
  }

  // Neighbours: the other vertices of the incident tetrahedra, sorted, unique.
  Offsets.assign(static_cast<std::size_t>(NumVertices) + 1, 0);
  std::vector<std::vector<Index>> rows(static_cast<std::size_t>(NumVertices));
  ParallelFor(NumVertices, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v)
    {
      std::vector<Index>& row = rows[v];
      for (const Index* t = IncidentBegin(static_cast<Index>(v)); t != IncidentEnd(static_cast<Index>(v)); ++t)
      {
        for (int a = 0; a < 4; ++a)
        {
          const Index w = Tets[4 * static_cast<std::size_t>(*t) + a];
          if (w != v)
          {
            row.push_back(w);
          }
        }
      }
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      Offsets[v + 1] = static_cast<std::int64_t>(row.size());
    }
  });
  std::partial_sum(Offsets.begin(), Offsets.end(), Offsets.begin());
  NeighborList.resize(static_cast<std::size_t>(Offsets.back()));
  ParallelFor(NumVertices, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v)
    {
      std::copy(rows[v].begin(), rows[v].end(), NeighborList.begin() + Offsets[v]);
    }
  });
  // Per incident tetrahedron of every vertex: its three edges at the vertex
  // and their positions in the vertex's neighbour row (found once here, not
  // per assembly).
  IncidentEdge.resize(3 * Incident.size());
  IncidentSlot.resize(3 * Incident.size());
  ParallelFor(NumVertices, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t v = begin; v < end; ++v)
    {
      const Index* row = NeighborList.data() + Offsets[v];
      const Index* rowEnd = NeighborList.data() + Offsets[v + 1];
      std::size_t entry = 3 * static_cast<std::size_t>(IncidentOffsets[v]);
      for (const Index* t = IncidentBegin(static_cast<Index>(v)); t != IncidentEnd(static_cast<Index>(v)); ++t)
      {
        const Index* c = &Tets[4 * static_cast<std::size_t>(*t)];
        for (int e = 0; e < 6; ++e)
        {
          const Index a = c[TetrahedronEdges[e][0]], b = c[TetrahedronEdges[e][1]];
          if (a == v || b == v)
          {
            IncidentEdge[entry] = static_cast<std::uint8_t>(e);
            IncidentSlot[entry++] = static_cast<std::uint32_t>(std::lower_bound(row, rowEnd, a == v ? b : a) - row);
          }
        }
      }
    }
  });
}

std::vector<Index> GridTetrahedra(Index nx, Index ny, Index nz)
{
  std::vector<Index> tets;
  if (nx < 2 || ny < 2 || nz < 2)
  {
    return tets;
  }
  tets.reserve(static_cast<std::size_t>(nx - 1) * (ny - 1) * (nz - 1) * 24);
  const auto id = [&](Index i, Index j, Index k) { return (k * ny + j) * nx + i; };
  for (Index k = 0; k + 1 < nz; ++k)
  {
    for (Index j = 0; j + 1 < ny; ++j)
    {
      for (Index i = 0; i + 1 < nx; ++i)
      {
        for (const auto& path : KuhnPaths)
        {
          Index c[3] = { i, j, k };
          tets.push_back(id(c[0], c[1], c[2]));
          for (int step = 0; step < 3; ++step)
          {
            ++c[path[step]];
            tets.push_back(id(c[0], c[1], c[2]));
          }
        }
      }
    }
  }
  return tets;
}

std::vector<std::uint8_t> TetrahedralMesh::BoundaryVertices() const
{
  // Every face as its sorted corners; a face that appears once is on the boundary.
  std::vector<std::array<Index, 3>> faces;
  faces.reserve(Tets.size());
  for (std::size_t t = 0; t < Tets.size(); t += 4)
  {
    for (int skip = 0; skip < 4; ++skip)
    {
      std::array<Index, 3> f;
      int m = 0;
      for (int a = 0; a < 4; ++a)
      {
        if (a != skip)
        {
          f[m++] = Tets[t + a];
        }
      }
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  }
  std::sort(faces.begin(), faces.end());
  std::vector<std::uint8_t> boundary(NumVertices, 0);
  for (Index v = 0; v < NumVertices; ++v)
  {
    boundary[v] = IncidentOffsets[v + 1] == IncidentOffsets[v]; // in no tetrahedron
  }
  for (std::size_t k = 0; k < faces.size();)
  {
    std::size_t e = k + 1;
    while (e < faces.size() && faces[e] == faces[k])
    {
      ++e;
    }
    if (e - k == 1)
    {
      for (const Index v : faces[k])
      {
        boundary[v] = 1;
      }
    }
    k = e;
  }
  return boundary;
}

double TetrahedralMesh::MeanEdgeLength(const double* points, const Partition* split) const
{
  double sums[2] = { 0.0, 0.0 }; // lengths, edges
  for (Index v = 0; v < NumVertices; ++v)
  {
    for (std::int64_t k = Offsets[v]; k < Offsets[v + 1]; ++k)
    {
      const Index w = NeighborList[k];
      if (w > v && (!split || split->CountsEdge(v, w)))
      {
        const double* a = points + 3 * static_cast<std::int64_t>(v);
        const double* b = points + 3 * static_cast<std::int64_t>(w);
        sums[0] += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
          (a[2] - b[2]) * (a[2] - b[2]));
        sums[1] += 1.0;
      }
    }
  }
  if (split)
  {
    split->Sum(sums, 2);
  }
  return sums[1] > 0.0 ? sums[0] / sums[1] : 0.0;
}

void AssembleTetrahedralLaplacian(const TetrahedralMesh& mesh, const double* points, int dimension,
  GraphLaplacian& l, int numThreads, LargeVector<TetrahedronTerms>* kept)
{
  const Index n = mesh.NumberOfVertices();
  l.NumberOfVertices = n;
  l.Offsets = mesh.NeighborOffsets().data();
  l.Neighbors = mesh.Neighbors().data();
  l.Weights.assign(static_cast<std::size_t>(mesh.NeighborOffsets()[n]), 0.0);
  l.Diagonal.assign(n, 0.0);
  l.Mass.assign(n, 0.0);
  const std::vector<Index>& tets = mesh.TetrahedronList();
  std::atomic<Index> degenerate{ 0 };
  // Every tetrahedron evaluated once, then summed row by row (each row reads
  // the terms of its tetrahedra): no two threads write the same entry, and
  // the sums do not depend on the threads.
  const std::int64_t numTets = mesh.NumberOfTetrahedra();
  LargeVector<TetrahedronTerms> local;
  LargeVector<TetrahedronTerms>& terms = kept ? *kept : local;
  terms.resize(static_cast<std::size_t>(numTets)); // (every entry written below)
  ParallelFor(numTets, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t t = begin; t < end; ++t)
    {
      const Index* v = &tets[4 * static_cast<std::size_t>(t)];
      terms[t] = Tetrahedron(points + static_cast<std::int64_t>(v[0]) * dimension,
        points + static_cast<std::int64_t>(v[1]) * dimension, points + static_cast<std::int64_t>(v[2]) * dimension,
        points + static_cast<std::int64_t>(v[3]) * dimension, dimension);
    }
  });
  ParallelFor(n, numThreads, [&](std::int64_t begin, std::int64_t end) {
    Index nDegenerate = 0;
    for (Index i = static_cast<Index>(begin); i < end; ++i)
    {
      const std::int64_t first = l.Offsets[i];
      double mass = 0.0;
      const std::uint8_t* edge = mesh.IncidentEdges(i);
      const std::uint32_t* slot = mesh.IncidentSlots(i);
      double* weights = l.Weights.data() + first;
      for (const Index* t = mesh.IncidentBegin(i); t != mesh.IncidentEnd(i); ++t, edge += 3, slot += 3)
      {
        const TetrahedronTerms& term = terms[*t];
        if (term.Degenerate)
        {
          nDegenerate += tets[4 * static_cast<std::size_t>(*t)] == i; // each tetrahedron counted once
          continue;
        }
        mass += 0.25 * term.Volume;
        for (int j = 0; j < 3; ++j)
        {
          weights[slot[j]] += term.Weights[edge[j]];
        }
      }
      l.FinishRow(i, mass);
    }
    degenerate += nDegenerate;
  });
  l.DegenerateTriangles = degenerate;
}

} // namespace beltrami
