/**
 * @class   vtkImplicitFairing
 * @brief   Surface smoothing of thesis chapter 3: implicit fairing, curvature
 *          flow, exact volume preservation, constraints and anisotropic
 *          (feature-preserving) smoothing.
 *
 * Moves the points of a triangle mesh (polygons and strips are triangulated
 * internally; the output keeps the input's cells and point data) by
 * NumberOfIterations steps of the flow dX/dt = lambda W L(X):
 *  - Operator: UMBRELLA (eq. 3.7), SCALE_DEPENDENT_UMBRELLA (eq. 3.11),
 *    CURVATURE_FLOW (section 3.5, dX/dt = -kappa_H n, so flat regions
 *    do not move whatever their triangulation), CURVATURE_FLOW_AND_SAMPLING
 *    (section 3.6: the curvature flow plus the tangential part of the
 *    umbrella, which evens out the triangles without changing the shape),
 *    or LEAST_ESTIMATED_ERROR (default): with the automatic time step, the
 *    curvature flow or the umbrella, whichever ends at the lower estimated
 *    error (the umbrella alone on a crumpled mesh, median dihedral angle
 *    37 degrees or more); with a given time step the curvature flow.  The
 *    field array FairingOperator holds the operator used.
 *  - TimeStep 0 (default): chosen from the input.  The noise of the
 *    geometry is estimated (the height of each point above a quadric fitted
 *    to its 2- to 6-ring, robust to curvature and to sharp features, see
 *    beltrami::EstimateSurfaceNoise) and the step chosen by generalized
 *    cross-validation over steps h^(2k) 2^(j/2), its error estimated by
 *    Stein's unbiased risk estimate (the whole run, its divergence by a
 *    random finite difference), so a clean
 *    mesh is left nearly as it is and a noisy one smoothed as its noise
 *    needs.  Field data: FairingNoise (standard deviation along the normals,
 *    length), FairingTimeStep (the step, in Units; 0 when none helps) and
 *    FairingEstimatedError (RMS distance of the moving points to the
 *    noise-free surface, estimated).  A positive TimeStep is used as given.
 *    Costs about ten runs per operator tried (on a surface of more than
 *    four times StepSearchPoints points, runs of a sample of that many, the
 *    field array FairingSampledPoints its size, then one of the whole).
 *  - Order 1 (L), 2 (L^2, section 3.2.6; default: the sharper low-pass
 *    filter, which removes noise at the scale of the triangles and keeps
 *    larger shapes), 3 or 4 (closer still to an ideal low-pass, figure 3.4a;
 *    each solver iteration costs k stiffness products), or COMBINATION (0):
 *    the flow dX/dt = -lambda sum_k c_k (-L)^k X with OrderWeights c_1..c_4
 *    (default 1, 1: L + L^2).  A negative weight on a lower order amplifies
 *    that scale (feature exaggeration, section 3.2.6); the highest weight
 *    used must be positive, and a step that would amplify a frequency more
 *    than 100-fold (or without bound: its matrix not positive definite) is
 *    refused with an error.  One step multiplies the component of frequency
 *    w by 1 / (1 + dt sum_k c_k w^k); the largest gain of a run goes to the
 *    field array FairingLargestGain.  Orders 3 and 4 are solved as products
 *    of factors of degree 1 and 2; on a 37k-point scan they need about 15x
 *    the solver iterations of order 2 (2900-3200 against 190: raise
 *    MaximumSolverIterations, a warning says when the limit ends a solve)
 *    and smooth noise about as well (bunny00, 0.3% noise, best step: RMS
 *    error 0.00120 and 0.00126 of the diagonal against 0.00121).
 *  - Preconditioner: JACOBI (default), MULTIGRID (one V-cycle of hypre's
 *    BoomerAMG per conjugate-gradient iteration) or GEOMETRIC_MULTIGRID (one
 *    V-cycle on a hierarchy of the surface's own vertices, built once per
 *    run: Solvers/SurfaceMultigrid.h) for the steps of order 1 and 2
 *    without constraints.  The multigrids need a few iterations for a step
 *    of any size where Jacobi needs 70-800, but each costs many of Jacobi's
 *    and their set-up more: on 2 cores Jacobi is the faster for the default
 *    steps up to the 1.2M triangles measured, the geometric multigrid for
 *    large steps (the guide's benchmarks page).  Distributed, Jacobi and
 *    the algebraic multigrid run over the ranks with the serial iteration
 *    counts (the hierarchy spans the ranks; the order-2 Jacobi solve is the
 *    same complex-shift COCG; order-1 Jacobi solves are in double precision,
 *    without the serial renumbering); the geometric multigrid cycles on each
 *    rank's hierarchy of its own points, joined by a coarse level made of a
 *    level of every rank's (Solvers/RankCoarseSpace.h), in 1-1.25 times the
 *    serial iterations at order 1 and about 2 times at order 2.
 *  - OperatorMollification (default 1; 0: off): the operator of each step is
 *    evaluated on a mollified copy of the points - each moved by the normal
 *    part of one implicit umbrella step of this (dimensionless) time -
 *    instead of on the points themselves.  On noisy scans the cotangents of
 *    the noisy triangles are noisy too; the copy damps that noise and keeps
 *    the sampling, so flat regions still never move.  Measured on bunny00
 *    with normal noise of 0.3% of the diagonal, RMS error / diagonal after
 *    the defaults (one step of 4 h^4, order 2): 0.00121; 0.00127 without
 *    mollification (best step); vtkWindowedSincPolyDataFilter at its best
 *    pass band 0.00125.
 *  - Integration: IMPLICIT (default; backward Euler, stable for any step,
 *    a Jacobi-preconditioned conjugate gradient per step - for order 2 on the
 *    complex system whose real part is the step, see SolveSquaredLaplacian -
 *    iteration counts in the field array FairingIterations), EXPLICIT (forward Euler: a warning
 *    when the step is above the stability limit) or TAUBIN_LAMBDA_MU
 *    (Taubin's lambda|mu passes, for comparison).
 *  - TimeStep lambda*dt.  With Units = MEAN_EDGE_LENGTH (default) it
 *    is given in units of h^(2k) for order k, h the input's mean edge
 *    length, so the same value smooths coarse
 *    and fine scans of one object alike (a combination's terms are
 *    c_k (h^2 L)^k and its step is in units of h^(2K), K its highest order);
 *    with PHYSICAL it is in length^(2k) (the umbrella's step is always
 *    dimensionless).
 *  - Invariant (section 3.3): AUTOMATIC (default) keeps the enclosed volume
 *    exactly for closed, oriented surfaces without fixed points, and nothing
 *    otherwise; VOLUME, AREA, HEIGHT_FIELD_VOLUME (volume between the surface
 *    and the plane through the boundary's mean point with normal
 *    ReferencePlaneNormal), REVOLUTION_VOLUME (surfaces of revolution, open
 *    or closed: the volume between the surface and the axis through the area
 *    centroid along ReferencePlaneNormal, restored by scaling the distances
 *    to the axis) or NONE.  Restored by scaling after every step.
 *  - Constraints (section 3.2.7): input array 0 (optional) is a point array
 *    whose non-zero values mark fixed points, and AddFixedPoint adds fixed
 *    points by id (they stay bit-exact unless an invariant rescales the
 *    whole surface); input array 1 (optional) is a
 *    point array of smoothing weights in [0, 1] (0 = fixed); input arrays
 *    2 and 3 (optional, 3 components) hold points on an axis or a plane: a
 *    non-zero vector of AXIS_DIRECTIONS_ARRAY lets the point move only along
 *    it, one of PLANE_NORMALS_ARRAY only in the plane normal to it (a mirror
 *    plane's cut, a slide along a symmetry axis).  They are kept inside the
 *    solves (Baraff and Witkin's filtered conjugate gradient), so the rest
 *    of the surface sees them; like fixed points they turn the automatic
 *    volume invariant off.
 *  - BoundaryHandling (section 3.5.2): FIXED (default), SMOOTH_CURVE (the
 *    boundary loops are smoothed as curves), VIRTUAL_VERTEX (each loop is
 *    closed by a fan to a hidden vertex and smoothed with the surface).
 *  - Anisotropic (section 3.7.1): per-point weights from the principal
 *    curvatures: 1 where both are below FeatureThreshold T, 0 at corners,
 *    kappa_min / kappa_H along edges, clamped at MinimumAnisotropicWeight
 *    (-0.1); computed on a pre-mollified copy (Mollification, in time steps).
 *    T is in units of 1/h with MEAN_EDGE_LENGTH units.  SmoothFeatureCurves
 *    adds a curve-smoothing pass along the detected edges.
 * Non-manifold points, points without area and points with NaN coordinates
 * do not move (a warning says how many); zero-area triangles are skipped
 * (section 3.5.3).  Reports progress per step and honours AbortExecute (the
 * output is then the input).  Field data: FairingIterations (solver
 * iterations per linear solve), FairingInvariant (initial and final value of
 * the preserved quantity, if any).
 * Distributed runs (pvbatch, pvserver): data split over several ranks (one
 * piece per rank, without ghost cells, e.g. after RedistributeDataSet) are
 * smoothed in place: the ranks exchange the triangles around their pieces'
 * common points, each rank assembles the rows of the points it owns, and
 * every solve is one conjugate gradient over all ranks (the serial
 * solvers, see Preconditioner), the invariants global sums; no rank holds more than its
 * piece and the ring around it, and the results are the serial ones to the
 * solver tolerance.  Field data FairingDistribution on each rank: the
 * points it owns, the ghost points it holds, the triangles it holds, and
 * the points whose values it sends to other ranks per ghost update (two
 * updates of 3 values per point in each Jacobi iteration of an order-2 solve).
 * Every option runs so (explicit and Taubin steps with a ghost update after
 * each power of the operator, anisotropic weights and feature curves by
 * each point's owner, boundaries smoothed as curves from the boundary edges
 * at owned points, the invariants and axis and plane constraints over the
 * ranks) except boundaries closed by a virtual vertex (one vertex joined to
 * a whole loop); it and fixed point ids (which name points of one data set)
 * gather the pieces on rank 0 instead (vtkBeltramiGather), smoothed there
 * as one surface: the numbers of a serial run, with the memory and time of
 * one process.  So do pieces that come with ghost cells.
 */
