// Beltrami core, inside the remesher: the remesh's distances from its input
// (Remeshing/RemeshDistances.cxx), the checks of its fidelity and the
// fidelity rounds (Remeshing/RemeshFidelity.cxx) that RemeshSurface and
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
/// remesh, that of its triangles' edge midpoints and centres (where
/// measured: RemeshDistances::FromInputTriangles), and the distance to the
/// input of every remesh triangle (RemeshDistances::FromTriangles) that a
/// corner of lies on one of the vertex's triangles (a triangle that spans a
/// gap; the largest of those).  Every input vertex
/// farther than `pin` from the remesh that is the farthest of its 1-ring
/// (a cone point of the input between the remesh's vertices) is flagged in
/// `pinned`.
std::vector<double> LocalDeviations(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, double pin, std::vector<std::uint8_t>& pinned, int numThreads);

/// A remesh's distances from its input, both ways.
struct RemeshDistances
{
  std::vector<double> FromInput;   ///< per input vertex, to the remesh (0 at one in no triangle or not finite;
                                   ///< infinite where the remesh has no triangle)
  std::vector<Index> Nearest;      ///< per input vertex, the remesh triangle nearest to it (-1: none)
  /// Per input triangle, the largest distance to the remesh of points
  /// along its edges and of its centre (a crease or a long edge the remesh
  /// cuts, between input vertices that lie on it), measured where that could
  /// exceed the largest of FromInput (InputTrianglesTo; 0 elsewhere, where
  /// it is at most that), and which of them (0-2: the edge from corner k
  /// to k + 1, at FarthestAlong of its length from corner k; 3: the
  /// centre).  An edge is measured at its midpoint where it is at most two
  /// spacings long, else in parts of at most a spacing (`Spacing`: of
  /// equilateral triangles covering the input with the remesh's count).
  std::vector<double> FromInputTriangles;
  std::vector<std::uint8_t> FarthestSample;
  std::vector<float> FarthestAlong;
  double Spacing = 0.0;
  /// Per remesh triangle, the largest distance to the input of its centre
  /// and its edges' midpoints (0 where not finite).
  std::vector<double> FromTriangles;
};

/// The distances of `remesh` from the input (its triangles in `toInput`).
RemeshDistances MeasureDistances(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& remesh, int numThreads);

/// `d`, the distances of remesh `before`, made those of `after`, the same
/// mesh with vertices moved and edges swapped (PinNearestVertices),
/// measuring again only where it changed.
void UpdateDistances(const MeshTopology& topology, const double* points, const TriangleGrid& toInput,
  const RemeshResult& before, const RemeshResult& after, RemeshDistances& d, int numThreads);

/// A remesh's smallest angle and share of angles below 30 degrees, measured
/// in its metric where it has one (an anisotropic remesh's triangles are
/// long and thin by design: measured in space, its fidelity rounds were
/// never kept).  `remeshTopology`: the remesh's, where the caller has it.
std::pair<double, double> ShapeFigures(const MeshTopology& topology, const double* points, const RemeshResult& r,
  int numThreads, const MeshTopology* remeshTopology = nullptr);

/// Whether remesh `next` is kept over `best` (RemeshSurface's remeshes,
/// the fidelity rounds' moves): measured without error, closer to the input
/// by FarPinGain in the larger of its two deviations (or no farther in it
/// and closer by FarPinGain in their sum), its triangles within the bar or
/// as good as the first
/// remesh's `first` figures (ShapeFigures: AsGoodTriangles' rule, in the
/// metric for an anisotropic remesh).
bool KeptOver(const MeshTopology& topology, const double* points, const RemeshResult& next, const RemeshResult& best,
  const std::pair<double, double>& first, int numThreads, const MeshTopology* nextTopology = nullptr);

/// CheckFidelity of `out`, made from `remesh` (optimised with
/// `optimization`), then the fidelity rounds (RemeshOptions::FarPinSpacings)
/// on it: up to FarPinRounds times, each input vertex the remesh leaves
/// farther than FarPinSpacings spacings (the farthest of its 1-ring) takes
/// the nearest free vertex of the remesh that can move onto it without a
/// fold, kept there, the rings around settled (PinNearestVertices), and so
/// do points a spacing apart along the input edges that it leaves a point of
/// that far (creases of a coarse input: the round made with them and with
/// the vertices alone, the closer kept); where
/// none is that far, the input's corners at the remesh's scale
/// (CornerPinSpacings, CornerSagRatio), all of them; a round
/// is kept where the remesh comes closer to the input by FarPinGain (KeptOver) and
/// its triangles stay within the bar or as good as the first's (AsGood, in
/// the metric for an anisotropic remesh: ShapeFigures).  Not with
/// options.PinnedVertices or FinalSurface.
void CheckFidelityInRounds(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const RemeshOptions& options, const RemeshOptimizationOptions& optimization, Remesh& remesh, RemeshResult& out);

} // namespace beltrami
