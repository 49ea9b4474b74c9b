#include "Mesh/MeshTopology.h"

#include "Support/DisjointSets.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace beltrami
{

namespace
{

// One half-edge seen from vertex v: the neighbour at its other end, the corner
// of v in the triangle holding it, and whether it leaves v (+1) or enters v (-1).
struct RingEntry
{
  Index Neighbor;
  Index Corner;
  Index LocalFace; // position of Corner in v's corner list
  std::int8_t Direction;
};

// Collects and sorts the half-edges around v; entries with the same
// neighbour are contiguous (one group per undirected edge).
void GatherRing(const MeshTopology& topo, Index v, std::vector<RingEntry>& ring)
{
  ring.clear();
  Index local = 0;
  const Index* pair = topo.RingPairsBegin(v);
  for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c, ++local, pair += 2)
  {
    ring.push_back({ pair[0], *c, local, +1 });
    ring.push_back({ pair[1], *c, local, -1 });
  }
  std::sort(ring.begin(), ring.end(), [](const RingEntry& a, const RingEntry& b) {
    return a.Neighbor != b.Neighbor ? a.Neighbor < b.Neighbor : a.Corner < b.Corner;
  });
}

// Corner opposite the edge (v, neighbour) in the triangle of a ring entry.
Index OppositeCorner(const RingEntry& e)
{
  return e.Direction > 0 ? MeshTopology::Prev(e.Corner) : MeshTopology::Next(e.Corner);
}

// The common case, checked without sorting: v is an interior manifold
// vertex whose triangles form one consistently oriented fan, i.e. the
// (next, previous) pairs of its corners chain into a single cycle through
// all of them.  Then every neighbour appears once as a next and once as a
// previous vertex (each edge has two triangles of opposite directions) and
// no two triangles repeat.  Returns the number of neighbours with a larger
// id (the edges v owns), or -1 when the general classification is needed.
int RegularFanOwnedEdges(const Index* pairs, Index valence, Index v)
{
  constexpr Index MaximumValence = 32;
  if (valence < 3 || valence > MaximumValence)
  {
    return -1;
  }
  // successor[a]: the corner whose next vertex is the previous vertex of a.
  std::int8_t successor[MaximumValence];
  int owned = 0;
  for (Index a = 0; a < valence; ++a)
  {
    int found = -1;
    for (Index b = 0; b < valence; ++b)
    {
      if (b != a && pairs[2 * b] == pairs[2 * a])
      {
        return -1; // a neighbour twice as a next vertex
      }
      if (pairs[2 * b] == pairs[2 * a + 1])
      {
        found = b;
      }
    }
    if (found < 0 || found == a)
    {
      return -1;
    }
    successor[a] = static_cast<std::int8_t>(found);
    owned += pairs[2 * a] > v;
  }
  // One cycle through all corners (next vertices are distinct, so the
  // successor map is a permutation).
  Index length = 0;
  Index c = 0;
  do
  {
    c = successor[c];
    ++length;
  } while (c != 0 && length <= valence);
  return length == valence ? owned : -1;
}

} // namespace

