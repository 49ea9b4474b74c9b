// Beltrami core: intrinsic parameterizations of disk-like triangle meshes
// (thesis chapter 5).
//
// The map U: vertices -> R^2 solves the linear system of section 5.4.1,
//
//     (lambda M^A + mu h^2 M^chi) U = 0  at free vertices,   U = C  on the fixed boundary,
//
// with M^A the discrete conformal (DCP, eq. 5.4: cot a_ij + cot b_ij) and M^chi
// the discrete authalic (DAP, eq. 5.6: (cot g_ij + cot d_ij)/|x_i - x_j|^2)
// coefficients.  h^2, the mean squared edge length, makes the mix independent
// of the mesh's size (the thesis' M^chi carries 1/length^2).
//
// Boundaries: the outer loop (the longest) fixed on a circle or a square
// (arc-length or uniform spacing) or to given positions; other loops (holes)
// are free.  Natural boundaries (section 5.4.2, eq. 5.7) give the natural
// conformal map: the minimum of E_D - A(U) with two pinned vertices.
// Point constraints (section 5.4.1) are added by Lagrange multipliers.
//
// Section 5.5: the near-optimal map U = l U^A + (1-l) U^chi minimising the
// edge-length or area distortion energy, and gradient descent on the boundary
// points through the impulse-response basis (BoundaryBasis).
#pragma once

