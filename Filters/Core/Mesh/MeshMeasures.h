// Beltrami core: global measures of a triangle surface (3 doubles per
// point): enclosed volume (eq. 3.10), area, the volume above a plane (the
// invariants of section 3.3.1), their centroids, the mean edge length
// (the unit of time steps and of the data scale of the graph flows), and
// the sharp edges.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

/// The length unit of the settings of the smoothing flows (time steps,
/// feature thresholds, the data scale of the graph flows): the mean edge
/// length of the input (the same settings then suit meshes of any size) or
/// the mesh's own units.
enum class LengthUnit : int
{
  MeanEdgeLength = 0,
  Physical = 1
};

/// Volume enclosed by a closed oriented triangle mesh (eq. 3.10), total area,
/// and the volume between the surface and the plane through `origin` with unit
/// normal `normal` (the surface projected on the plane times its height).
double EnclosedVolume(const MeshTopology& topology, const double* points, int numThreads = 0);
/// A point inside each cavity of a closed oriented surface (TetGen's hole
/// list): a component whose enclosed volume has the sign opposite to the
/// whole surface's is a wall facing into a void within the solid (a hollow
/// ball's inner sphere); its point lies off the middle of its largest
/// triangle on the side the triangle faces, half way to the nearest other
/// triangle there at most (none where the surface encloses no volume).
std::vector<Vec3> CavityPoints(const MeshTopology& topology, const double* points);
/// Empty where the coordinates of the vertices used by triangles are finite
/// and within the range whose products the geometry can form (magnitudes
/// and a bounding box within 1e-75 to 1e75 units: areas and cotangents
/// multiply four coordinates), and not all equal; else a sentence that
/// says what is wrong.
std::string CoordinateRangeProblem(const MeshTopology& topology, const double* points);
/// Mean length of the edges (the natural unit of time steps: lambda*dt ~ h^2);
/// edges at NaN or infinite points are left out (0 when none is left).
/// split (optional, collective): a surface split over processes, each edge
/// counted by the owner of its end of lower global row.
double MeanEdgeLength(const MeshTopology& topology, const double* points, const Partition* split = nullptr);
double SurfaceArea(const MeshTopology& topology, const double* points, int numThreads = 0);
/// 1 per edge of topology.Edges() whose two triangles' normals differ by
/// more than `angleDegrees` (the dihedral test of thesis section 4.2.3, like
/// vtkFeatureEdges' FeatureAngle); boundary and non-manifold edges: 0, and
/// the edges of triangles turned over (a dihedral angle above MostFoldAngle
/// at two of their edges or three: a fold of the input, not a crease).  A
/// cap (a triangle with an angle above MostCapAngle) has no normal of its
/// own (it turns with the slightest move of its middle corner:
/// cylinder_locally_refined's three caps of 174-179 degrees made sharp
/// edges, and charts, of their own): it takes the normal of the triangle
/// across its long edge, the side of the surface it lies on.  A decimated
/// CAD part has caps along its creases, lying in the crease: their two short
/// edges are the crease (fandisk decimated to a tenth: 68 of its 312 crease
/// edges, whose remesh cut across them 0.45% of the diagonal from the input
/// where they were left out).
std::vector<std::uint8_t> SharpEdges(const MeshTopology& topology, const double* points, double angleDegrees);
constexpr double MostCapAngle = 170.0;
constexpr double MostFoldAngle = 150.0;
/// Joins the fragments of a crease that the mesh's edges cross at a slant
/// (sharp on only some of its edges): from each end of a feature chain (a
/// vertex with one feature edge of `features`, 1 per edge of
/// topology.Edges()), along the sharpest edge above `weakAngleDegrees` at
/// each vertex (never back to a vertex of the path), the path is added
/// where it reaches the end of another line within a length of
/// `longestGap`: hysteresis, as Canny's edge detector links its weak edges
/// to its strong ones.  Not to the middle of a line, nor back to its own:
/// the fragments often lie in two rows side by side, and a path between
/// them would make a junction or a loop.  (fandisk_large's 689 edges above
/// 60 degrees have 419 ends; joined over paths above 30 degrees no longer
/// than the spacing of 2,000 vertices, 137.)  Returns the number of edges
/// added.
std::int64_t BridgeFeatureGaps(const MeshTopology& topology, const double* points, double weakAngleDegrees,
  double longestGap, std::vector<std::uint8_t>& features);
