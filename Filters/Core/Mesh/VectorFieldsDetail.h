// Beltrami core, private to Mesh/VectorFields: the triangles' frames, the
// steps of the decomposition (Mesh/VectorFieldsParts.cxx), shared by the
// serial decomposer and the split one (Mesh/DistributedVectorFields.cxx),
// and the stream function integrated across the triangles instead of
// solved (Mesh/VectorFieldsIntegration.cxx).
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshTopology.h"
#include "Mesh/VectorFields.h"

#include <cstdint>
#include <vector>

namespace beltrami::detail
{

inline void Store(double* target, const Vec3& value)
{
  target[0] = value[0];
  target[1] = value[1];
  target[2] = value[2];
}

/// Vertex k of triangle t and the side opposite it: e_k = x_{k+2} - x_{k+1}
/// (counter-clockwise about the normal), the side of grad phi_k = n x e_k / 2A.
inline Vec3 Side(const double* points, const IndexArray& tri, Index corner)
{
  return Point(points, tri[MeshTopology::Prev(corner)]) - Point(points, tri[MeshTopology::Next(corner)]);
}

/// Per triangle: the unit normal and the area (0 for a zero-area triangle).
struct TriangleFrames
{
  std::vector<double> Normals; ///< 3 per triangle
  std::vector<double> Areas;
};

TriangleFrames MakeFrames(const MeshTopology& topo, const double* points, int threads);
/// Splits the input into its tangent part (r.Tangent) and normal component (r.Normal).
void ProjectToTangent(const TriangleFrames& f, const double* vectors, VectorFieldDecomposition& r, int threads);
/// The right-hand side of the potential's system, (X, grad phi_i) per
/// vertex; also the divergence and curl at the vertices (r.Divergence,
/// r.Curl: they share the loop over the corners).
std::vector<double> PotentialRightHandSide(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  int threads, VectorFieldDecomposition& r);
/// r.CurlFree = grad r.Potential per triangle.
void GradientPart(const MeshTopology& topo, const double* points, const TriangleFrames& f, int threads,
  VectorFieldDecomposition& r);
/// The right-hand side of the stream function's system, per edge.
std::vector<double> StreamRightHandSide(const MeshTopology& topo, const double* points, int threads,
  const VectorFieldDecomposition& r);
/// r.DivergenceFree = J grad r.StreamFunction per triangle.
void RotatedGradientPart(const MeshTopology& topo, const double* points, const TriangleFrames& f,
  const EdgeGraph& graph, int threads, VectorFieldDecomposition& r);
/// The harmonic remainder, the energies and the inner products (over the
/// triangles where `counted` is non-zero; null: all).
void HarmonicPart(const TriangleFrames& f, int threads, VectorFieldDecomposition& r, const std::uint8_t* counted = nullptr);
/// The rows of the points' system (`cotangent`, its stiffness) held at 0:
/// those without coupling, and where the boundary condition fixes the
/// potential, the boundary of what is decomposed (the surface's, and the
/// rims of the zero-area triangles, left out).  Right at the vertices whose
/// whole star `topo` holds.
std::vector<std::uint8_t> FixedVertices(
  const MeshTopology& topo, const TriangleFrames& f, const GraphLaplacian& cotangent, VectorFieldBoundary boundary);
/// The same for the edges' system (MeshTopology::Edges() order): edges in
/// three or more triangles too, and where the condition fixes the stream
/// function, the edges of one triangle with an area.  Right at the edges
/// whose triangles `topo` holds.
std::vector<std::uint8_t> FixedEdges(
  const MeshTopology& topo, const TriangleFrames& f, const GraphLaplacian& nonconforming, VectorFieldBoundary boundary);
/// The results of the points times 2^-e and the field times 2^-f back to
/// their scales.
void ScaleBack(int e, int f, VectorFieldDecomposition& r);

/// Whether the surface is manifold and oriented, without zero-area
/// triangles (`degenerate` of them), and every component a closed surface
/// of genus 0 or a disk (Euler characteristic 2 or 1; 2g + b - 1 harmonic
/// fields with b boundary loops, 2g closed): no harmonic fields.
/// `component`: per vertex, its component's id (a vertex id).
bool NoHarmonicFields(const MeshTopology& topology, const std::vector<Index>& component, Index degenerate);

/// Integrates grad v = J^T rest = -n x rest (`rest` 3 per triangle) from
/// edge midpoint to edge midpoint, breadth first over the triangles joined
/// by edges to triangle `start`, from v[first] (an edge of it, kept), into
/// `v` (per edge); marks the edges `known` and the triangles `visited`
/// (those already marked are not crossed again).  Returns the edges it set
/// (`first` too); the triangles it crossed in `triangles` (optional).
std::vector<Index> IntegrateAcross(const MeshTopology& topology, const double* points, const TriangleFrames& frames,
  const EdgeGraph& graph, const std::vector<double>& rest, Index start, Index first, std::vector<double>& v,
  std::vector<std::uint8_t>& known, std::vector<std::uint8_t>& visited, std::vector<Index>* triangles = nullptr);

/// The stream function v (one value per edge) of `rest` (3 per triangle),
/// a field with no curl-free and no harmonic part (X - grad u where there
/// are no harmonic fields): grad v = J^T rest = -n x rest on
/// each triangle, integrated from edge midpoint to edge midpoint, breadth
/// first over the triangles of each component from one edge.  On a
/// component with a boundary where the stream function is fixed there
/// (TangentDivergenceFree) from a boundary edge at 0, the boundary's edges
/// then set to 0 (the integration gives them 0 to the solves' accuracy);
/// otherwise from any edge, then zero mean.
std::vector<double> IntegrateStreamFunction(const MeshTopology& topology, const double* points,
  const TriangleFrames& frames, const EdgeGraph& graph, VectorFieldBoundary boundary,
  const std::vector<double>& rest);

} // namespace beltrami::detail