#include "Maps/BoundaryPlacement.h"
#include "Maps/Distortion.h"
#include "Mesh/MeshTopology.h"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace beltrami
{

class Partition;

/// A surface point (a vertex, or a point of a triangle given by barycentric
/// weights) to be mapped onto a target (section 5.4.1).
struct PointConstraint
{
  std::array<Index, 3> Vertices{ { -1, -1, -1 } }; ///< unused entries: -1
  std::array<double, 3> Weights{ { 1.0, 0.0, 0.0 } };
  double Target[2] = { 0.0, 0.0 };
};

/// Section 5.4.1: a line on the surface mapped onto a segment of the plane,
/// "by constraining the endpoints and the intersections of the line with
/// the edges of the mesh": a path of mesh vertices (consecutive ones joined
/// by a mesh edge, e.g. a geodesic path along edges), each vertex placed on
/// the segment From-To at its arc-length fraction.  Expanded into point
/// constraints (Lagrange multipliers, one per vertex of the path).
struct LineConstraint
{
  std::vector<Index> Path;
  /// Path holds waypoints (at least the two ends): consecutive ones are
  /// joined by the shortest path along mesh edges between them.
  bool ShortestPaths = false;
  double From[2] = { 0.0, 0.0 };
  double To[2] = { 1.0, 0.0 };
};

struct ParameterizationOptions
{
  double ConformalWeight = 1.0; ///< lambda (DCP)
  double AuthalicWeight = 0.0;  ///< mu (DAP)
  ParameterizationBoundary Boundary = ParameterizationBoundary::Circle;
  BoundarySpacing Spacing = BoundarySpacing::ArcLength;
  SquareCorners Corners = SquareCorners::QuarterLength; ///< Square only
  const double* GivenUV = nullptr; ///< 2 per vertex, read at boundary vertices (Given)
  std::vector<PointConstraint> Constraints;
  std::vector<LineConstraint> Lines; ///< added to Constraints by Parameterize

  /// Section 5.5.1: replace the map by l U^A + (1-l) U^chi with the l in
  /// [OptimalRange[0], OptimalRange[1]] that minimises OptimalEnergy (fixed
  /// boundaries only; the weights above are then not used).
  bool OptimizeMix = false;
  DistortionEnergy OptimalEnergy = DistortionEnergy::EdgeLength;
  double OptimalRange[2] = { 0.0, 1.0 };

  /// Section 5.5.2: gradient-descent steps on the boundary points (fixed
  /// boundaries; point and line constraints stay met); 0 = off.
  int BoundaryOptimizationSteps = 0;
  DistortionEnergy BoundaryEnergy = DistortionEnergy::EdgeLength;
  /// Keep the impulse-response basis in the result (BoundaryBasis).
  bool KeepBoundaryBasis = false;
  /// The basis holds (free vertices) x (boundary vertices) doubles up to
  /// this size; beyond it the basis is kept as the factorization (the
  /// conformal energy: one solve per use) or, for energies whose system is
  /// not symmetric, refused with an error rather than exhausting memory.
  double MaximumBasisBytes = 1024.0 * 1024.0 * 1024.0;

  int NumberOfThreads = 0;

  /// Split over processes (Parameterize with a Partition): the residual
  /// reduction of the multigrid-preconditioned conjugate gradients (the
  /// serial path solves directly).
  double SplitTolerance = 1e-10;
};

/// The impulse responses b_i of section 5.4.2: the map for any placement of
/// the fixed boundary vertices, without a new solve (U = sum_i u_i b_i).
class BoundaryBasis
{
public:
  /// basis: column-major, free.size() x boundary.size(); offset (optional,
  /// point constraints): the map of the free vertices (u and v, 2 per free
  /// vertex) for a boundary all at (0, 0), added to every map.
  BoundaryBasis(Index numberOfVertices, std::vector<Index> boundary, std::vector<Index> free,
    std::vector<double> basis, std::vector<double> offset = {});
  /// A basis too large to hold (ParameterizationOptions::MaximumBasisBytes),
  /// kept as the factorization it comes from: `map` takes the boundary
  /// positions (2 per boundary vertex) to the free vertices' (2 each, the
  /// offset included), `pullBack` a gradient on the free vertices (2 each)
  /// to the boundary (2 each); one solve per call.
  using Map = std::function<void(const double* in, double* out)>;
  BoundaryBasis(Index numberOfVertices, std::vector<Index> boundary, std::vector<Index> free, Map map, Map pullBack);
  /// Whether the basis is held as a matrix (false: as a factorization).
  bool IsDense() const { return !Implicit; }
  const std::vector<Index>& BoundaryVertices() const { return Boundary; }
  Index NumberOfVertices() const { return Vertices; }
  /// uv: 2 per vertex on exit (points in no triangle get (0, 0)); boundaryUV:
  /// 2 per boundary vertex, in the order of BoundaryVertices().
  void Apply(const double* boundaryUV, double* uv) const;
  /// Chain rule: the gradient with respect to the boundary positions of a
  /// function whose gradient with respect to every vertex is `gradient`.
  void PullBack(const double* gradient, double* boundaryGradient) const;

private:
  Index Vertices = 0;
  std::vector<Index> Boundary; ///< fixed vertices, columns of the basis
  std::vector<Index> Free;     ///< free vertices, rows of the basis
  std::vector<double> Basis;
  std::vector<double> Offset; ///< 2 per free vertex, or empty
  Map Implicit, ImplicitPullBack;
};

struct ParameterizationResult
{
  std::string Error;   ///< non-empty: no map (UV empty), and why
  std::string Warning; ///< non-fatal remarks
  std::vector<double> UV; ///< 2 per vertex; vertices in no triangle get (0, 0)
  std::vector<Index> OuterBoundary; ///< the loop that was fixed (or pinned)
  std::array<Index, 2> PinnedVertices{ { -1, -1 } }; ///< natural boundaries
  double OptimalMix = -1.0;         ///< the l found by OptimizeMix, else -1
  std::vector<double> BoundaryEnergies; ///< energy before/after each descent step
  Index DegenerateTriangles = 0;
  std::unique_ptr<BoundaryBasis> Basis; ///< when KeepBoundaryBasis
  /// Split over processes: the global rows (Partition::GlobalRow) of the
  /// outer loop, and the iterations of the solve.
  std::vector<std::int64_t> OuterRows;
  int Iterations = 0;
};

/// Says whether the mesh can be parameterized (one connected, manifold,
/// oriented surface of genus 0 with at least one boundary loop); if not,
/// `error` says what the input is instead.
bool CheckDiskTopology(const MeshTopology& topology, std::string& error);

/// The point constraints of `line` (appended to `constraints`); an error
/// sentence, empty if the line is usable (at least two distinct vertices on
/// the surface, joined by mesh edges, finite and distinct end targets).
std::string AppendLineConstraint(const MeshTopology& topology, const double* points, const LineConstraint& line,
  std::vector<PointConstraint>& constraints);

/// Computes the parameterization of the mesh at `points` (3 per vertex).
ParameterizationResult Parameterize(
  const MeshTopology& topology, const double* points, const ParameterizationOptions& options);

/// Why the options cannot be solved over processes (Parameterize with a
/// Partition): the feature they need, or empty when they can.  The split
/// solve covers the conformal energy (DCP) with the outer loop fixed on a
/// circle or square (corners at the quarters), or every loop at given
/// positions; the natural boundary, the authalic energy and its mix, point
/// and line constraints, and the boundary basis need the whole surface.
std::string DistributedParameterizationLimitation(const ParameterizationOptions& options);

/// The parameterization of a surface split over MPI processes (collective:
/// every process of `split` calls it, an empty piece's too).  `topology`
/// holds the process's piece with the whole star of every point it owns
/// (ghost rows after them); `points` and GivenUV one row per topology
/// point.  Each process assembles the conformal rows of its owned points,
/// and the conjugate gradients preconditioned by multigrid (hypre's
/// BoomerAMG, spanning the processes) solve to SplitTolerance; only the
/// boundary is gathered on every process.  The outer loop starts at its
/// point of the lowest `pointIds` (optional, one per topology point: ids
/// that a serial run would have, so that it starts where the serial run's
/// loop does, at its lowest point id), else at its lexicographically first
/// point (x, then y, then z).  On return UV holds every topology row (ghosts
/// their owners' values); the checks and errors are those of the serial
/// path, agreed over the processes.
ParameterizationResult Parameterize(const MeshTopology& topology, const double* points,
  const ParameterizationOptions& options, const Partition& split, const std::int64_t* pointIds = nullptr);

} // namespace beltrami
