// Beltrami core: paths along the edges of a triangle mesh.
#pragma once
#include "Mesh/MeshTopology.h"

#include <vector>

namespace beltrami
{
/// The shortest path along mesh edges (3D edge lengths, `points`: 3 per
/// vertex) from vertex `from` to vertex `to`, both ends included, in order
/// (Dijkstra); empty when no edge path joins them or an end is not a vertex.
std::vector<Index> ShortestEdgePath(const MeshTopology& topology, const double* points, Index from, Index to);
} // namespace beltrami
