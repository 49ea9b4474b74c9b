// Beltrami core: the boundary of a map into the plane: which loop is the
// outer one, and where its vertices go on a circle or a square (thesis
// sections 5.3 and 4.2.2), spaced like the loop or uniformly.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"

#include <array>
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

/// Where a square boundary puts its corners.
enum class SquareCorners : int
{
  QuarterLength = 0, ///< the vertices nearest to the quarters of the loop's length
  Sharpest = 1       ///< ChooseSquareCorners: the loop's sharpest turns, sides alike
};

enum class BoundarySpacing : int
{
  ArcLength = 0, ///< spacing proportional to the 3D edge lengths along the loop
  Uniform = 1    ///< equal spacing
};

/// Length of a closed loop of vertices.
double LoopLength(const std::vector<Index>& loop, const double* points);
/// The normalised parameter along a closed loop: t[k] for loop[k], t[0] = 0,
/// t[n] = 1 (back at loop[0]); by 3D edge lengths or uniform.
std::vector<double> LoopParameter(const std::vector<Index>& loop, const double* points, BoundarySpacing spacing);

/// The index of the longest loop (the outer boundary); 0 if there is none.
std::size_t LongestLoop(const std::vector<std::vector<Index>>& loops, const double* points);
/// Writes the positions (u, v at 2 v, 2 v + 1 of uv) of the vertices of
/// `loop`, counter-clockwise (the loop runs with the surface on its left),
/// on the circle of centre (0.5, 0.5) and radius 0.5 or on [0,1]^2 (`shape`
/// Circle or Square; a square needs at least 4 vertices: its corners are the
/// vertices nearest to the quarters of the length).
/// `corners` (Square only, optional): the positions in `loop` of the four
/// corners, ascending (ChooseSquareCorners), instead of the quarters.
void PlaceBoundaryLoop(const std::vector<Index>& loop, const double* points,
  ParameterizationBoundary shape, BoundarySpacing spacing, double* uv,
  const std::array<std::size_t, 4>* corners = nullptr);

/// The corners of a square for the boundary `loop` of `topology` (positions
/// in the loop, ascending): four vertices where the surface's angle (the sum
/// of its triangles' angles at the vertex) is smallest, traded against sides
/// of equal length, such that no triangle has its three vertices on one side
/// of the square (such a triangle would be flat: a vertex with a single
/// triangle, the tip of an ear, must be a corner).  When that cannot be met
/// (more than four such tips), the quarters of the length.
std::array<std::size_t, 4> ChooseSquareCorners(
  const MeshTopology& topology, const double* points, const std::vector<Index>& loop);

} // namespace beltrami
