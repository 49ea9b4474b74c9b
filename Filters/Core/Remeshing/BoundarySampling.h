// Beltrami core, inside the sampler: the chart boundaries as paths of
// surface vertices and their samples (Remeshing/BoundarySampling.cxx), for
// Remeshing/SurfaceSampling.cxx.
#pragma once

#include "Remeshing/SurfaceSampling.h"

#include <cstdint>
#include <vector>

namespace beltrami
{

/// The chart boundaries as paths of surface vertices between corners
/// (vertices where other than two boundary edges meet, where the path
/// passes from a kept edge, a feature or the surface's boundary, to another
/// edge, or where a kept line turns sharply (IsSharpTurn) or is pinned
/// (SamplingOptions::PinnedVertices); a closed loop without one starts and
/// ends at its first vertex, made a corner).
struct BoundaryPaths
{
  std::vector<std::vector<Index>> Paths;
  std::vector<Index> Corners;
};

/// The boundaries of the charts of `chartOfTriangle` (one per input
/// triangle) as BoundaryPaths; kept lines (`featureEdges` and the surface's
/// boundary) turning sharply, and `pinned` vertices (null: none) on a path,
/// are corners.
BoundaryPaths ChartBoundaries(const MeshTopology& topology, const double* points, const double* importance,
  const double* metric, double density, const std::vector<int>& chartOfTriangle, const std::uint8_t* featureEdges,
  const std::uint8_t* pinned);

/// The triangle with the edge (a, b) (b == a: one with the vertex a) and the
/// weights of the point at fraction t of the way from a to b.
Index EdgePoint(const MeshTopology& topology, Index a, Index b, double t, double* w);

/// The corners, then samples along every path at the spacing of the density
/// (1D error diffusion: samples where the integral of sqrt(density) passes
/// even fractions of it; a closed loop keeps at least three samples).  Kept
/// lines (features, the surface's boundary) take more samples where they
/// bend: a chord between samples s apart on a line of curvature k departs
/// from it by s^2 k / 8, at most maxSag (0: no bound) times the spacing
/// 1 / lambda of the density, so at least sqrt(k lambda / (8 maxSag))
/// samples per length.  With a metric (6 per surface vertex), the density
/// along a path is its length along the path over its mean length times the
/// density's (AlongPath).  Seams (chart boundaries that are no kept line)
/// are sampled seamSpacing times sparser.
void SampleBoundaries(const MeshTopology& topology, const double* points, const double* importance,
  const std::vector<int>& chartOfTriangle, const BoundaryPaths& boundaries, double density,
  const std::uint8_t* featureEdges, double maxSag, const double* metric, SurfaceSamples& out,
  double seamSpacing = 1.0);

} // namespace beltrami