MeshTopology::MeshTopology(Index numberOfVertices, IndexArray triangles, int numThreads)
  : NumVertices(std::max<Index>(0, numberOfVertices))
  , NumThreads(ResolveThreadCount(numThreads))
{
  if (triangles.size() % 3 != 0)
  {
    throw std::invalid_argument("MeshTopology: triangle list length is not a multiple of 3");
  }
  if (triangles.size() / 3 > static_cast<std::size_t>(std::numeric_limits<Index>::max() / 3))
  {
    throw std::length_error("MeshTopology: too many triangles for 32-bit corner ids");
  }
  // Keep only well-formed triangles (compacting in place).
  const Index inputTriangles = static_cast<Index>(triangles.size() / 3);
  OriginalIds.reserve(inputTriangles);
  std::size_t out = 0;
  for (Index t = 0; t < inputTriangles; ++t)
  {
    const Index a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
    const bool inRange = a >= 0 && b >= 0 && c >= 0 && a < NumVertices && b < NumVertices &&
      c < NumVertices;
    if (!inRange || a == b || b == c || a == c)
    {
      ++DroppedTriangles;
      continue;
    }
    triangles[out++] = a;
    triangles[out++] = b;
    triangles[out++] = c;
    OriginalIds.push_back(t);
  }
  triangles.resize(out);
  Triangles = std::move(triangles);

  // Vertex -> incident corners (CSR, corners ascending within each vertex)
  // and their ring pairs.  Each thread owns a range of vertices and scans
  // all corners: no atomics, and the order does not depend on the threads.
  const Index numCorners = static_cast<Index>(Triangles.size());
  CornerOffsets.assign(static_cast<std::size_t>(NumVertices) + 1, 0);
  const int owners = numCorners < (1 << 18) ? 1 : NumThreads;
  const auto forOwnedCorners = [&](auto&& f) {
    ParallelFor(owners, owners, [&](std::int64_t first, std::int64_t last) {
      for (std::int64_t owner = first; owner < last; ++owner)
      {
        const Index begin = static_cast<Index>(NumVertices * owner / owners);
        const Index end = static_cast<Index>(NumVertices * (owner + 1) / owners);
        for (Index c = 0; c < numCorners; ++c)
        {
          const Index v = Triangles[c];
          if (v >= begin && v < end)
          {
            f(v, c);
          }
        }
      }
    }, {}, 1, 1);
  };
  forOwnedCorners([&](Index v, Index) { ++CornerOffsets[v + 1]; });
  std::partial_sum(CornerOffsets.begin(), CornerOffsets.end(), CornerOffsets.begin());
  VertexCorners.resize(Triangles.size());
  RingPairs.resize(2 * Triangles.size());
  {
    LargeVector<std::int64_t> cursor(CornerOffsets.begin(), CornerOffsets.end() - 1);
    forOwnedCorners([&](Index v, Index c) {
      const std::int64_t slot = cursor[v]++;
      VertexCorners[slot] = c;
      RingPairs[2 * slot] = Triangles[Next(c)];
      RingPairs[2 * slot + 1] = Triangles[Prev(c)];
    });
  }
  Classify();
}

