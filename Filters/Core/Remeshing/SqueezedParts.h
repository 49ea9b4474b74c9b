// Beltrami core: the parts of a chart that its map squeezes beyond what the
// control map can sample (Remeshing/SurfaceSampling).  A conformal map
// shrinks a protrusion exponentially along it: the end of a cow's leg in the
// chart of its body holds 1e-5 of the texels its area needs, so the halftone
// puts no sample there and the remesh cuts the hoof off.  Such parts are
// found per input triangle (more expected samples than texels), and sampled
// on the surface itself instead, by farthest-point sampling at the density's
// spacing; their texels are left out of the halftone, which takes the rest
// of the count.
#pragma once

#include "Maps/Atlas.h"
#include "Mesh/MeshTopology.h"

#include <cstdint>
#include <vector>

namespace beltrami
{

struct SqueezedSamples
{
  /// Per triangle of the packed atlas (PackedAtlas): 1 where its part is
  /// sampled here (its texels are not the halftone's).
  std::vector<std::uint8_t> PackedSqueezed;
  std::vector<Index> Triangle;     ///< surface triangle per sample
  std::vector<double> Barycentric; ///< 3 per sample
  std::vector<int> Chart;          ///< per sample
};

/// The squeezed parts of `packed` (the atlas's charts at one texel density,
/// `resolution` texels a side) at `density` samples per unit area where
/// the importance (per surface vertex; null: uniform) is 1: the connected
/// sets of a chart's triangles (sharing a vertex) that expect more than one
/// sample per texel of theirs, each with as many samples as it expects
/// (rounded; none: the part is left to the halftone), at most `most` in all.
/// The first sample of a part goes to its point farthest from the part's
/// border (a limb's end), each next one to the point farthest from the
/// samples and the border, in units of the spacing there.
SqueezedSamples SampleSqueezedParts(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const AtlasChart& packed, const double* importance, double density, int resolution, std::int64_t most);

} // namespace beltrami
