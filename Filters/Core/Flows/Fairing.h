// Beltrami core: surface smoothing of thesis chapter 3 (sections 3.2-3.7).
//
// Every flow is dX/dt = lambda * W * L(X) with one of the Laplacians of
// Laplacian.h (order 1), dX/dt = -lambda * W * L(L(X)) (order 2, section
// 3.2.6), in general dX/dt = -lambda * W * sum_k c_k (-L)^k X for k = 1..4
// (orders 3 and 4, and the combinations of section 3.2.6), W the per-vertex weights (soft constraints, section 3.2.7, times the
// anisotropic weights of section 3.7.1).  The operator is linearised per step
// (sections 3.4.3 and 3.5.3).  Implicit integration solves, in the symmetric
// form (multiplying the rows of (I - dt W L) X' = X by a_i / w_i),
//     order 1:  (M W^-1 + dt S) X' = M W^-1 X
//     order 2:  (M W^-1 + dt S M^-1 S) X' = M W^-1 X
//     general:  (M W^-1 + dt sum_k c_k S (M^-1 S)^(k-1)) X' = M W^-1 X
// which are symmetric positive definite for every operator (the cotangent
// stiffness is positive semi-definite), with a Jacobi-preconditioned
// conjugate gradient (appendix A.5): order 1 by the graph solver
// (SolveShiftedLaplacian); order 2 with unit weights W as the real part of
// the complex system (M + i sqrt(dt) S) Z = b (SolveSquaredLaplacian: same
// solution, a few times fewer iterations), otherwise matrix-free.  A step
// maps a component along a generalised eigenvector S v = w M v to
// 1 / (1 + dt sum_k c_k w^k) of itself (figure 3.4's transfer function): the
// higher the order, the closer to an ideal low-pass; a negative c_k amplifies
// low or middle frequencies (feature exaggeration), allowed as long as no
// frequency of the mesh (up to Gershgorin's bound) grows more than 100-fold
// in one step; beyond, the run is refused (or ends) with a message.  Above
// order 2 with unit weights the step is solved as the product of its real
// factors of degree 1 and 2, one after the other (exact, held rows included).  Vertices with w_i = 0 are hard
// constraints and keep their position exactly.
#pragma once

