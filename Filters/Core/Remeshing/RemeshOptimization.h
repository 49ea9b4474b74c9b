// Beltrami core: the optimisation of a remesh (thesis sections 4.4.2-4.4.4)
// with its vertices kept: edge swaps inside charts that bring valences to 6
// (4 on the surface's boundary) and improve the triangles' area/perimeter^2
// ratio in 3D, alternated with a relaxation of the vertices in their chart's
// parameter plane: Lloyd's step, each vertex to the centroid of its Voronoi
// cell (the mixed areas of section 2.3 in every triangle) with the density
// of the triangle's 3D area times its importance per unit of plane area, so
// that the cells become equal in area (or in importance integral for an
// adapted mesh; the thesis' area-dispersion weights of 4.4.3 in Lloyd's
// form, which measured better: valence 6 at 80% against 75%), vertices on chart boundaries sliding along
// their path by the tangential part of the same relaxation across the seam
// (fig. 4.10), corners fixed.  Every move and swap keeps all triangles
// positively oriented in their chart's parameter plane.
#pragma once

#include "Remeshing/Remesh.h"

namespace beltrami
{

struct RemeshOptimizationOptions
{
  /// Rounds of (swaps, relaxation).
  int Iterations = 50;
  /// One value >= 0 per input vertex weighting the relaxation (null: uniform).
  const double* Importance = nullptr;
};

struct RemeshOptimizationStatistics
{
  std::int64_t ValenceSwaps = 0, ShapeSwaps = 0;
  double MeanDisplacement = 0.0; ///< of the vertices in the last relaxation, in 3D (the surface's units)
};

RemeshOptimizationStatistics OptimizeRemesh(Remesh& remesh, const MeshTopology& topology, const double* points,
  const AtlasResult& atlas, const SurfaceSamples& samples, const RemeshOptimizationOptions& options = {});

} // namespace beltrami
