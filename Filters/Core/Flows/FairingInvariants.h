// Beltrami core, private to Flows/Fairing: the invariants of section 3.3.1
// (enclosed volume, area, volume above a reference plane, volume about an
// axis), measured and
// restored by scaling after every smoothing step.
#pragma once

#include "Flows/Fairing.h"
#include "Solvers/Partition.h"

#include <functional>
#include <utility>

namespace beltrami::detail
{

struct InvariantState
{
  FairingInvariant Kind = FairingInvariant::None;
  /// The reference plane (HeightFieldVolume) or axis (RevolutionVolume).
  Vec3 PlaneOrigin = Vec3::Zero(), PlaneNormal = Vec3::UnitZ();
  double Initial = 0.0;
  /// A distributed run: the triangles this process counts in the measures
  /// (each triangle of the surface on one process), summed over the
  /// processes of `Split`.
  const MeshTopology* Counted = nullptr;
  const Partition* Split = nullptr;
};

/// The mean of the points of x that `use` selects (finite ones only) and
/// their count; distributed, over the owned points of all processes.
std::pair<Vec3, double> MeanPoint(
  const MeshTopology& topo, const double* x, const Partition* split, const std::function<bool(Index)>& use);

/// The invariant's value on x; `center` (optional): the centre the scaling
/// uses (the volume or area centroid).
double MeasureInvariant(const InvariantState& s, const MeshTopology& topo, const double* x, int threads,
  Vec3* center);

/// Section 3.3.1: scales x back to the initial value of the invariant;
/// returns the value after, measured again where `measure` (else the
/// initial value, which the scaling reaches up to round-off: the step
/// search's runs, where a measure of the volume cost about a twentieth of
/// the run on the bunny Loop-subdivided twice).
double RestoreInvariant(const InvariantState& s, const MeshTopology& topo, double* x, int threads, bool measure = true);

} // namespace beltrami::detail
