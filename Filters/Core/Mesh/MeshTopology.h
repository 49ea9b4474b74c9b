// Beltrami core: the one mesh-topology builder shared by every filter.
//
// Input: a triangle list (three vertex ids per triangle).  Built eagerly:
//   - the corner table (corner c = 3*t + k is vertex k of triangle t),
//   - the incident corners of every vertex (its 1-ring of triangles, CSR),
//     with the other two vertices of each of those triangles stored next to
//     them, so that 1-ring loops read their neighbours sequentially instead
//     of through the corner table (8 bytes per corner; on meshes of
//     millions of triangles those random reads were half of the run time),
//   - a classification of every vertex (boundary, non-manifold edge or fan,
//     inconsistent orientation, duplicate triangle, isolated),
//   - the outgoing boundary half-edge of each boundary vertex, and global
//     counts (edges, Euler characteristic, boundary loops ...).
// Built on first use (thread-safe):
//   - the unique undirected edges with their opposite corners (the angles
//     alpha_ij, beta_ij of the cotangent formula) and the vertex-neighbour
//     CSR (1-ring vertices with the edge that joins them).
// Everything is VTK-free; the construction is parallel and deterministic.
#pragma once

#include "Support/LargeBuffer.h"
#include "Support/Parallel.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace beltrami
{

/// Vertex / triangle / corner ids of a large mesh (see LargeBuffer.h).
using IndexArray = LargeVector<Index>;

/// Bits of MeshTopology::VertexFlags().
enum VertexFlag : std::uint8_t
{
  VertexRegular = 0,
  VertexBoundary = 1,        ///< on an edge used by one triangle
  VertexNonManifold = 2,     ///< on an edge used by 3+ triangles, or several triangle fans meet
  VertexInconsistent = 4,    ///< on an edge whose two triangles have opposite orientations
  VertexDuplicateFace = 8,   ///< in two triangles with the same three vertices
  VertexIsolated = 16,       ///< used by no triangle
  VertexInvalidGeometry = 32 ///< set by geometric passes: non-finite coordinates or degenerate triangles
};

struct TopologySummary
{
  Index NumberOfVertices = 0;
  Index NumberOfUsedVertices = 0;
  Index NumberOfTriangles = 0;
  std::int64_t NumberOfEdges = 0;
  Index NumberOfBoundaryEdges = 0;
  Index NumberOfNonManifoldEdges = 0;
  Index NumberOfInconsistentEdges = 0;
  Index NumberOfBoundaryVertices = 0;
  Index NumberOfNonManifoldVertices = 0;
  Index NumberOfIsolatedVertices = 0;
  Index NumberOfDuplicateTriangles = 0;
  Index NumberOfBoundaryLoops = 0;
  std::int64_t EulerCharacteristic = 0; ///< V_used - E + F

  bool IsManifold() const
  {
    return NumberOfNonManifoldEdges == 0 && NumberOfNonManifoldVertices == 0 &&
      NumberOfDuplicateTriangles == 0;
  }
  bool IsOriented() const { return NumberOfInconsistentEdges == 0; }
  bool IsClosed() const { return NumberOfBoundaryEdges == 0; }
};

class MeshTopology
{
public:
  /// Builds the topology. Triangles with an out-of-range vertex id or a
  /// repeated vertex id are dropped (counted in NumberOfDroppedTriangles()).
  /// The arrays are LargeVectors: on meshes of millions of triangles the
  /// page faults of ordinary allocations cost more than building them.
  MeshTopology(Index numberOfVertices, IndexArray triangles, int numThreads = 0);

  Index NumberOfVertices() const { return NumVertices; }
  Index NumberOfTriangles() const { return static_cast<Index>(Triangles.size() / 3); }
  Index NumberOfDroppedTriangles() const { return DroppedTriangles; }
  const IndexArray& TriangleList() const { return Triangles; }
  /// Index into the caller's original triangle list for each kept triangle.
  const IndexArray& OriginalTriangleIds() const { return OriginalIds; }

  // Corner table.
  static Index Next(Index c) { return c % 3 == 2 ? c - 2 : c + 1; }
  static Index Prev(Index c) { return c % 3 == 0 ? c + 2 : c - 1; }
  Index CornerVertex(Index c) const { return Triangles[c]; }

  /// Incident corners of vertex v: [CornersBegin(v), CornersEnd(v)).
  const Index* CornersBegin(Index v) const { return VertexCorners.data() + CornerOffsets[v]; }
  const Index* CornersEnd(Index v) const { return VertexCorners.data() + CornerOffsets[v + 1]; }
  Index Valence(Index v) const { return CornerOffsets[v + 1] - CornerOffsets[v]; }
  /// The (next, previous) vertices of v's incident corners, two per corner,
  /// in the order of CornersBegin(v): for corner c, CornerVertex(Next(c))
  /// and CornerVertex(Prev(c)).
  const Index* RingPairsBegin(Index v) const { return RingPairs.data() + 2 * CornerOffsets[v]; }

  std::uint8_t VertexFlags(Index v) const { return Flags[v]; }
  const LargeVector<std::uint8_t>& VertexFlagArray() const { return Flags; }
  bool IsInterior(Index v) const { return Flags[v] == VertexRegular; }
  /// For a boundary vertex, the other end of its outgoing boundary half-edge
  /// (the boundary is walked with the surface on the left); -1 otherwise.
  Index BoundaryNext(Index v) const { return BoundaryNextVertex[v]; }

  const TopologySummary& Summary() const { return Info; }

  /// Boundary loops as ordered vertex lists (computed on each call).
  std::vector<std::vector<Index>> BoundaryLoops() const;
  /// Connected components of the triangles (computed on each call).
  Index CountComponents() const;
  /// For every vertex, its component's id: the vertex id of one of the
  /// component's vertices, the same for all of them (an unused vertex: its
  /// own id).  Computed on each call.
  std::vector<Index> ComponentRoots() const;
  /// One-line human description (triangles, components, genus, boundary
  /// loops, defects), e.g. for error messages.
  std::string Describe() const;

  /// One undirected edge at a vertex (VertexEdges): the vertex at its other
  /// end, the number of triangles using it (saturating at 255), the corners
  /// opposite it in the first two of those triangles (ascending; -1 if
  /// absent) and those triangles' positions in the vertex's list of corners
  /// (CornersBegin).
  struct VertexEdge
  {
    Index Neighbor;
    Index Opposite[2];
    Index Local[2];
    int Faces;
  };
  /// In a consistently oriented fan (pairs: RingPairsBegin(v), `valence`
  /// corners), the position of the corner across the edge that leaves
  /// corner a towards its next vertex: the corner whose previous vertex
  /// that is; `valence` if none.
  static Index CornerAcross(const Index* pairs, Index valence, Index a)
  {
    Index b = 0;
    while (b < valence && pairs[2 * b + 1] != pairs[2 * a])
    {
      ++b;
    }
    return b;
  }
  /// The edges at v, ascending by neighbour, into `edges` (the caller's
  /// workspace); thread-safe.  At regular vertices read off the fan (a sort
  /// of its few edges), elsewhere from the sorted half-edges.
  void VertexEdges(Index v, std::vector<VertexEdge>& edges) const;

  // ---- Neighbours and edges (built on first use) ----
  /// The 1-ring of every vertex, ascending (CSR): the graph of the
  /// Laplacians, without the edge table's other arrays (which on a
  /// 19M-triangle mesh take another 1 GB).
  struct VertexGraph
  {
    LargeVector<std::int64_t> NeighborOffsets; ///< size V+1
    IndexArray Neighbors;
  };
  const VertexGraph& Graph() const;
  struct EdgeTable
  {
    explicit EdgeTable(const VertexGraph& graph)
      : NeighborOffsets(graph.NeighborOffsets)
      , Neighbors(graph.Neighbors)
    {
    }
    IndexArray Vertices;                ///< 2 per edge, first < second
    IndexArray OppositeCorners;         ///< 2 per edge: corners opposite the edge, -1 if absent
    LargeVector<std::uint8_t> FaceCount;///< triangles using the edge (saturates at 255)
    const LargeVector<std::int64_t>& NeighborOffsets; ///< Graph()'s: CSR per vertex, size V+1
    const IndexArray& Neighbors;        ///< Graph()'s: 1-ring vertices, ascending
    LargeVector<std::int64_t> NeighborEdges; ///< edge joining v and Neighbors[k]
    std::int64_t NumberOfEdges() const { return static_cast<std::int64_t>(FaceCount.size()); }
    /// The edge joining vertices a and b (either order; -1: none).
    std::int64_t Find(Index a, Index b) const;
  };
  const EdgeTable& Edges() const;
  /// The thread count given at construction (resolved).
  int NumberOfThreads() const { return NumThreads; }

private:
  void Classify();

  Index NumVertices = 0;
  Index DroppedTriangles = 0;
  int NumThreads = 0;
  IndexArray Triangles;
  IndexArray OriginalIds;
  LargeVector<std::int64_t> CornerOffsets;
  IndexArray VertexCorners;
  IndexArray RingPairs;
  LargeVector<std::uint8_t> Flags;
  IndexArray BoundaryNextVertex;
  TopologySummary Info;

  mutable std::once_flag GraphOnce, EdgesOnce;
  mutable std::unique_ptr<VertexGraph> GraphData;
  mutable std::unique_ptr<EdgeTable> EdgeData;
};

} // namespace beltrami
