// Beltrami core, private to Mesh/VectorFields: the triangles' frames, the
// stream function integrated across the triangles instead of solved, and
// the closed fields of a closed surface's handles that give its harmonic
// fields (Mesh/VectorFieldsIntegration.cxx).
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshTopology.h"
#include "Mesh/VectorFields.h"

#include <cstddef>
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

/// Whether the surface is manifold and oriented, without zero-area
/// triangles (`degenerate` of them), and every component a closed surface
/// of genus 0 or a disk (Euler characteristic 2 or 1; 2g + b - 1 harmonic
/// fields with b boundary loops, 2g closed): no harmonic fields.
/// `component`: per vertex, its component's id (a vertex id).
bool NoHarmonicFields(const MeshTopology& topology, const std::vector<Index>& component, Index degenerate);

/// Whether the surface is closed, manifold and oriented, without zero-area
/// triangles: its harmonic fields are those of its handles (HandleFields).
bool ClosedWithoutDegenerateTriangles(const MeshTopology& topology, Index degenerate);

/// The stream function v (one value per edge) of `rest` (3 per triangle),
/// a field with no curl-free and no harmonic part (X - grad u, less its
/// harmonic part where there is one): grad v = J^T rest = -n x rest on
/// each triangle, integrated from edge midpoint to edge midpoint, breadth
/// first over the triangles of each component from one edge.  On a
/// component with a boundary where the stream function is fixed there
/// (TangentDivergenceFree) from a boundary edge at 0, the boundary's edges
/// then set to 0 (the integration gives them 0 to the solves' accuracy);
/// otherwise from any edge, then zero mean.
std::vector<double> IntegrateStreamFunction(const MeshTopology& topology, const double* points,
  const TriangleFrames& frames, const EdgeGraph& graph, VectorFieldBoundary boundary,
  const std::vector<double>& rest);

/// On a closed, manifold, oriented surface: one field per triangle (3 per
/// triangle) for each of the 2g handles' cycles of its components (g the
/// genus), whose harmonic parts span its harmonic fields.  A tree-cotree
/// decomposition (a spanning forest of the edges, then one of the
/// triangles across the other edges; Eppstein 2003) leaves 2g edges; for
/// each, the closed 1-form that is 1 on it, 0 on the others left and on the
/// forest's edges, and on the triangles' forest's edges what makes it sum
/// to 0 around every triangle (solved from the leaves up), as the gradient
/// of the linear function on each triangle whose differences along its
/// sides it gives.  Such a field is curl-free and orthogonal to every
/// J grad v (along each edge its tangential part is shared by both
/// triangles, and v's jump has zero mean), but not a gradient: less its
/// curl-free part it is harmonic.  Empty where more than `most` edges are
/// left (the stream function is then solved).
std::vector<std::vector<double>> HandleFields(const MeshTopology& topology, const double* points,
  const TriangleFrames& frames, const EdgeGraph& graph, std::size_t most);

} // namespace beltrami::detail
