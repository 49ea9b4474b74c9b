// Beltrami core: how far a map of a triangle surface into the plane (2
// doubles per vertex) is from the surface (3 doubles per vertex): per-triangle
// angle, area and edge distortion, flipped triangles, and the energies of
// thesis section 5.5 with their gradients.  Used by the parameterization
// (its reports, the optimal mix and the boundary optimisation) and by any
// map that needs to judge a chart.
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"

#include <vector>

namespace beltrami
{

/// Energies of section 5.5 (both are used with the map scaled so that its
/// total area equals the surface's, which makes them independent of units).
enum class DistortionEnergy : int
{
  EdgeLength = 0, ///< sum over edges (|u_i - u_j|^2 / |x_i - x_j|^2 - 1)^2
  Area = 1        ///< sum over triangles ((A_2D / A_3D)^2 - 1)^2
};

struct DistortionReport
{
  std::vector<double> AngleDistortion; ///< per triangle: mean |angle_2D - angle_3D| (degrees)
  std::vector<double> AreaDistortion;  ///< per triangle: log((A_2D/sum A_2D) / (A_3D/sum A_3D))
  std::vector<double> EdgeDistortion;  ///< per triangle: mean |log(|e_2D| / (s |e_3D|))|, s^2 = sum A_2D / sum A_3D
  double MeanAngle = 0, MaxAngle = 0;  ///< over the triangles with a 3D area
  double MeanArea = 0, MaxArea = 0;    ///< of |AreaDistortion|
  double MeanEdge = 0, MaxEdge = 0;
  Index FlippedTriangles = 0;          ///< 2D signed area <= 0 (3D non-degenerate)
  Index DegenerateTriangles = 0;       ///< zero 3D area: left out of everything
};

/// Distortion of the map `uv` (2 per vertex) against the surface.  With
/// `split` (collective): the per-triangle values of every local triangle,
/// and the report's figures over the whole surface split over the processes
/// (each triangle counted once, Partition::CountsTriangle).
DistortionReport MeasureDistortion(const MeshTopology& topology, const double* points, const double* uv,
  int numThreads = 0, const Partition* split = nullptr);

/// The energies of section 5.5 for the map `uv` scaled by `scale`
/// (u -> scale * u), and their gradients (2 per vertex) if `gradient` is not null.
double DistortionEnergyValue(const MeshTopology& topology, const double* points, const double* uv,
  double scale, DistortionEnergy energy, double* gradient = nullptr);

/// Signed area of triangle t in the parameter plane.
double SignedArea2D(const MeshTopology& topology, const double* uv, Index t);
/// Area of triangle t on the surface.
double Area3D(const MeshTopology& topology, const double* points, Index t);
/// Triangles that count: false when the 3D area is above the degeneracy
/// threshold of RingGeometry (DegenerateTolerance).
bool Degenerate3D(const MeshTopology& topology, const double* points, Index t);
/// Sums over all triangles of the 3D areas and of the signed 2D areas.
double TotalArea3D(const MeshTopology& topology, const double* points, int threads);
double TotalArea2D(const MeshTopology& topology, const double* uv, int threads);
/// Triangles with a 3D area whose 2D signed area is not positive.
Index CountFlipped(const MeshTopology& topology, const double* points, const double* uv);

/// Calls visit(i, j, |x_i - x_j|^2) for every edge of non-zero length.
template <typename Visit>
void ForEachEdge(const MeshTopology& topo, const double* points, Visit&& visit)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    const Index i = edges.Vertices[2 * e], j = edges.Vertices[2 * e + 1];
    const double xx = (Point(points, i) - Point(points, j)).squaredNorm();
    if (xx > 0.0)
    {
      visit(i, j, xx);
    }
  }
}

/// Calls visit(t, 3D area) for every triangle with a 3D area.
template <typename Visit>
void ForEachTriangle(const MeshTopology& topo, const double* points, Visit&& visit)
{
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    if (!Degenerate3D(topo, points, t))
    {
      visit(t, Area3D(topo, points, t));
    }
  }
}

} // namespace beltrami
