// Beltrami core: the chart boundaries' samples made safe to triangulate
// (Remeshing/SurfaceSampling).  Each chart is triangulated in its parameter
// plane with the straight chords between consecutive samples of its
// boundary paths as constraints (Remeshing/Remesh).  A chord departs from
// its path where the path bends between the samples; where two paths run
// closer than that (the jagged rims of small holes punched into a scan,
// beside each other or beside a seam), chords of the two cross and the chart
// cannot be triangulated.  Such chords get more samples, at the path's
// vertices, until none cross.
#pragma once

#include "Maps/Atlas.h"
#include "Remeshing/SurfaceSampling.h"

#include <cstdint>

namespace beltrami
{

/// Adds boundary samples to `out`'s paths (at path vertices, as
/// SampleKind::Boundary) wherever two chords between consecutive samples of
/// a chart's boundary paths cross in that chart's parameter plane: on each
/// crossing chord that has path vertices between its ends, at the one
/// farthest from the chord, in rounds until no chords cross (at most 16).
/// Returns the number of samples added.
std::int64_t SeparateCrossingChords(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  SurfaceSamples& out);

} // namespace beltrami
