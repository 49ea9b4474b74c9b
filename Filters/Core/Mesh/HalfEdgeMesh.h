// Beltrami core: an editable triangle mesh for the remesher of thesis
// chapter 4 (edge flips, vertex moves with the topology kept, charts cut
// out as submeshes with a vertex map).  MeshTopology stays the immutable,
// fast structure every operator reads; this one converts to and from it.
//
// Half-edges are the corners of the triangle list: half-edge h = 3 f + k of
// face f runs from the vertex of corner k to the vertex of corner k + 1, so
// Next, Prev and Face are arithmetic and the triangle list is the mesh.
// Stored besides: the opposite half-edge (Twin, -1 on the boundary) and one
// outgoing half-edge per vertex (the boundary one for boundary vertices, -1
// for unused vertices), so that a vertex's fan is walked counter-clockwise
// from it.  Only manifold, consistently oriented meshes are represented.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"

#include <string>
#include <vector>

namespace beltrami
{

class HalfEdgeMesh
{
public:
  HalfEdgeMesh() = default;

  /// Builds the mesh of `topology` (its kept triangles) with `points` (3
  /// per vertex); false with a sentence in `error` unless the topology is
  /// manifold and consistently oriented.
  static bool FromTopology(const MeshTopology& topology, const double* points, HalfEdgeMesh& mesh,
    std::string& error);

  Index NumberOfVertices() const { return static_cast<Index>(VertexEdge.size()); }
  Index NumberOfFaces() const { return static_cast<Index>(Tri.size() / 3); }
  Index NumberOfHalfEdges() const { return static_cast<Index>(Tri.size()); }

  static Index Next(Index h) { return MeshTopology::Next(h); }
  static Index Prev(Index h) { return MeshTopology::Prev(h); }
  static Index Face(Index h) { return h / 3; }
  Index Tail(Index h) const { return Tri[h]; }
  Index Head(Index h) const { return Tri[Next(h)]; }
  Index Twin(Index h) const { return Opposite[h]; }
  bool IsBoundary(Index h) const { return Opposite[h] < 0; }
  /// An outgoing half-edge of v: the boundary one if v is on the boundary;
  /// -1 if v is in no face.
  Index OutgoingHalfEdge(Index v) const { return VertexEdge[v]; }
  bool IsBoundaryVertex(Index v) const { return VertexEdge[v] >= 0 && IsBoundary(VertexEdge[v]); }
  /// The next outgoing half-edge counter-clockwise around Tail(h); -1 past
  /// the last one of a boundary vertex.
  Index RotateCounterClockwise(Index h) const { return Opposite[Prev(h)]; }
  /// Calls visit(h) for every outgoing half-edge of v, counter-clockwise.
  template <typename Visit>
  void ForEachOutgoing(Index v, Visit&& visit) const
  {
    const Index start = VertexEdge[v];
    // A fan has at most as many half-edges as the mesh: the bound keeps a
    // corrupted mesh from looping (CheckConsistency reports it).
    Index left = NumberOfHalfEdges();
    for (Index h = start; h >= 0 && left-- > 0;)
    {
      visit(h);
      h = RotateCounterClockwise(h);
      if (h == start)
      {
        break;
      }
    }
  }
  /// The half-edge from a to b, or -1.
  Index FindHalfEdge(Index a, Index b) const;
  Index Valence(Index v) const;

  Vec3 Position(Index v) const { return Point(Positions.data(), v); }
  /// Moves a vertex; the connectivity is kept.
  void SetPosition(Index v, const Vec3& p);
  const std::vector<double>& Points() const { return Positions; }

  /// An interior edge whose flip would not create an edge that exists.
  bool CanFlip(Index h) const;
  /// Replaces the edge of h (between faces (a, b, c) and (b, a, d)) by the
  /// edge c-d, keeping the orientation; false (nothing changed) if it cannot.
  bool FlipEdge(Index h);

  /// The triangle list (3 vertex ids per face) and a MeshTopology of it.
  const std::vector<Index>& Triangles() const { return Tri; }
  MeshTopology ToTopology(int numThreads = 0) const;

  /// The faces with keep[f] != 0 as a mesh of their own; vertexMap[new] =
  /// old vertex id (ascending).  False with `error` if the faces do not form
  /// a manifold (e.g. two fans meeting at one vertex).
  bool ExtractFaces(const std::vector<std::uint8_t>& keep, HalfEdgeMesh& part, std::vector<Index>& vertexMap,
    std::string& error) const;

  /// Empty if every invariant holds (twins, tails and heads, vertex
  /// half-edges, boundary half-edges of boundary vertices); else the first
  /// violation.  For tests and debugging.
  std::string CheckConsistency() const;

private:
  std::vector<Index> Tri;        ///< corner -> vertex
  std::vector<Index> Opposite;   ///< half-edge -> twin, -1 on the boundary
  std::vector<Index> VertexEdge; ///< vertex -> outgoing half-edge
  std::vector<double> Positions; ///< 3 per vertex

  /// Sets v's outgoing half-edge from any outgoing one: turned clockwise to
  /// the boundary half-edge if v is on the boundary.
  void AnchorVertex(Index v, Index outgoing);
};

} // namespace beltrami
