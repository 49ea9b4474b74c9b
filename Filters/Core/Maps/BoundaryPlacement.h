// Beltrami core: the boundary of a map into the plane: which loop is the
// outer one, and where its vertices go on a circle or a square (thesis
// sections 5.3 and 4.2.2), spaced like the loop or uniformly.
#pragma once

#include "Mesh/Geometry.h"

#include <vector>

namespace beltrami
{

enum class ParameterizationBoundary : int
{
  Circle = 0,  ///< outer loop on the circle of centre (0.5, 0.5), radius 0.5
  Square = 1,  ///< outer loop on [0,1]^2, corners at the quarters of its length
  Given = 2,   ///< every boundary vertex at the caller's position (GivenUV)
  Natural = 3  ///< natural boundaries (eq. 5.7), conformal energy only
};

enum class BoundarySpacing : int
{
  ArcLength = 0, ///< spacing proportional to the 3D edge lengths along the loop
  Uniform = 1    ///< equal spacing
};

/// Length of a closed loop of vertices.
double LoopLength(const std::vector<Index>& loop, const double* points);
/// The index of the longest loop (the outer boundary); 0 if there is none.
std::size_t LongestLoop(const std::vector<std::vector<Index>>& loops, const double* points);
/// Writes the positions (u, v at 2 v, 2 v + 1 of uv) of the vertices of
/// `loop`, counter-clockwise (the loop runs with the surface on its left),
/// on the circle of centre (0.5, 0.5) and radius 0.5 or on [0,1]^2 (`shape`
/// Circle or Square; a square needs at least 4 vertices: its corners are the
/// vertices nearest to the quarters of the length).
void PlaceBoundaryLoop(const std::vector<Index>& loop, const double* points,
  ParameterizationBoundary shape, BoundarySpacing spacing, double* uv);

} // namespace beltrami
