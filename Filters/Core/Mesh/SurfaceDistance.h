// Beltrami core: distances from points to a triangle surface through a
// uniform grid of its triangles, and the two-sided deviation of one
// surface from another (a Hausdorff distance estimated at the vertices,
// edge midpoints and triangle centres of each): what the remesher reports
// of its own fidelity.
#pragma once

#include "Mesh/Geometry.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace beltrami
{

/// The triangles of a surface in a uniform grid of about two triangles a
/// cell (their bounding boxes' cells), for nearest-point queries.
class TriangleGrid
{
public:
  /// `points`: 3 per vertex; `triangles`: 3 vertex ids each.
  TriangleGrid(const double* points, const Index* triangles, std::size_t numberOfTriangles, int numThreads = 0);
  /// The distance from p to the nearest triangle (infinity when there is
  /// none, or p is not finite).
  double Distance(const Vec3& p) const;
  /// The nearest triangle to p (-1 where Distance is infinite), its
  /// distance in `distance`; with `within`, only a triangle nearer than
  /// that (-1 and `within` where none is: a search that stops there).
  Index Nearest(const Vec3& p, double& distance, double within = HUGE_VAL) const;
  /// The distance from p to triangle t (of the triangles given): a bound on
  /// Distance(p) without a search.
  double DistanceTo(Index t, const Vec3& p) const { return std::sqrt(TriangleDistance2(t, p)); }

private:
  const double* Points;
  const Index* Triangles;
  Vec3 Origin = Vec3::Zero();
  double Cell = 1.0;
  long Dims[3] = { 0, 0, 0 };
  std::vector<std::uint32_t> Offsets; ///< per cell into Items (CSR)
  std::vector<Index> Items;         ///< triangle ids
  long CellIndex(const Vec3& p, int axis) const;
  double TriangleDistance2(Index t, const Vec3& p) const;
  /// The squared distance from p to the bounding box of triangle t (no
  /// more than TriangleDistance2).
  double BoundsDistance2(Index t, const Vec3& p) const;
  /// The squared distance from p to the box of cell (x, y, z).
  double BoxDistance2(const Vec3& p, long x, long y, long z) const;
};

/// Where a surface's distance to another is measured.
enum class DeviationSamples
{
  Vertices, ///< its used vertices (a surface whose vertices lie on the other: 0)
  Centres,  ///< its triangles' centres (where a triangle spanning a gap is far)
  Both,
  Midpoints, ///< its triangles' centres and edges' midpoints (an edge across a crease)
  All        ///< its vertices, edges' midpoints and triangles' centres
};

/// The midpoint of a triangle's edge k (corners k and k + 1) for k < 3,
/// its centre for k = 3: where a deviation between its corners is measured.
Vec3 TriangleSample(const Vec3* corner, int k);

/// How far two surfaces are apart, each way: the largest distance from a
/// sample of one to the other (absolute units).
struct SurfaceDeviation
{
  double FirstToSecond = 0.0;
  double SecondToFirst = 0.0;
  Vec3 FarthestOfFirst = Vec3::Zero();  ///< the point of the first farthest from the second
  Vec3 FarthestOfSecond = Vec3::Zero(); ///< and the other way
};

/// The largest distance from the samples of a surface (`points`, `count`
/// `triangles`: its used vertices, its triangle centres, or both) to the
/// surface of `to`, and the sample where it is.
double FarthestFrom(const double* points, const Index* triangles, std::size_t count, DeviationSamples samples,
  const TriangleGrid& to, int numThreads, Vec3& where);

SurfaceDeviation MeasureDeviation(const double* firstPoints, const Index* firstTriangles, std::size_t firstCount,
  DeviationSamples firstSamples, const double* secondPoints, const Index* secondTriangles, std::size_t secondCount,
  DeviationSamples secondSamples, int numThreads = 0);

/// The length of the bounding-box diagonal of the vertices used by the
/// triangles (finite ones).
double UsedBoundingBoxDiagonal(const double* points, const Index* triangles, std::size_t numberOfTriangles);

} // namespace beltrami