void MeshTopology::Classify()
{
  Flags.assign(NumVertices, VertexRegular);
  BoundaryNextVertex.assign(NumVertices, -1);

  std::atomic<std::int64_t> edges{ 0 }, boundaryEdges{ 0 }, nonManifoldEdges{ 0 },
    inconsistentEdges{ 0 }, duplicates{ 0 };

  ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
    std::vector<RingEntry> ring;
    std::vector<Index> parent;
    std::vector<std::pair<Index, Index>> faces;
    std::int64_t nEdges = 0, nBoundary = 0, nNonManifold = 0, nInconsistent = 0, nDup = 0;
    for (Index v = static_cast<Index>(begin); v < end; ++v)
    {
      const Index valence = Valence(v);
      if (valence == 0)
      {
        Flags[v] = VertexIsolated;
        continue;
      }
      const int regularOwned = RegularFanOwnedEdges(RingPairsBegin(v), valence, v);
      if (regularOwned >= 0)
      {
        Flags[v] = VertexRegular;
        nEdges += regularOwned;
        continue;
      }
      GatherRing(*this, v, ring);
      parent.resize(valence);
      std::iota(parent.begin(), parent.end(), 0);
      std::uint8_t flags = VertexRegular;
      for (std::size_t g = 0; g < ring.size();)
      {
        std::size_t h = g + 1;
        int directionSum = ring[g].Direction;
        while (h < ring.size() && ring[h].Neighbor == ring[g].Neighbor)
        {
          directionSum += ring[h].Direction;
          ++h;
        }
        const std::size_t count = h - g;
        const bool owned = ring[g].Neighbor > v; // count each undirected edge once
        if (count == 1)
        {
          flags |= VertexBoundary;
          if (ring[g].Direction > 0)
          {
            BoundaryNextVertex[v] = ring[g].Neighbor;
          }
          nBoundary += owned;
        }
        else if (count == 2)
        {
          if (directionSum != 0)
          {
            flags |= VertexInconsistent;
            nInconsistent += owned;
          }
          // The two triangles are joined across this edge: same fan.
          const Index a = FindRoot(parent, ring[g].LocalFace);
          const Index b = FindRoot(parent, ring[g + 1].LocalFace);
          parent[a] = b;
        }
        else
        {
          flags |= VertexNonManifold;
          nNonManifold += owned;
        }
        nEdges += owned;
        g = h;
      }
      Index fans = 0;
      for (Index f = 0; f < valence; ++f)
      {
        fans += FindRoot(parent, f) == f;
      }
      if (fans > 1)
      {
        flags |= VertexNonManifold;
      }
      // Duplicate triangles: two corners of v seeing the same unordered {j, k}.
      faces.clear();
      for (const Index* pair = RingPairsBegin(v); pair != RingPairsBegin(v + 1); pair += 2)
      {
        faces.emplace_back(std::min(pair[0], pair[1]), std::max(pair[0], pair[1]));
      }
      std::sort(faces.begin(), faces.end());
      if (std::adjacent_find(faces.begin(), faces.end()) != faces.end())
      {
        flags |= VertexDuplicateFace;
        // Count each duplicated triangle once: at its smallest vertex.
        for (std::size_t f = 1; f < faces.size(); ++f)
        {
          nDup += faces[f] == faces[f - 1] && v < faces[f].first;
        }
      }
      Flags[v] = flags;
    }
    edges += nEdges;
    boundaryEdges += nBoundary;
    nonManifoldEdges += nNonManifold;
    inconsistentEdges += nInconsistent;
    duplicates += nDup;
  });

  Info = TopologySummary();
  Info.NumberOfVertices = NumVertices;
  Info.NumberOfTriangles = NumberOfTriangles();
  Info.NumberOfEdges = edges;
  Info.NumberOfBoundaryEdges = static_cast<Index>(boundaryEdges);
  Info.NumberOfNonManifoldEdges = static_cast<Index>(nonManifoldEdges);
  Info.NumberOfInconsistentEdges = static_cast<Index>(inconsistentEdges);
  Info.NumberOfDuplicateTriangles = static_cast<Index>(duplicates);
  for (Index v = 0; v < NumVertices; ++v)
  {
    const std::uint8_t f = Flags[v];
    Info.NumberOfIsolatedVertices += (f & VertexIsolated) != 0;
    Info.NumberOfBoundaryVertices += (f & VertexBoundary) != 0;
    Info.NumberOfNonManifoldVertices += (f & VertexNonManifold) != 0;
  }
  Info.NumberOfUsedVertices = NumVertices - Info.NumberOfIsolatedVertices;
  Info.EulerCharacteristic = static_cast<std::int64_t>(Info.NumberOfUsedVertices) -
    Info.NumberOfEdges + Info.NumberOfTriangles;
  Info.NumberOfBoundaryLoops = static_cast<Index>(BoundaryLoops().size());
}

