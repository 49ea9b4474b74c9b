// Beltrami core: the repairs of a triangle surface that a user expects a
// geometry toolkit to make by itself (as VTK's normals and clean filters
// do), each reported so that the filter can say what it changed:
//   - coincident points merged: an unwelded triangle soup (STL files, meshes
//     split along texture seams) becomes one connected surface;
//   - edges of zero length collapsed: the coincident ends of an edge inside
//     the surface (a decimation's or marching cubes' leftovers) become one
//     point, and the triangles of no area beside the edge go;
//   - orientation made consistent: every component's triangles are turned to
//     agree with their neighbours across each manifold edge, closed
//     components facing outwards (positive enclosed volume), open ones
//     keeping the orientation of most of their triangles.
// Both work on a triangle list and leave the caller to rebuild the topology.
#pragma once

#include "Mesh/MeshTopology.h"

#include <vector>

namespace beltrami
{

/// Boundary points closer than this fraction of the bounding box's diagonal
/// (or than 8 units in the last place of the coordinates' type) are one:
/// the seam of a latitude-longitude grid whose points at 0 and 360 degrees
/// were computed with sines and cosines differs by 1e-16, and float data
/// computed in float by 1e-7.
constexpr double NearlyCoincident = 1e-10;

/// For every point, the point it is merged into (itself when kept): the
/// boundary points of `topology` that coincide (within NearlyCoincident,
/// joined transitively) map to the lowest id among them.  Points inside the
/// surface are never merged (a surface that touches itself stays as it is).
/// Empty when nothing is merged.  `merged` gets the number of points merged
/// away.
template <typename T>
std::vector<Index> CoincidentBoundaryPoints(const MeshTopology& topology, const T* points, Index& merged);

/// For every point, the point it is merged into (itself when kept): the two
/// ends of every edge of `topology` no longer than the coincidence tolerance
/// (NearlyCoincident: an edge collapsed in place, as decimations and
/// marching cubes at grid points leave them, with triangles of no area
/// beside it), where the collapse keeps the surface manifold: a manifold
/// edge whose ends have no common neighbours but the vertices opposite it
/// (the link condition), neither end in another collapse or on the
/// boundary.  Empty when none; `merged` gets their number.
template <typename T>
std::vector<Index> CollapsedEdges(const MeshTopology& topology, const T* points, Index& merged);

/// `triangles` with every vertex id replaced by merge[id] (merge as above).
IndexArray MergePoints(const IndexArray& triangles, const std::vector<Index>& merge);

/// The triangles (3 ids each in `triangles`) whose three vertices, in any
/// order, are those of an earlier triangle: their indices, ascending (a
/// triangle and its copy, as STL exports and careless merges leave).
std::vector<Index> RepeatedTriangles(const IndexArray& triangles);

/// Splits every pinched vertex, where separate fans of triangles meet at one
/// point (a scan with holes, a surface that touches itself at a corner),
/// into one vertex per fan: the first fan keeps the vertex, each other one
/// gets a new vertex (numbered from topology.NumberOfVertices() on).  An
/// edge of three or more triangles (a fin, a decimation's fold) joins none
/// of them: the surface is cut along it (`cutEdges` of them), and its ends
/// split.  `triangles` is the topology's triangle list (same order) with
/// those corners renumbered; the result gives, for every new vertex, the
/// vertex it copies (empty: nothing split).
std::vector<Index> SplitPinchedVertices(const MeshTopology& topology, IndexArray& triangles, Index& cutEdges);

/// What OrientConsistently did.
struct OrientationRepair
{
  Index FlippedTriangles = 0;
  Index NonOrientableComponents = 0; ///< components left as they were (e.g. a Moebius strip)
  bool Changed() const { return FlippedTriangles > 0; }
};

/// Turns triangles of `topology` (their order kept: vertices 1 and 2 swapped)
/// so that neighbours across every edge of two triangles agree.  Per
/// component: closed ones (no boundary edge) end with a positive enclosed
/// volume when `points` (3 doubles per point) are given, the others keep the
/// orientation of the majority of their triangles.  Components that cannot
/// be oriented are left as they are and counted.  `triangles` is the
/// topology's triangle list with the flips applied.
OrientationRepair OrientConsistently(const MeshTopology& topology, const double* points, IndexArray& triangles);

} // namespace beltrami
