// Beltrami core: the remesh's vertices pinned at the input's cone points
// (the tips of spikes, horns and fingers) and, for the error-driven mode,
// at the input vertices a remesh left farthest (Remeshing/SurfaceSampling).
#pragma once

#include "Remeshing/SurfaceSampling.h"

#include <cstdint>

namespace beltrami
{

/// The angle defect of interior vertex v: 2 pi minus its corners' angles.
double AngleDefect(const MeshTopology& topology, const double* points, Index v);

/// Every interior vertex with an angle defect above `threshold` (0: none),
/// or `pinned` (per vertex; may be null), or that stands out of its 1-ring
/// by a quarter of the spacing of `density` (samples per unit area where
/// `importance`, per vertex or null, is 1; 0: none) - a vertex by its angle
/// defect only a spacing from every such spike and sharper cone - takes the nearest
/// sample of `out`, exactly at the vertex, as a Tip (SamplingOptions::
/// TipAngleDefect, PinnedVertices): an interior sample of its chart where
/// all its triangles are in one, else, at a cone point, a sample of its
/// chart boundary's path.  At the tip of a needle (a cone sharper than 39
/// degrees) on a chart boundary, each chart whose fan there is narrower
/// than 60 degrees and holds no interior sample within a spacing of the
/// tip moves its most crowded interior sample into the middle of that fan,
/// a spacing from the tip: a seam that runs up a needle and down again
/// leaves a strip on either side too narrow for a sample, and the needle's
/// remesh a flat fin of triangles with angles of 0 (in the anisotropic mode
/// too: the comb's fingers at 2,000 and 10,000 vertices, 0.00 and 0.05
/// degrees without these samples, 3.3 and 2.7 with them).  `defects`: the
/// angle defect of every vertex (RemeshCache::AngleDefects).  Returns the
/// number of path samples moved onto tips.
std::int64_t PinTips(const MeshTopology& topology, const double* points, const AtlasResult& atlas, double threshold,
  const double* defects, const std::uint8_t* pinned, const double* importance, double density, SurfaceSamples& out);

} // namespace beltrami