#ifndef vtkImplicitFairing_h
#define vtkImplicitFairing_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

#include <cstdint> // for GatherConstraints
#include <vector>  // for Iterations

class vtkBeltramiSurface;
enum class vtkBeltramiCopy;
namespace beltrami
{
struct FairingOptions;
struct FairingReport;
}

class BELTRAMIFILTERS_EXPORT vtkImplicitFairing : public vtkPolyDataAlgorithm
{
public:
  static vtkImplicitFairing* New();
  vtkTypeMacro(vtkImplicitFairing, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum OperatorType
  {
    UMBRELLA = 0,
    SCALE_DEPENDENT_UMBRELLA = 1,
    CURVATURE_FLOW = 2,
    CURVATURE_FLOW_AND_SAMPLING = 3,
    LEAST_ESTIMATED_ERROR = 4 ///< default: see the class documentation
  };
  enum OrderType
  {
    COMBINATION = 0 ///< the weighted sum of L..L^4 given by OrderWeights
  };
  enum IntegrationType
  {
    IMPLICIT = 0,
    EXPLICIT = 1,
    TAUBIN_LAMBDA_MU = 2
  };
  enum InvariantType
  {
    AUTOMATIC = 0,
    NONE = 1,
    VOLUME = 2,
    AREA = 3,
    HEIGHT_FIELD_VOLUME = 4,
    REVOLUTION_VOLUME = 5
  };
  enum BoundaryType
  {
    FIXED = 0,
    SMOOTH_CURVE = 1,
    VIRTUAL_VERTEX = 2
  };
  /// The input arrays (SetInputArrayToProcess index): both optional.
  enum InputArrays
  {
    FIXED_POINTS_ARRAY = 0,     ///< non-zero values mark fixed points
    SMOOTHING_WEIGHTS_ARRAY = 1, ///< smoothing weights in [0, 1]
    AXIS_DIRECTIONS_ARRAY = 2,   ///< 3 components: non-zero = moves only along it
    PLANE_NORMALS_ARRAY = 3      ///< 3 components: non-zero = moves only normal to it
  };
  enum UnitsType
  {
    MEAN_EDGE_LENGTH = 0,
    PHYSICAL = 1
  };
  enum PreconditionerType
  {
    JACOBI = 0,
    MULTIGRID = 1,
    GEOMETRIC_MULTIGRID = 2,
    AUTOMATIC_PRECONDITIONER = 3
  };

  /// Umbrella (eq. 3.7), scale-dependent umbrella (eq. 3.11), curvature flow (section 3.5),
  /// curvature flow plus the tangential part of the umbrella, which evens out the triangles
  /// (section 3.6), or Least Estimated Error (default): with the automatic time step, the curvature
  /// flow or the umbrella, whichever ends at the lower estimated error (field array
  /// FairingOperator; where a search leaves the points as they are, their error is the larger of
  /// the two noises the searches found: noise that one search saw more of is there for both); with
  /// a given time step, the curvature flow. Values: 0 Umbrella, 1 Scale-Dependent Umbrella, 2
  /// Curvature Flow, 3 Curvature Flow And Sampling, 4 Least Estimated Error. Default: Least
  /// Estimated Error.
  vtkSetClampMacro(Operator, int, UMBRELLA, LEAST_ESTIMATED_ERROR);
  vtkGetMacro(Operator, int);
  /// Order of the operator (section 3.2.6): L^2 (default) is a sharper low-pass filter: it removes
  /// noise at the scale of the triangles and keeps larger shapes; L smooths more broadly and is
  /// cheaper per step; L^3 and L^4 come closer still to an ideal low-pass (figure 3.4a), solved as
  /// products of factors of degree 1 and 2 with about 15x the solver iterations of L^2 on scans
  /// (raise Maximum Solver Iterations; a warning says when the limit ends a solve), for about the
  /// same noise removal on bunny00. One step multiplies the component of frequency w by 1/(1 + dt
  /// w^k). Combination: the weighted sum of the Order Weights. Values: 1 L, 2 L squared, 3 L cubed,
  /// 4 L to the fourth, 0 Combination. Default: L squared.
  vtkSetClampMacro(Order, int, COMBINATION, 4);
  vtkGetMacro(Order, int);
  /// Combination: the weights c1..c4 of L, L^2, L^3, L^4 in the flow dX/dt = -lambda sum c_k (-L)^k
  /// X; one step multiplies frequency w by 1/(1 + dt sum c_k w^k). With mean-edge-length units each
  /// term is c_k (h^2 L)^k and the time step is in units of h^(2K), K the highest order used. A
  /// negative weight on a lower order amplifies the shapes of that scale (feature exaggeration,
  /// section 3.2.6; the largest gain is reported in the field array FairingLargestGain); the
  /// highest weight used must be positive, and a step that would amplify some frequency more than
  /// 100-fold (or without bound) is refused with an error. Default: 1 1 0 0.
  vtkSetVector4Macro(OrderWeights, double);
  vtkGetVector4Macro(OrderWeights, double);
  /// 0: the operator of each step is evaluated on the points themselves (the thesis'
  /// linearisation). Above 0 (default 1): on a mollified copy, each point moved by the normal part
  /// of one implicit umbrella step of this time. On noisy scans the cotangents of the noisy
  /// triangles are noisy too; the copy damps that noise and keeps the sampling, so flat regions
  /// still never move. Not used by the umbrella operator. Default: 1.0.
  vtkSetClampMacro(OperatorMollification, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(OperatorMollification, double);
  /// Implicit (backward Euler, stable for any time step), explicit (forward Euler; a warning above
  /// the stability limit) or Taubin's lambda|mu passes. Values: 0 Implicit, 1 Explicit, 2 Taubin
  /// lambda|mu. Default: Implicit.
  vtkSetClampMacro(Integration, int, IMPLICIT, TAUBIN_LAMBDA_MU);
  vtkGetMacro(Integration, int);
  /// lambda*dt of each step: the amount of smoothing (see Units). 0 (default): chosen from the
  /// input - the noise of its geometry is estimated, the step chosen by generalized
  /// cross-validation and its error estimated (Stein's unbiased risk estimate), so a clean mesh is
  /// left nearly as it is and a noisy one smoothed as much as its noise needs; the field arrays
  /// FairingNoise, FairingTimeStep and FairingEstimatedError report the choice. A positive value is
  /// used as given. Default: 0.
  vtkSetClampMacro(TimeStep, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TimeStep, double);
  /// With TimeStep 0, on a surface of more than four times this many points the step (and the
  /// operator) is chosen on a sample of this many of them, eight balls of the surface around points
  /// spread over it (the same sample in a distributed run), and the whole surface is then smoothed
  /// once with it; the field array FairingSampledPoints holds the sample's size (0: the whole
  /// surface searched). Each step tried costs two runs of the sample instead of the surface: on a
  /// 1.2M-triangle scan with noise of 0.075% of the diagonal 7.2 s instead of 71 s, as near the
  /// clean surface. 0: the whole surface is searched. Default: 131072.
  vtkSetClampMacro(StepSearchPoints, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(StepSearchPoints, vtkIdType);
  /// Mean Edge Length: the time step is in units of h^(2k) for order k (h^2, h^4 for order 2; h the
  /// mean edge length; h^(2K) for a combination up to order K) and the feature threshold in units
  /// of 1/h. Physical: length^(2k) and 1/length (the umbrella's step is dimensionless). Values: 0
  /// Mean Edge Length, 1 Physical. Default: Mean Edge Length.
  vtkSetClampMacro(Units, int, MEAN_EDGE_LENGTH, PHYSICAL);
  vtkGetMacro(Units, int);
  /// Number of time steps; the operator is rebuilt at every step. Default: 1.
  vtkSetClampMacro(NumberOfIterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfIterations, int);
  /// Reduction of the conjugate-gradient residual at each implicit step. Default: 1e-4.
  vtkSetClampMacro(SolverTolerance, double, 1e-15, 1.0);
  vtkGetMacro(SolverTolerance, double);
  /// The most conjugate-gradient iterations of each implicit step. Default: 1000.
  vtkSetClampMacro(MaximumSolverIterations, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumSolverIterations, int);
  /// Preconditioner of the order-1 and order-2 solves. Automatic (default): Geometric Multigrid for
  /// the steps where it was measured the faster (at least 20,000 vertices, serial, order-1 steps
  /// from about 150 h^2 and order-2 steps from about 100 h^4, h the mean edge length, and any
  /// order-2 step on 1.5 to 4 million vertices: one clean order-2 step of 400 h^4 on 1.2M triangles
  /// takes 2.0 s instead of 5.9), otherwise Jacobi; where the one it chose stops short of
  /// SolverTolerance when MaximumSolverIterations run out (a fan of thousands of slivers round one
  /// point), the solve goes on from there with the multigrid it did not choose (after Jacobi,
  /// Geometric Multigrid from 20,000 points in a serial run, else Algebraic Multigrid), up to as
  /// many iterations again. Jacobi: mixed precision, the faster for the default steps on the
  /// measured machines. Algebraic Multigrid: one V-cycle of hypre's BoomerAMG per iteration; 3-4
  /// iterations for a clean mesh's step of any size where Jacobi needs 70-500, but each iteration
  /// and its set-up cost more. Geometric Multigrid: one V-cycle on a hierarchy of the surface's own
  /// vertices (built once per run); 5-10 iterations for a clean mesh's order-1 and order-2 steps
  /// whatever its size, more on noisy ones, the fastest for large steps (the guide's benchmarks
  /// page). In a distributed run every preconditioner gives the serial numbers: the algebraic
  /// hierarchy spans the ranks (the serial iteration counts); Geometric Multigrid cycles on each
  /// rank's hierarchy of its own points, joined by a coarse level made of a level of every rank's
  /// (for order 1 the finest that keeps it within 12,000 rows: 1-1.25 times the serial iterations
  /// of a bunny's step on 2-4 ranks; for order 2 the coarsest: about 2 times); Automatic takes
  /// Jacobi there; order-1 Jacobi solves are in double precision. Values: 0 Jacobi, 1 Algebraic
  /// Multigrid, 2 Geometric Multigrid, 3 Automatic. Default: Automatic.
  vtkSetClampMacro(Preconditioner, int, JACOBI, AUTOMATIC_PRECONDITIONER);
  vtkGetMacro(Preconditioner, int);
  /// Quantity restored by scaling after each step (section 3.3). Automatic: the volume for closed
  /// surfaces without fixed points, nothing otherwise. Values: 0 Automatic, 1 None, 2 Volume, 3
  /// Area, 4 Height Field Volume, 5 Volume Of Revolution. Default: Automatic.
  vtkSetClampMacro(Invariant, int, AUTOMATIC, REVOLUTION_VOLUME);
  vtkGetMacro(Invariant, int);
  /// Normal of the reference plane of Height Field Volume (the plane passes through the mean
  /// boundary point), or the direction of the axis of Volume Of Revolution (the axis passes through
  /// the area centroid). Default: 0 0 1.
  vtkSetVector3Macro(ReferencePlaneNormal, double);
  vtkGetVector3Macro(ReferencePlaneNormal, double);
  /// Boundary points stay fixed, are smoothed as curves, or each boundary loop is closed by a
  /// hidden vertex (section 3.5.2). Values: 0 Fixed, 1 Smooth As Curve, 2 Virtual Vertex. Default:
  /// Fixed.
  vtkSetClampMacro(BoundaryHandling, int, FIXED, VIRTUAL_VERTEX);
  vtkGetMacro(BoundaryHandling, int);
  /// Feature-preserving smoothing (section 3.7.1): edges and corners found from the principal
  /// curvatures are kept. Default: off.
  vtkSetMacro(Anisotropic, bool);
  vtkGetMacro(Anisotropic, bool);
  vtkBooleanMacro(Anisotropic, bool);
  /// T: a principal curvature above T marks a feature (in units of 1/h by default). Default: 0.5.
  vtkSetClampMacro(FeatureThreshold, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FeatureThreshold, double);
  /// The anisotropic weights (kappa_min / kappa_H along edges) are clamped at this value: slightly
  /// negative values let edges sharpen a little, as in the thesis. Default: -0.1.
  vtkSetClampMacro(MinimumAnisotropicWeight, double, -1.0, 1.0);
  vtkGetMacro(MinimumAnisotropicWeight, double);
  /// The anisotropic weights are computed on a copy smoothed by this many time steps of isotropic
  /// curvature flow (0: off). Default: 1.0.
  vtkSetClampMacro(Mollification, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Mollification, double);
  /// Also smooth the detected edges as curves. Default: off.
  vtkSetMacro(SmoothFeatureCurves, bool);
  vtkGetMacro(SmoothFeatureCurves, bool);
  vtkBooleanMacro(SmoothFeatureCurves, bool);
  /// Section 3.4.3: keep the operator (weights and areas) of the first step for every step, a
  /// filter relative to the input mesh instead of the current one: each step applies the same
  /// linear filter. Off: the operator follows the surface (the thesis' linearisation per step).
  /// Default: off.
  vtkSetMacro(KeepFirstOperator, bool);
  vtkGetMacro(KeepFirstOperator, bool);
  vtkBooleanMacro(KeepFirstOperator, bool);
  /// Taubin's lambda: the weight of the shrinking pass of each lambda|mu step (Taubin 1995; the
  /// defaults are those of the thesis' figure 3.5(d), pass band 1/lambda + 1/mu = 0.1). Default:
  /// 0.6307.
  vtkSetMacro(TaubinLambda, double);
  vtkGetMacro(TaubinLambda, double);
  /// Taubin's mu (negative, |mu| > lambda): the weight of the inflating pass. Default: -0.6732.
  vtkSetMacro(TaubinMu, double);
  vtkGetMacro(TaubinMu, double);
  /// Threads (0: all cores, shared among the processes of an MPI job on the node; or
  /// BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);

  /// The names these settings had before (state files and scripts keep
  /// working): TimeStepUnits = Units, NumberOfSteps = NumberOfIterations,
  /// Tolerance = SolverTolerance, MaximumNumberOfIterations =
  /// MaximumSolverIterations.
  void SetTimeStepUnits(int units) { this->SetUnits(units); }
  int GetTimeStepUnits() { return this->Units; }
  void SetNumberOfSteps(int steps) { this->SetNumberOfIterations(steps); }
  int GetNumberOfSteps() { return this->NumberOfIterations; }
  void SetTolerance(double tolerance) { this->SetSolverTolerance(tolerance); }
  double GetTolerance() { return this->SolverTolerance; }
  void SetMaximumNumberOfIterations(int iterations) { this->SetMaximumSolverIterations(iterations); }
  int GetMaximumNumberOfIterations() { return this->MaximumSolverIterations; }

  /// Keep the points marked by a point array fixed (in ParaView: tick this box, then choose the
  /// array). Default: on. (The ParaView panel starts at off: Python opts in by choosing the array;
  /// ParaView preselects an array for every array choice, so its panel starts off.)
  vtkSetMacro(UseFixedPointsArray, bool);
  vtkGetMacro(UseFixedPointsArray, bool);
  vtkBooleanMacro(UseFixedPointsArray, bool);
  /// Hold points on axes given by a 3-component point array (in ParaView: tick this box, then
  /// choose the array). Default: on. (The ParaView panel starts at off: Python opts in by choosing
  /// the array; ParaView preselects an array for every array choice, so its panel starts off.)
  vtkSetMacro(UseAxisDirectionsArray, bool);
  vtkGetMacro(UseAxisDirectionsArray, bool);
  vtkBooleanMacro(UseAxisDirectionsArray, bool);
  /// Hold points on planes given by a 3-component point array of normals (in ParaView: tick this
  /// box, then choose the array). Default: on. (The ParaView panel starts at off: Python opts in by
  /// choosing the array; ParaView preselects an array for every array choice, so its panel starts
  /// off.)
  vtkSetMacro(UsePlaneNormalsArray, bool);
  vtkGetMacro(UsePlaneNormalsArray, bool);
  vtkBooleanMacro(UsePlaneNormalsArray, bool);
  /// Attenuate the smoothing by a per-point weight array in [0, 1] (in ParaView: tick this box,
  /// then choose the array). Default: on. (The ParaView panel starts at off: Python opts in by
  /// choosing the array; ParaView preselects an array for every array choice, so its panel starts
  /// off.)
  vtkSetMacro(UseSmoothingWeightsArray, bool);
  vtkGetMacro(UseSmoothingWeightsArray, bool);
  vtkBooleanMacro(UseSmoothingWeightsArray, bool);

  /// Fixed points given by id (ids of the input's points), in addition to
  /// the fixed-points array: they stay where they are (bit-exact unless an
  /// invariant rescales the surface).  Ids outside the input are reported
  /// with a warning and ignored.
  void AddFixedPoint(vtkIdType pointId);
  void RemoveAllFixedPoints();
  int GetNumberOfFixedPoints() const { return static_cast<int>(this->FixedPointIds.size()); }

  /// Solver iterations of the last run, one per linear solve.
  int GetNumberOfSolves() const { return static_cast<int>(this->Iterations.size()); }
  int GetIterations(int solve) const
  {
    return solve >= 0 && solve < this->GetNumberOfSolves() ? this->Iterations[solve] : 0;
  }

protected:
  vtkImplicitFairing();
  ~vtkImplicitFairing() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Defaults: the core's FairingOptions{} (set in the constructor).
  int Operator;
  int Order;
  double OrderWeights[4];
  double OperatorMollification;
  int Integration;
  double TimeStep;
  int Units;
  int NumberOfIterations;
  double SolverTolerance;
  int MaximumSolverIterations;
  int Preconditioner;
  int Invariant;
  double ReferencePlaneNormal[3];
  int BoundaryHandling;
  bool Anisotropic;
  double FeatureThreshold;
  double MinimumAnisotropicWeight;
  double Mollification;
  bool SmoothFeatureCurves;
  bool KeepFirstOperator;
  double TaubinLambda;
  double TaubinMu;
  int NumberOfThreads;
  vtkIdType StepSearchPoints;
  bool UseFixedPointsArray = true;
  std::vector<vtkIdType> FixedPointIds;
  bool UseSmoothingWeightsArray = true;
  bool UseAxisDirectionsArray = true;
  bool UsePlaneNormalsArray = true;
  std::vector<int> Iterations;

private:
  vtkImplicitFairing(const vtkImplicitFairing&) = delete;
  void operator=(const vtkImplicitFairing&) = delete;

  /// Smooths the surface Execute built (RequestData's value).
  int Fair(vtkBeltramiSurface& surface);
  /// The fixed points (array and ids) and smoothing weights of `surface`
  /// into `fixed` and `weights`; false (after an error) when unusable.
  bool GatherConstraints(vtkBeltramiSurface& surface, std::vector<std::uint8_t>& fixed, std::vector<double>& weights,
    std::vector<double>& axes, std::vector<double>& normals);
  /// Writes the smoothed points `x` and the report into the output.
  void WriteOutput(vtkBeltramiSurface& surface, const std::vector<double>& x, const beltrami::FairingReport& report);
  /// Copies the settings to or from the core's options (one list of pairs).
  void CopySettings(beltrami::FairingOptions& options, vtkBeltramiCopy direction);
};

#endif
