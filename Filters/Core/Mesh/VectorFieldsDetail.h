// Beltrami core, private to Mesh/VectorFields: the triangles' frames and
// the stream function integrated across the triangles instead of solved
// (Mesh/VectorFieldsIntegration.cxx).
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshTopology.h"
#include "Mesh/VectorFields.h"

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
