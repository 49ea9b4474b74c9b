// Beltrami core: the chart boundaries' samples made safe to triangulate
// (Remeshing/SurfaceSampling).  Each chart is triangulated in its parameter
// plane with the straight chords between consecutive samples of its
// boundary paths as constraints (Remeshing/Remesh).  A chord departs from
// its path where the path bends between the samples; where two paths run
// closer than that (the jagged rims of small holes punched into a scan,
// beside each other or beside a seam), chords of the two cross and the chart
// cannot be triangulated; where a path bends round other boundary samples
// (a seam round a thin chart's corners), its chord passes on their far side
// and the chart's polygon turns inside out.  Such chords get more samples,
// at the path's vertices, until none cross and none passes round a sample.
#pragma once

#include "Maps/Atlas.h"
#include "Remeshing/SurfaceSampling.h"

#include <cstdint>

namespace beltrami
{

/// Adds boundary samples to `out`'s paths (at path vertices, as
/// SampleKind::Boundary) wherever two chords between consecutive samples of
/// a chart's boundary paths cross in that chart's parameter plane, or where
/// a chord's lune (the chord and its path between its samples) holds
/// another chord's end: on each such chord that has path vertices between
/// its ends, at the one farthest from the chord, in rounds until there are
/// none (at most 16).  `keepCount` (after the interior samples are placed):
/// each new boundary sample is the interior sample of the path's charts
/// nearest to it, moved there (none: the chord is left).
/// Returns the number of samples added (or moved onto paths).
std::int64_t SeparateCrossingChords(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  SurfaceSamples& out, bool keepCount = false);

} // namespace beltrami
