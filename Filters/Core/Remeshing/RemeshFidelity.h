// Beltrami core, inside the remesher: the checks of a remesh's fidelity and
// the fidelity rounds (Remeshing/RemeshFidelity.cxx) that RemeshSurface and
// RemeshToDeviation share with Remeshing/SurfaceRemeshing.cxx.
#pragma once

#include "Mesh/SurfaceDistance.h"
#include "Remeshing/RemeshOptimization.h"
#include "Remeshing/SurfaceRemeshing.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace beltrami
{

/// The surface's largest principal curvatures and cotangent Laplacian in
/// `cache` (computed once per surface).
void KeepCurvatures(const MeshTopology& topology, const double* points, int numThreads, RemeshCache& cache);

/// The remesh's deviation at every input vertex: its distance to the
/// remesh, and the distance to the input of the centre of every remesh
/// triangle that a corner of lies on one of the vertex's triangles (a
/// triangle that spans a gap; the largest of those).  Every input vertex
/// farther than `pin` from the remesh that is the farthest of its 1-ring
/// (a cone point of the input between the remesh's vertices) is flagged in
/// `pinned`.
std::vector<double> LocalDeviations(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, double pin, std::vector<std::uint8_t>& pinned, int numThreads);

/// AsGoodTriangles' rule on (smallest angle, share below 30 degrees).
bool AsGood(double angle, double below30, double firstAngle, double firstBelow30);

/// A remesh's smallest angle and share of angles below 30 degrees, measured
/// in its metric where it has one (an anisotropic remesh's triangles are
/// long and thin by design: measured in space, its fidelity rounds were
/// never kept).
std::pair<double, double> ShapeFigures(
  const MeshTopology& topology, const double* points, const RemeshResult& r, int numThreads);

/// CheckFidelity of `out`, made from `remesh` (optimised with
/// `optimization`), then the fidelity rounds (RemeshOptions::FarPinSpacings)
/// on it: up to FarPinRounds times, each input vertex the remesh leaves
/// farther than FarPinSpacings spacings (the farthest of its 1-ring) takes
/// the nearest free vertex of the remesh that can move onto it without a
/// fold, kept there, the rings around settled (PinNearestVertices); where
/// none is that far, the input's corners at the remesh's scale
/// (CornerPinSpacings, CornerSagRatio), all of them; a round
/// is kept where the remesh comes closer to the input by FarPinGain and
/// its triangles stay within the bar or as good as the first's (AsGood, in
/// the metric for an anisotropic remesh: ShapeFigures).  Not with
/// options.PinnedVertices or FinalSurface.
void CheckFidelityInRounds(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const RemeshOptions& options, const RemeshOptimizationOptions& optimization, Remesh& remesh, RemeshResult& out);

} // namespace beltrami
