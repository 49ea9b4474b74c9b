// Beltrami core: the optimisation of a remesh (thesis sections 4.4.2-4.4.4)
// with its vertices kept, in two passes.  Chart rounds: edge swaps inside
// charts that bring valences to 6 (on the surface's boundary one more than
// the vertex's angle in sixties: 4 on a straight stretch) and improve
// the triangles' area/perimeter^2 ratio in 3D, alternated with a relaxation
// of the vertices in their chart's parameter plane: Lloyd's step, each
// vertex to the centroid of its Voronoi cell (the mixed areas of section 2.3
// in every triangle) with the density of the triangle's 3D area times its
// importance per unit of plane area, so that the cells become equal in area
// (or in importance integral for an adapted mesh; the thesis'
// area-dispersion weights of 4.4.3 in Lloyd's form, which measured better:
// valence 6 at 80% against 75%), vertices on chart boundaries sliding along
// their path by the tangential part of the same relaxation across the seam
// (fig. 4.10), on the surface's boundary towards the middle of their
// neighbours there, corners fixed; each move over-relaxed (past the
// centroid, OverRelaxation) but along paths; every move and swap keeps all triangles
// positively oriented in their chart's parameter plane.  Stitching rounds
// (section 4.4.4) then free the seams: the same swaps over every edge and
// Lloyd's step in 3D on the surface itself (each triangle's Voronoi part in
// its own plane, the move made tangential and put back on the input
// surface at the nearest point), so the triangles of close chart corners
// and the ears along seams get repaired; only samples on the surface's
// boundary and on feature edges stay on their paths, and corners on them
// stay fixed.  Every stitching move and swap keeps the triangles within 60
// degrees of their neighbourhood's normal and none facing against the
// input (no fold); faces that do already (a lifted chart map far from
// linear at the spacing) are unfolded by the swaps and moves that leave
// fewer such, each vertex of one moving towards the middle of its
// neighbours.  The relaxation runs
// colour by colour (no two neighbours share a colour), each colour's moves
// in parallel: the same mesh for any thread count.  A last swap pass
// mends the triangles with an angle below 30 degrees that the last
// relaxation left where a swap raises their area/perimeter^2 ratio, and a
// few rounds move the free vertices of triangles below 20 degrees towards
// the middle of their neighbours where that raises the smallest angle
// around them (the fans at tips thinner than the spacing), swapping again.
#pragma once

#include "Remeshing/Remesh.h"

#include <array>

namespace beltrami
{

struct RemeshOptimizationOptions
{
  /// Chart rounds of (swaps, relaxation).
  int Iterations = 5;
  /// Stitching rounds of (swaps, relaxation) after them.
  int StitchingIterations = 20;
  /// Each relaxation move first tries this multiple of the way to its
  /// centroid (over-relaxed Lloyd: 1.8 reaches in 25 rounds better meshes
  /// than plain Lloyd, 1, in 50); moves along paths stay plain (over-relaxed,
  /// they left triangles of 9.5-12.5 degrees at fandisk's sharp corners).
  double OverRelaxation = 1.8;
  /// One value >= 0 per input vertex weighting the relaxation (null: uniform).
  const double* Importance = nullptr;
  /// The anisotropic mode: a metric per input vertex (6 numbers, as
  /// Remeshing/RemeshMetric's; null: none).  Swaps, slivers and the
  /// relaxation (Lloyd's step in the metric frozen at the vertex: the
  /// anisotropic centroidal Voronoi tessellation of Du and Wang) measure
  /// edges and angles in it.
  const double* Metric = nullptr;
  /// One flag per edge of topology.Edges(): feature edges (sharp or marked)
  /// whose samples stay on their paths while stitching (null: none).
  const std::uint8_t* FeatureEdges = nullptr;
  /// One flag per surface vertex: vertices the sampling pinned
  /// (SamplingOptions::PinnedVertices), whose corners on the boundary stay
  /// (null: none).
  const std::uint8_t* PinnedVertices = nullptr;
  /// The sampling's bound on the chords of the surface's boundary
  /// (SamplingOptions::MaximumLineSag), which the corners moved along it
  /// keep (Optimizer::RoundRimCorners).
  double MaximumLineSag = 0.05;
  int NumberOfThreads = 0; ///< for the relaxation (by colours: the same result for any count)
  RemeshCache* Cache = nullptr; ///< optional: the charts' locators kept between calls
};

struct RemeshOptimizationStatistics
{
  std::int64_t ValenceSwaps = 0, ShapeSwaps = 0;
  std::int64_t FoldSwaps = 0; ///< stitching swaps that unfolded faces (Folded)
  double MeanDisplacement = 0.0; ///< of the vertices in the last relaxation, in 3D (the surface's units)
  Index FreedVertices = 0;  ///< chart-boundary samples that moved freely while stitching
};

RemeshOptimizationStatistics OptimizeRemesh(Remesh& remesh, const MeshTopology& topology, const double* points,
  const AtlasResult& atlas, const SurfaceSamples& samples, const RemeshOptimizationOptions& options = {});

/// The fidelity rounds' move (RemeshOptions::FarPinRounds), after
/// A point of the input a remesh vertex is pinned on (PinNearestVertices):
/// input vertex `Vertex`, or (Vertex < 0) the point at barycentric `W` of
/// input triangle `Triangle` (on a crease the remesh cuts); `Face`: the
/// remesh face nearest to it.
struct PinTarget
{
  Index Vertex = -1;
  Index Triangle = -1;
  std::array<double, 3> W = { 0.0, 0.0, 0.0 };
  Index Face = -1;
};

/// OptimizeRemesh: for each of `targets` (the farthest first) the free
/// vertex of its face or their neighbours nearest to it moves exactly onto
/// it and stays there, as the sampling pins one
/// (a Tip), where no face around it folds or turns by 90
/// degrees; those on one input edge of a crease are joined by an edge along
/// it, which the swaps keep (a coarse input's creases, 1.6 spacings long
/// around a needle's flat ends at 10,000 vertices: 0.102% of the diagonal
/// from the remesh without the joins, 0.044% with them); then `rounds`
/// stitching rounds settle the vertices around them and the slivers are
/// mended.
struct PinnedVertices
{
  std::vector<Index> Reached; ///< the input vertices of `targets` a vertex was moved onto
  Index ReachedPoints = 0;    ///< the other targets a vertex was moved onto
  Index Unreached = 0;        ///< the input vertices of `targets` none could be moved onto
};
PinnedVertices PinNearestVertices(Remesh& remesh, const MeshTopology& topology, const double* points,
  const AtlasResult& atlas, const SurfaceSamples& samples, const std::vector<PinTarget>& targets,
  const RemeshOptimizationOptions& options, int rounds);

} // namespace beltrami