#include "Mesh/MeshMeasures.h"
#include "Solvers/AlgebraicMultigrid.h"
#include "Solvers/Partition.h"
#include "Solvers/SurfaceMultigrid.h"
#include "Mesh/MeshTopology.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace beltrami
{

enum class FairingOperator : int
{
  Umbrella = 0,               ///< eq. 3.7 (dimensionless time step)
  ScaleDependentUmbrella = 1, ///< eq. 3.11 (Fujiwara)
  CurvatureFlow = 2,          ///< eq. 3.12/3.13: dX/dt = -kappa_H n
  CurvatureFlowAndSampling = 3, ///< section 3.6: curvature flow + tangential part of the
                                ///< scale-dependent umbrella (regularises the sampling)
  /// With a chosen time step (TimeStep 0, implicit, isotropic): the curvature
  /// flow or the umbrella, whichever reaches the lower estimated error (the
  /// umbrella alone where the mesh is crumpled: median dihedral angle of 40
  /// degrees or more, where the cotangent weights are noise themselves);
  /// otherwise the curvature flow.  The umbrella's uniform weights do not
  /// see the noise and win on very noisy meshes, the curvature flow on
  /// coarse ones whose triangles are uneven.
  LeastEstimatedError = 4
};

enum class FairingIntegration : int
{
  Implicit = 0,      ///< backward Euler (eq. 3.9): any time step is stable
  Explicit = 1,      ///< forward Euler (eq. 3.8), for comparison
  TaubinLambdaMu = 2 ///< Taubin's lambda|mu passes with the chosen operator (section 3.2.1)
};

enum class FairingInvariant : int
{
  Automatic = 0,        ///< Volume for closed, oriented surfaces without hard constraints; else None
  None = 1,
  Volume = 2,           ///< exact volume (eq. 3.10) by scaling about the volume centroid
  Area = 3,             ///< total area by scaling about the area centroid
  HeightFieldVolume = 4, ///< volume between the surface and a reference plane, by scaling heights
  RevolutionVolume = 5   ///< volume about an axis (surfaces of revolution), by scaling the radii
};

enum class FairingBoundary : int
{
  Fixed = 0,        ///< boundary vertices do not move
  SmoothCurve = 1,  ///< boundary loops smoothed as curves (1D eq. 3.11, section 3.5.2)
  VirtualVertex = 2 ///< each loop closed by a fan to a virtual vertex at its barycentre
};

/// The defaults are those of vtkImplicitFairing and its ParaView panel (one
/// source: the filter starts from FairingOptions{}): second-order curvature
/// flow, one implicit step of the size chosen from the input's noise.
struct FairingOptions
{
  FairingOperator Operator = FairingOperator::LeastEstimatedError;
  /// 1-4: L^k (section 3.2.6); 0: the combination of OrderWeights.
  int Order = 2;
  /// Order 0: the weights c_1..c_4 of L, L^2, L^3, L^4 in the flow
  /// dX/dt = -lambda sum_k c_k (-L)^k X.  With MeanEdgeLength units each term
  /// is made dimensionless with h (c_k (h^2 L)^k), so TimeStep is in units of
  /// h^(2K), K the highest order used.  A negative weight on a lower order
  /// exaggerates the features of that scale (section 3.2.6); the highest
  /// order's weight must be positive.
  double OrderWeights[4] = { 1.0, 1.0, 0.0, 0.0 };
  FairingIntegration Integration = FairingIntegration::Implicit;
  /// lambda*dt, in length^(2k) of `Units` for order k (2K for a
  /// combination up to order K); the umbrella operator's step is dimensionless.
  /// 0 (default): chosen from the input for the given NumberOfIterations -
  /// the noise of its geometry estimated (EstimateSurfaceNoise) and the
  /// step chosen by generalized cross-validation, its error estimated by
  /// Stein's unbiased risk estimate (Flows/FairingStepChoice.h); a clean
  /// mesh is left nearly as it is.
  /// Not with Taubin's passes (their steps are TaubinLambda and TaubinMu).
  double TimeStep = 0.0;
  /// TimeStep 0: the input's noise (length), its noise measured one ring
  /// wider, on its first rings and median dihedral angle where a run on the
  /// same input estimated them already (its FairingReport's Noise,
  /// WiderNoise, LocalNoise and MedianDihedral); 0: estimated here.
  double KnownNoise = 0.0, KnownWiderNoise = 0.0, KnownLocalNoise = 0.0, KnownMedianDihedral = 0.0;
  /// Unit of TimeStep and FeatureThreshold: the mean edge length h of the
  /// input (then the step is scaled by h^2 or h^4 and the threshold by 1/h),
  /// or the mesh's own units.
  LengthUnit Units = LengthUnit::MeanEdgeLength;
  int NumberOfIterations = 1; ///< time steps
  double SolverTolerance = 1e-4; ///< reduction of the solver residual (see ConjugateGradient.h)
  int MaximumSolverIterations = 1000;
  /// Of the graph solvers (orders 1 and 2 without constraints): Jacobi,
  /// algebraic multigrid (see Solvers/AlgebraicMultigrid.h for when it pays),
  /// geometric multigrid (Solvers/SurfaceMultigrid.h), or Automatic: the
  /// geometric multigrid for large steps on large surfaces, where it was
  /// measured the faster (Solvers/GraphSolvers.h, ChosenPreconditioner), else
  /// Jacobi, going on with a multigrid where that stops short of the
  /// tolerance (SolveShiftedLaplacian).
  Preconditioning Preconditioner = Preconditioning::Automatic;
  /// GeometricMultigrid: the hierarchy of the run's surface, built once by
  /// the fairing (from the input's points) for all its solves; Automatic:
  /// built by the first solve that takes the multigrid, kept for the others
  /// (KeptHierarchy, made per run). Not settings.
  std::shared_ptr<const SurfaceHierarchy> Hierarchy;
  std::shared_ptr<std::shared_ptr<const SurfaceHierarchy>> KeptHierarchy;
  FairingInvariant Invariant = FairingInvariant::Automatic;
  /// HeightFieldVolume: the normal of the reference plane; RevolutionVolume:
  /// the direction of the axis (through the initial area centroid).
  double ReferencePlaneNormal[3] = { 0.0, 0.0, 1.0 };
  FairingBoundary Boundary = FairingBoundary::Fixed;
  bool Anisotropic = false;          ///< section 3.7.1
  double FeatureThreshold = 0.5;     ///< T, a curvature (1/length of `Units`)
  double MinimumAnisotropicWeight = -0.1;
  /// The weights are computed on a pre-mollified copy (one implicit
  /// curvature-flow step of Mollification * TimeStep; 0: off), as the thesis
  /// recommends for this ill-posed, edge-enhancing flow.
  double Mollification = 1.0;
  /// The operator (weights and areas) of each step is evaluated on a
  /// mollified copy of the positions: each point moved by the normal part of
  /// one implicit umbrella step of this (dimensionless) time; 0: on the
  /// positions themselves (the thesis' linearisation).  On noisy scans the
  /// cotangents of the noisy triangles are noisy too; the copy damps the
  /// noise across the surface and keeps the sampling, so a flat region's
  /// copy is the region itself (flat regions still never move).  Noisy
  /// bunny, order 2, 4 h^4: RMS error 0.00121 of the diagonal instead of
  /// 0.00127.  Not used by the umbrella operator.
  double OperatorMollification = 1.0;
  bool SmoothFeatureCurves = false;  ///< a curve-smoothing pass along detected edges
  /// Section 3.4.3: the surface operator of the first step (its weights and
  /// areas) kept for every step, a filter relative to the input mesh instead
  /// of the current one (each step then applies the same linear filter).
  bool KeepFirstOperator = false;
  double TaubinLambda = 0.6307, TaubinMu = -0.6732; ///< figure 3.5(d)
  int NumberOfThreads = 0;
  /// TimeStep 0 on a surface of more than SampledSearchRatio times this
  /// many points: the step (and the operator) chosen on a sample of this
  /// many of them, then one run of the whole surface (0: the whole surface
  /// searched; Flows/FairingStepChoice.h, FairWithSampledSearch).
  std::int64_t StepSearchPoints = std::int64_t(1) << 17;
};

/// Section 3.2.7.  Axis and plane constraints are kept during the solves
/// (Baraff and Witkin's filtered conjugate gradient: the step's system
/// restricted to the allowed directions, so the other points see the
/// constraint); they take the matrix-free solver.  A vertex with both moves
/// along its axis; fixed vertices stay fixed.  Like fixed points, they rule
/// out the automatic volume invariant (its scaling would move them).
struct FairingConstraints
{
  const std::uint8_t* Fixed = nullptr; ///< per vertex: non-zero = hard constraint
  const double* Weights = nullptr;     ///< per vertex smoothing weight, clamped to [0, 1]
  /// Per vertex 3 values: a non-zero direction holds the vertex on the line
  /// through it along that direction (only that component moves).
  const double* AxisDirections = nullptr;
  /// Per vertex 3 values: a non-zero normal holds the vertex on the plane
  /// through it normal to that direction (only the other components move).
  const double* PlaneNormals = nullptr;
};

struct FairingReport
{
  bool Completed = true;               ///< false if cancelled (positions of the last full step)
  std::string Error;                   ///< non-empty: nothing was done (points unchanged)
  std::vector<int> Iterations;         ///< solver iterations per linear solve
  double LargestResidual = 0.0;        ///< relative residual of the worst solve
  bool Converged = true;               ///< every solve reached the tolerance
  bool ExplicitUnstable = false;       ///< explicit time step above the stability limit
  double StabilityLimit = 0.0;         ///< largest stable explicit lambda*dt (estimate)
  /// Implicit combinations with a negative weight: the largest factor by
  /// which one step multiplies a frequency, 1 / min(1 + dt p(w)) (estimate;
  /// 1 when nothing is amplified).
  double LargestGain = 1.0;
  FairingInvariant InvariantUsed = FairingInvariant::None;
  double InitialInvariant = 0.0, FinalInvariant = 0.0;
  Index FixedVertices = 0;             ///< hard constraints + fixed boundary + unusable vertices
  Index UnusableVertices = 0;          ///< non-manifold, no area or non-finite: kept fixed
  Index DegenerateTriangles = 0;       ///< zero-area triangles skipped (largest over the steps)
  Index FeatureVertices = 0;           ///< anisotropic: vertices on edges or corners (last step)
  std::string Warning;                 ///< a sentence for the user, empty if none
  /// A chosen time step (TimeStep 0): the noise of the input's geometry
  /// (standard deviation along the normals, length), the median dihedral
  /// angle (degrees, EstimateSurfaceNoise), the step (in the options' Units; 0: none needed) and the
  /// estimated RMS distance of the moving points to the noise-free surface
  /// after the run (length).  All 0 when the step was given.
  double Noise = 0.0;
  double MedianDihedral = 0.0;
  /// The noise estimated with neighbourhoods one ring wider, and on the
  /// first rings (SurfaceNoise::WiderDeviation, LocalDeviation).
  double WiderNoise = 0.0, LocalNoise = 0.0;
  /// The noise per direction of the tangent planes the step's risk
  /// assumed (length): 0 (noise along the normals) or Noise (isotropic
  /// noise, where the estimate says so: Flows/FairingStepChoice.h).
  double TangentialNoise = 0.0;
  FairingOperator OperatorUsed = FairingOperator::CurvatureFlow; ///< the operator the run used
  double ChosenTimeStep = 0.0;
  double EstimatedError = 0.0;
  /// The estimated error of leaving the points as they are (length): the
  /// noise the step's risk used, over every direction it counts (the noise
  /// estimate, or more where the risk of the best step showed more).
  double InputError = 0.0;
  /// The sentences of the step's choice in Warning (a step at the search's
  /// end, a surface left as it is).
  std::string StepWarning;
  /// The step was chosen on a sample of this many points of the surface
  /// (0: on the whole surface; FairingOptions::StepSearchPoints).
  Index SampledPoints = 0;
};

/// Smooths `points` (3 doubles per vertex, in place) of the surface `topology`.
///
/// Distributed (`split`: the surface's points split over MPI processes, see
/// Solvers/Partition.h; collective, every process calls it): `topology` is
/// this process' piece with the whole star of every point it owns (the
/// other points are ghosts, and may miss triangles), and the constraint
/// arrays cover the piece's points.  Each process assembles the rows of its
/// own points; every solve is one conjugate gradient over all processes (the
/// serial solvers: order 2 by the complex-shift COCG or multigrid, order 1
/// by multigrid or matrix-free in double precision, the rest matrix-free),
/// the measures and invariants are sums over the processes, and the ghosts'
/// results are their owners'.  The owned
/// points' results equal a serial run's to the solver tolerance.  Not
/// every option is distributed: see DistributedFairingLimitation.
FairingReport FairSurface(const MeshTopology& topology, double* points,
  const FairingOptions& options, const FairingConstraints& constraints = {},
  const ProgressCallback& progress = {}, const Partition* split = nullptr);

/// Empty when FairSurface runs `options` distributed, else what it cannot
/// run that way (virtual vertices: one per whole boundary loop, joined to
/// all its points): the caller then gathers the surface on one process.
std::string DistributedFairingLimitation(const FairingOptions& options);

} // namespace beltrami