/// Extends each dangling feature line of `features` (1 per edge of
/// topology.Edges(); an end: a vertex with one feature edge) where its
/// crease fades out: along the sharpest edge above `weakAngleDegrees` at
/// each vertex that turns the line by at most `mostTurnDegrees`, up to the
/// first edge below that angle or a vertex of another line (hysteresis:
/// the weak edges that continue a strong line are part of it).  fandisk's
/// crease that ends at 60 degrees runs on for seven edges, its dihedral
/// angle falling by about 4 degrees an edge to 30; a remesh whose line
/// stopped at 60 cut it there by 0.17 of its spacing at 10,000 vertices.
/// Returns the number of edges added.
std::int64_t ExtendFeatureEnds(const MeshTopology& topology, const double* points, double weakAngleDegrees,
  double mostTurnDegrees, std::vector<std::uint8_t>& features);
/// Drops from `features` (1 per edge of topology.Edges()) the dangling
/// chains shorter than `minimumLength`: runs of feature edges from an end
/// (a vertex with one feature edge) to the next vertex with other than two,
/// repeated while a drop leaves new ends.  Closed lines and networks stay.
/// Returns the number of edges dropped.
std::int64_t DropShortFeatureChains(
  const MeshTopology& topology, const double* points, double minimumLength, std::vector<std::uint8_t>& features);
double VolumeAbovePlane(const MeshTopology& topology, const double* points, const double origin[3],
  const double normal[3], int numThreads = 0);


/// The quality figures of a triangle mesh (the remesher's targets, thesis
/// chapter 4): angles of its triangles, valences of its interior vertices,
/// regularity of its edge lengths.
struct TriangleQuality
{
  double MeanMinimumAngle = 0.0;    ///< degrees: mean over the triangles of their smallest angle
  double MinimumAngle = 0.0;        ///< degrees: the smallest angle of all
  double MaximumAngle = 0.0;        ///< degrees: the largest angle of all
  double FractionBelow30 = 0.0;     ///< of the triangles, with an angle below 30 degrees
  double FractionValence6 = 0.0;    ///< of the interior vertices, of valence 6
  double EdgeLengthVariation = 0.0; ///< standard deviation / mean of the edge lengths
  Index DegenerateTriangles = 0;    ///< of zero area (or non-finite points)
};
TriangleQuality MeasureTriangleQuality(const MeshTopology& topology, const double* points);

/// The bounding box of the used vertices (valence > 0) with finite
/// coordinates; empty when there are none.
template <typename T>
Eigen::AlignedBox3d UsedPointsBox(const MeshTopology& topology, const T* points);

/// The power of two e that brings a box far from unit size near 1 (its
/// extent or offset beyond 2^+-60, where squared areas overflow or vanish:
/// computations there run on the points times 2^-e, exactly, and scale
/// their results back), else 0 (and for an empty box).
int FarScaleExponent(const Eigen::AlignedBox3d& box);
/// 3 * numberOfVertices coordinates times 2^exponent (exact), in double precision.
template <typename T>
std::vector<double> PointsTimesPowerOfTwo(const T* points, Index numberOfVertices, int exponent);
/// values[0 .. count) times 2^exponent, in place (nothing when values is null).
void TimesPowerOfTwo(double* values, std::size_t count, int exponent);

/// The mean of the points of used vertices (valence > 0, finite).
Vec3 VertexCentroid(const MeshTopology& topology, const double* points);
/// The enclosed volume (relative to the vertex centroid, for accuracy) and,
/// if `centroid` is given, the centroid of the enclosed solid.  With
/// `origin`: relative to it instead (the signed volume of the cones from it
/// over the triangles; on part of a closed surface, a share that adds up to
/// the volume over all parts measured from the same origin).
double VolumeAndCentroid(const MeshTopology& topology, const double* points, int numThreads, Vec3* centroid,
  const Vec3* origin = nullptr);
/// The total area and, if `centroid` is given, the area centroid.
double AreaAndCentroid(const MeshTopology& topology, const double* points, int numThreads, Vec3* centroid);
/// VolumeAbovePlane with a unit normal.
double HeightVolume(const MeshTopology& topology, const double* points, const Vec3& origin,
  const Vec3& normal, int numThreads);
/// The volume between the surface and the axis through `origin` along the
/// unit `axis` (a surface of revolution, open or closed: the flux of half the
/// radial position, whose divergence is 1 and whose flux through the end
/// disks is 0).  Signed by the orientation (positive for outward normals).
double RevolutionVolume(const MeshTopology& topology, const double* points, const Vec3& origin,
  const Vec3& axis, int numThreads);

} // namespace beltrami
