// Beltrami core: interactive use of a kept boundary basis (thesis section
// 5.4.2): boundary vertices dragged to new places ("handles"), the rest of
// their loops following, and the map recomputed from the basis alone.
#pragma once
#include "Maps/Parameterization.h"
#include "Mesh/MeshTopology.h"
#include <string>
#include <vector>

namespace beltrami
{
struct BoundaryHandle
{
  Index Vertex = -1;  ///< a vertex of the basis' fixed boundary
  double Target[2] = { 0.0, 0.0 };
};

/// The map (uv, 2 per vertex) of `basis` for the boundary of `solvedUV` (2
/// per vertex: the map the basis came with) with its handles moved: each
/// handle's vertex goes to its target; the other vertices of a boundary loop
/// with handles move by the handles' displacements interpolated by arc
/// length (in 3D, `points`) between the handles before and after them along
/// the loop (one handle: the loop is translated); loops without handles stay.
/// Returns an error sentence (uv untouched), empty on success: a handle off
/// the fixed boundary, or with a target that is not finite.
std::string MoveBoundaryHandles(const MeshTopology& topology, const double* points, const BoundaryBasis& basis,
  const std::vector<double>& solvedUV, const std::vector<BoundaryHandle>& handles, std::vector<double>& uv);
} // namespace beltrami