std::vector<std::vector<Index>> MeshTopology::BoundaryLoops() const
{
  std::vector<std::vector<Index>> loops;
  std::vector<std::uint8_t> visited(NumVertices, 0);
  for (Index start = 0; start < NumVertices; ++start)
  {
    if (visited[start] || BoundaryNextVertex[start] < 0)
    {
      continue;
    }
    std::vector<Index> loop;
    Index v = start;
    // Walk outgoing boundary half-edges; stops on a visited vertex, so
    // non-manifold boundaries cannot make it loop forever.
    while (v >= 0 && !visited[v])
    {
      visited[v] = 1;
      loop.push_back(v);
      v = BoundaryNextVertex[v];
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<Index> MeshTopology::ComponentRoots() const
{
  std::vector<Index> parent(NumVertices);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t t = 0; t < Triangles.size(); t += 3)
  {
    const Index a = FindRoot(parent, Triangles[t]);
    const Index b = FindRoot(parent, Triangles[t + 1]);
    const Index c = FindRoot(parent, Triangles[t + 2]);
    parent[b] = a;
    parent[c] = a;
  }
  for (Index v = 0; v < NumVertices; ++v)
  {
    parent[v] = FindRoot(parent, v);
  }
  return parent;
}

Index MeshTopology::CountComponents() const
{
  const std::vector<Index> root = ComponentRoots();
  Index components = 0;
  for (Index v = 0; v < NumVertices; ++v)
  {
    components += Valence(v) > 0 && root[v] == v;
  }
  return components;
}

std::string MeshTopology::Describe() const
{
  std::ostringstream os;
  const Index components = CountComponents();
  os << Info.NumberOfTriangles << " triangles, " << Info.NumberOfUsedVertices << " vertices, "
     << components << (components == 1 ? " component" : " components") << ", "
     << Info.NumberOfBoundaryLoops << " boundary loop" << (Info.NumberOfBoundaryLoops == 1 ? "" : "s")
     << ", Euler characteristic " << Info.EulerCharacteristic;
  if (components == 1 && Info.IsManifold() && Info.IsOriented())
  {
    // chi = 2 - 2g - b for a connected orientable surface with b boundary loops.
    const std::int64_t twiceGenus = 2 - Info.EulerCharacteristic - Info.NumberOfBoundaryLoops;
    if (twiceGenus >= 0 && twiceGenus % 2 == 0)
    {
      os << ", genus " << twiceGenus / 2;
    }
  }
  if (Info.NumberOfNonManifoldEdges)
  {
    os << ", " << Info.NumberOfNonManifoldEdges << " non-manifold edges";
  }
  if (Info.NumberOfNonManifoldVertices)
  {
    os << ", " << Info.NumberOfNonManifoldVertices << " non-manifold vertices";
  }
  if (Info.NumberOfInconsistentEdges)
  {
    os << ", " << Info.NumberOfInconsistentEdges << " edges with inconsistent orientation";
  }
  if (Info.NumberOfDuplicateTriangles)
  {
    os << ", " << Info.NumberOfDuplicateTriangles << " duplicate triangles";
  }
  if (DroppedTriangles)
  {
    os << ", " << DroppedTriangles << " invalid triangles dropped";
  }
  return os.str();
}

void MeshTopology::VertexEdges(Index v, std::vector<VertexEdge>& edges) const
{
  edges.clear();
  const Index* pairs = RingPairsBegin(v);
  const Index* corners = CornersBegin(v);
  const Index valence = Valence(v);
  bool fan = Flags[v] == VertexRegular;
  // One consistently oriented fan: the neighbour after corner a is the one
  // before exactly one other corner b, and a, b are the edge's triangles.
  for (Index a = 0; fan && a < valence; ++a)
  {
    const Index b = CornerAcross(pairs, valence, a);
    fan = b < valence;
    if (fan)
    {
      const Index leaving = Prev(corners[a]), entering = Next(corners[b]);
      edges.push_back(leaving < entering ? VertexEdge{ pairs[2 * a], { leaving, entering }, { a, b }, 2 }
                                         : VertexEdge{ pairs[2 * a], { entering, leaving }, { b, a }, 2 });
    }
  }
  if (fan)
  {
    std::sort(edges.begin(), edges.end(),
      [](const VertexEdge& x, const VertexEdge& y) { return x.Neighbor < y.Neighbor; });
    return;
  }
  edges.clear();
  thread_local std::vector<RingEntry> ring;
  GatherRing(*this, v, ring);
  for (std::size_t g = 0; g < ring.size();)
  {
    std::size_t h = g;
    while (h < ring.size() && ring[h].Neighbor == ring[g].Neighbor)
    {
      ++h;
    }
    VertexEdge edge{ ring[g].Neighbor, { -1, -1 }, { -1, -1 }, static_cast<int>(std::min<std::size_t>(h - g, 255)) };
    for (std::size_t k = 0; k < std::min<std::size_t>(h - g, 2); ++k)
    {
      edge.Opposite[k] = OppositeCorner(ring[g + k]);
      edge.Local[k] = ring[g + k].LocalFace;
    }
    edges.push_back(edge);
    g = h;
  }
}

const MeshTopology::VertexGraph& MeshTopology::Graph() const
{
  std::call_once(GraphOnce, [this]() {
    auto graph = std::make_unique<VertexGraph>();
    graph->NeighborOffsets.assign(static_cast<std::size_t>(NumVertices) + 1, 0);
    ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
      std::vector<VertexEdge> edges;
      for (Index v = static_cast<Index>(begin); v < end; ++v)
      {
        if (Flags[v] == VertexRegular) // a closed manifold fan: as many neighbours as triangles
        {
          graph->NeighborOffsets[v + 1] = Valence(v);
          continue;
        }
        VertexEdges(v, edges);
        graph->NeighborOffsets[v + 1] = static_cast<std::int64_t>(edges.size());
      }
    });
    std::partial_sum(graph->NeighborOffsets.begin(), graph->NeighborOffsets.end(), graph->NeighborOffsets.begin());
    graph->Neighbors.resize(graph->NeighborOffsets[NumVertices]);
    ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
      std::vector<VertexEdge> edges;
      for (Index v = static_cast<Index>(begin); v < end; ++v)
      {
        VertexEdges(v, edges);
        std::transform(edges.begin(), edges.end(), graph->Neighbors.begin() + graph->NeighborOffsets[v],
          [](const VertexEdge& e) { return e.Neighbor; });
      }
    });
    GraphData = std::move(graph);
  });
  return *GraphData;
}

const MeshTopology::EdgeTable& MeshTopology::Edges() const
{
  std::call_once(EdgesOnce, [this]() {
    auto table = std::make_unique<EdgeTable>(Graph());
    const std::size_t nv = static_cast<std::size_t>(NumVertices);
    const auto& offsets = table->NeighborOffsets;
    const auto& neighbors = table->Neighbors;
    // The edges a vertex owns: those to a neighbour of a larger id.
    LargeVector<std::int64_t> ownedOffsets(nv + 1, 0);
    ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t v = begin; v < end; ++v)
      {
        ownedOffsets[v + 1] = std::count_if(neighbors.begin() + offsets[v], neighbors.begin() + offsets[v + 1],
          [v](Index u) { return u > v; });
      }
    });
    std::partial_sum(ownedOffsets.begin(), ownedOffsets.end(), ownedOffsets.begin());
    const std::int64_t numEdges = ownedOffsets[nv];
    table->Vertices.resize(2 * numEdges);
    table->OppositeCorners.resize(2 * numEdges);
    table->FaceCount.resize(numEdges);
    table->NeighborEdges.resize(offsets[nv]);
    // The owned edges and the edge ids of the neighbour lists' larger ids.
    ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
      std::vector<VertexEdge> edges;
      for (Index v = static_cast<Index>(begin); v < end; ++v)
      {
        VertexEdges(v, edges);
        std::int64_t slot = offsets[v];
        std::int64_t edge = ownedOffsets[v];
        for (const VertexEdge& e : edges)
        {
          table->NeighborEdges[slot] = -1;
          if (e.Neighbor > v)
          {
            table->NeighborEdges[slot] = edge;
            table->Vertices[2 * edge] = v;
            table->Vertices[2 * edge + 1] = e.Neighbor;
            table->FaceCount[edge] = static_cast<std::uint8_t>(e.Faces);
            table->OppositeCorners[2 * edge] = e.Opposite[0];
            table->OppositeCorners[2 * edge + 1] = e.Opposite[1];
            ++edge;
          }
          ++slot;
        }
      }
    });
    // The edge ids of the smaller neighbours (edges the neighbour owns).
    ParallelFor(NumVertices, NumThreads, [&](std::int64_t begin, std::int64_t end) {
      for (Index v = static_cast<Index>(begin); v < end; ++v)
      {
        for (std::int64_t s = table->NeighborOffsets[v]; s < table->NeighborOffsets[v + 1]; ++s)
        {
          const Index n = table->Neighbors[s];
          if (n > v)
          {
            continue;
          }
          // n's owned edges are stored in ascending neighbour order.
          const auto first = table->Vertices.begin();
          std::int64_t lo = ownedOffsets[n], hi = ownedOffsets[n + 1];
          while (lo < hi)
          {
            const std::int64_t mid = (lo + hi) / 2;
            if (first[2 * mid + 1] < v)
            {
              lo = mid + 1;
            }
            else
            {
              hi = mid;
            }
          }
          table->NeighborEdges[s] = lo;
        }
      }
    });
    EdgeData = std::move(table);
  });
  return *EdgeData;
}

std::int64_t MeshTopology::EdgeTable::Find(Index a, Index b) const
{
  const Index* begin = Neighbors.data() + NeighborOffsets[a];
  const Index* end = Neighbors.data() + NeighborOffsets[a + 1];
  const Index* at = std::lower_bound(begin, end, b);
  return at != end && *at == b ? NeighborEdges[at - Neighbors.data()] : -1;
}

} // namespace beltrami
