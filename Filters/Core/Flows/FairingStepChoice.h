// Beltrami core, private to Flows/Fairing: the time step of a fairing run
// chosen from the noise of the input (FairingOptions::TimeStep = 0).
#pragma once

#include "Flows/Fairing.h"
#include "Flows/FairingInvariants.h"
#include "Flows/FairingSteps.h"
#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <vector>

namespace beltrami::detail
{

/// Where a run's solve may start (SmoothingRun): Points empty for the
/// points themselves.
struct RunStart
{
  std::vector<double> Points;
  int Iterations = 0; ///< the solver's, of the run that left these Points
};

struct StepChoice
{
  double TimeStep = 0.0;       ///< lambda*dt in the run's (physical) units; 0: leave the points
  double EstimatedError = 0.0; ///< RMS distance of the moving points to the noise-free ones, estimated
  double InputError = 0.0;     ///< the same of the points left as they are (the input's risk)
  int Evaluations = 0;         ///< time steps tried
  bool ShapeDetail = false;    ///< left as it is: the estimated noise is mostly the shape's detail
  bool AtLimit = false;        ///< the step is the largest or smallest tried, and the risk still fell there
  /// Where the run of the chosen step from x may start (the search's own
  /// run of it, SmoothingRun's `start`): the result of the same solve.
  RunStart Start;
};

/// The largest fraction of the estimated noise a chosen step may be
/// estimated to leave.  On the corpus' coarse meshes whose shape varies at
/// the scale of the triangles (elephant, cow, hand, nefertiti, cactus) the
/// estimate takes that detail for noise (at 0.1% of the diagonal it measures
/// 1.9-3 times the added noise) and its best step is estimated to leave
/// 0.75-0.99 of it: smoothing there ended 1-80% further from the clean mesh
/// than the noisy input.  Where the noise is real the best steps leave
/// 0.15-0.7 of it.
constexpr double MostKeptNoise = 0.75;

/// The deviation of the risk's probe (ChooseTimeStep's epsilon) over the
/// estimated noise.  The curvature flow's run is not linear in the points
/// (its cotangent weights are rebuilt from them), so the finite difference
/// of its divergence is biased by the size of the probe, which overstated
/// its risk against the umbrella's (linear in them): at half the noise, on
/// the corpus with noise of 1% of the diagonal along the normals, the
/// umbrella was kept on a head and a sphere where the flow, chosen at a
/// quarter, ended 15% and 13% nearer the clean mesh.  (Over the 75 cases:
/// 5 nearer by 3-15%, one further, the locally refined cylinder at 0.3%,
/// whose refined part the noise crumples; a tenth chose as a quarter did.)
constexpr double ProbeDeviation = 0.25;

/// Operator LeastEstimatedError tries the curvature flow only below this
/// median dihedral angle (degrees) of the noisy mesh; above it the umbrella
/// alone.  Noise that tilts the triangles this far makes the cotangent
/// weights noise themselves: on the corpus with noise of 0.1-1% of the
/// diagonal along the normals the flow ended nearer the clean mesh only
/// below 37 degrees (at 37.5-50 its estimated error was 1.03-3.1 times the
/// umbrella's and the umbrella was kept: blobby at 1% 37.5 degrees, the
/// locally refined cylinder at 0.3% 38.5, bunny00 at 0.3% 40.0), and with
/// isotropic noise it was kept once above 40, 18% further than the
/// umbrella.  On the 0.3%-noisy bunny of 300k triangles (47.7 degrees) its
/// step search was 8.4 s of 10.4, for an estimated error 1.7 times the
/// umbrella's; on the 1.2M-triangle bunny with 0.075% (37.6 degrees) 8.4 s
/// of 11.3 on one thread, the umbrella kept (the flow's estimated error 1.9
/// times its), 2.7 s without it.  (At 40 the same corpus results, both
/// kinds of noise.)
constexpr double CrumpledDihedral = 37.0;

/// A surface left as it is whose estimated variation along the normals is
/// below this fraction of its mean edge length (normals turned by about two
/// degrees: nothing a user could see) is clean, and said so only in the
/// report; above it a warning says how to smooth it anyway.  The corpus'
/// clean meshes measure 0.001-0.016 h (bunny00 0.011 h), its coarse ones
/// with detail at the scale of their triangles 0.047-0.095 h.
constexpr double CleanVariation = 0.03;

/// The most by which the noise estimate may grow when every neighbourhood
/// is one ring wider (SurfaceNoise::WiderDeviation) for it to be taken as
/// noise.  White noise measures the same at both sizes (its samples are
/// normalised by their gain); the shape's own variation, which the quadrics
/// leave, grows with the neighbourhood's radius (as its cube where the
/// third derivatives lead: 3.4 from two rings to three).  Where it grows
/// more than this, the surface is left as it is.  On the corpus with noise
/// of 0.1-1% of the diagonal along the normals: 0.94-1.17 on its fine
/// meshes, 1.1-1.95 on its coarse scans; 2.4-4.9 on the coarse tubes of
/// eight.off and double-torus-example.off, which the chosen steps took
/// 1.2-8 times further from the clean mesh than the noisy input (and 2.1-2.8
/// on the coarse elephants and cactus at 0.1%, which MostKeptNoise left).
constexpr double ShapeGrowth = 2.0;

/// Where the estimated noise is below this fraction of the mean edge length
/// no step is searched: smoothing could bring the points at most that much
/// nearer the noise-free surface, and the search costs tens of runs (a
/// clean Loop-subdivided bunny of 1.2M triangles, 0.0007 h: 36 s to decide
/// to leave it).  The corpus' clean meshes measure 0.001-0.016 h, its
/// meshes with noise of 0.1% of the diagonal 0.026 h and more.
constexpr double NoNoise = 0.01;

/// True where the noise is taken as isotropic (as strong in the tangent
/// planes as along the normals), from the deviations along the normals and
/// in the tangent planes (EstimateSurfaceNoise, EstimateTangentialNoise)
/// and the mean edge length h: the tangential one between half and one
/// times the normal one, and at least a fifth of h.  Noise along the
/// normals shows a fifth to two fifths of itself in the tangent planes at
/// 0.3-1% of the diagonal (the tilted normals take part of it), isotropic
/// noise 0.53-1.0 of itself.  Smaller than a fifth of h, or above the
/// normal noise, the tangential deviation is the irregular sampling of the
/// mesh itself (the corpus' clean meshes: 0.005-0.23 h; plane.off with
/// noise of 0.1% and 0.3% along its normals measures 2-6 times that noise;
/// a marching-cubes octopus with noise of 0.1% along its normals 1.11
/// times, 0.21 h: taken as isotropic up to 1.5 times, the umbrella's
/// tangential moves left it 1.43 times further from the clean surface than
/// the input, taken as noise along the normals 0.53 times).  Taken as noise
/// along the normals, isotropic noise was left as it is from 0.3% of the
/// diagonal on bunny00 (the flows' tangential moves counted as error, none
/// as noise removed); above the normal noise, as at 0.1% on two
/// marching-cubes surfaces (1.25-1.41 times), it is left 0.78 times as far
/// as the input rather than as far.
inline bool IsotropicNoise(double normal, double tangential, double h)
{
  return tangential >= 0.5 * normal && tangential <= 1.0 * normal && tangential >= 0.2 * h;
}

/// The largest correlation of a chosen step's moves over the surface's
/// edges (MoveCoherence) for the run to be kept.  Removing white noise
/// moves neighbouring points independently (the moves are the noise's high
/// frequencies: -0.23 to 0.09 over the corpus with noise of 0.1-1% of the
/// diagonal along the normals, 75 cases, none of which it changes); where
/// the run moves neighbours together it shrinks limbs and rounds the shape,
/// detail that the noise estimate took for noise: over the corpus meshes
/// quadric-decimated to a tenth of their triangles, stretched 6 times or
/// flattened to 0.15 (201 cases with noise of 0.1-1% and 67 clean,
/// inputs.variants_of), 13 of the runs above it ended 1.2-17.6 times
/// further from the clean mesh than their noisy input (the decimated
/// elephant with noise of 0.1%: 0.53, its estimate 30 times the noise), the
/// clean decimated elephant moved by 0.27 of its mean edge length, and one
/// ended 0.92 times as far (the decimated bunny at 0.1%, 0.16).  Of the
/// generated hard shapes (inputs.hard_shapes) with the same noise, it leaves
/// a closed plate thinner than its triangles (collapsed: 23-40 times
/// further) and a sphere amid 40 specks smaller than the noise at 0.1%
/// (whose specks shrink together; smoothed, 0.69 of its input).  Above it,
/// the points are left as they are (Fairing.cxx, LeaveCoherentMoves).
constexpr double MostCoherentMove = 0.1;

/// The largest correlation of the chosen step's moves along the normals of
/// its result over the surface's edges (MoveCorrelations::AlongNormals)
/// for the run to be kept.  On a coarse mesh a limb or a tube is a few
/// triangles round, so shrinking it moves neighbours in directions apart
/// (their 3D moves' correlation stays low) but all inwards, along their
/// normals.  Over the corpus, its variants (stretched, flattened, decimated)
/// and the generated hard shapes with noise of 0.1-1% of the diagonal along
/// the normals and, on the corpus, in every direction (278 cases with a
/// chosen step, 344 runs of the two operators): every run kept that ended
/// nearer the clean mesh measured at most 0.18 (crumpled by isotropic noise
/// of 1%, under 0.04: the result's normals are smooth), while the decimated
/// hand at 0.1-1% and the decimated knot at 0.1% measured 0.24-0.30 and
/// ended 1.9-12.7 times further from the clean mesh than their noisy input
/// (the clean decimated hand 0.21, moved by 0.074 of its mean edge length).
/// The area-weighted normals: with chapter 2's (UnitNormals), which turn
/// with the noise on such meshes, a run kept measured 0.19, the noisy
/// decimated hand 0.23 and the clean one 0.19 (left moved).
constexpr double MostCoherentNormalMove = 0.2;

/// The correlations of the moves d = after - before of the free points over
/// the surface's edges between them: in space, the mean of d_a . d_b per edge
/// over the mean of |d_a|^2 per point (1: all move alike; independent moves
/// about 0, the removal of white noise's high frequencies below; 0 where
/// nothing moved), and the same of the moves' components along the unit
/// normals of `after` (area-weighted, as ComputeCurvatures gives them).
/// Collective on a split surface (the ghosts' points their owners').
struct MoveCorrelations
{
  double InSpace = 0.0;
  double AlongNormals = 0.0;
};
MoveCorrelations MoveCoherence(const MeshTopology& topo, const double* before, const double* after,
  const std::vector<std::uint8_t>& held, const Partition* split);

/// The whole smoothing of `points` (3 per vertex, in place) with time step
/// `timeStep`; false where it is not defined (nothing to compare).  `start`:
/// where its solve may start, and on return where a run of the same points
/// with a nearby step may start (its solve's result before the invariant is
/// restored; none where the run has more than one step).  The search's
/// umbrella runs from x (and from the perturbed points) at steps a factor
/// of 2-4 apart start from each other: on bunny00 Loop-subdivided twice
/// with noise of 0.3% of the diagonal 314 -> 274 solver iterations, on the
/// corpus with noise of 0.1-1% 2% fewer.  The curvature flow's runs start
/// at the points: from a nearby step's result its COCG took 9% more
/// iterations over the corpus, and on the twice subdivided bunny with
/// noise of 0.075% up to 3 times as many (runs that missed the tolerance in
/// 1000 iterations).  The run of the chosen step starts at the search's own
/// (every operator: the same system, met at once).
using SmoothingRun = std::function<bool(double timeStep, double* points, RunStart& start)>;

/// The time step whose run brings the points `x` closest to the noise-free
/// surface by generalized cross-validation (Craven and Wahba 1979; f: the
/// run, m the moving points, d = 1 + 2 tangential^2 the directions counted,
/// `tangential` the noise in each direction of the tangent planes over that
/// along the normals: 0 none, 1 isotropic noise):
///     GCV = |f(x) - x|^2 / (d m - div f)^2,
/// which needs no noise level: with the estimated one in Stein's unbiased
/// risk estimate instead (for white noise of deviation `noise`),
///     E |f(x) - clean|^2 = |f(x) - x|^2 + 2 noise^2 div f - d noise^2 m,
/// the step followed the estimate's errors, too large where the coarse
/// scans' detail inflated it.  Over the corpus with noise of 0.1-1% of the
/// diagonal along the normals (75 cases, with the earlier probe below),
/// GCV's steps against SURE's: no further than the input 74 against 73, within 10% of the own best step
/// 64 against 62, ahead of windowed sinc's best 57 against 55 (the cow and
/// the elephant at 1% 9-11% nearer the clean mesh, nefertiti at 1% 13%
/// further); with isotropic noise 75 against 73, 47 against 43 and 40
/// against 33.  Stein's estimate with `noise` is the step's estimated error
/// (StepChoice::EstimatedError), which decides the shape's detail and the
/// operator.  The divergence over the noise's directions is estimated by a
/// finite difference in a random direction (Monte-Carlo SURE, Ramani, Blu and
/// Unser 2008): with `perturbed` = x + epsilon (b_i n_i + tangential t_i),
/// b_i random signs and t_i a tangent vector of random signs along two unit
/// tangents,
///     div f ~ sum_i (perturbed_i - x_i) . (f(perturbed)_i - f(x)_i) / epsilon^2,
/// and GCV's d m by the same sum with f the identity (exactly d m where
/// every moving point has a normal), so that its denominator, the trace of
/// the identity less f's, is estimated in one piece and vanishes with the
/// step.  (With random signs per coordinate taken along the normals, of unit
/// variance but lengths from 0 to 3, the estimate of f's trace at small
/// steps was a few percent of the points off d m: the denominator of GCV
/// stayed there while its numerator vanished, and its least value went to
/// the smallest steps - the cactus with noise of 1% was left as it is,
/// 0.0095 of the diagonal from the clean mesh, where a step chosen so ends
/// 0.0074.  Over the corpus with noise of 0.1-1% along the normals: no
/// further than the input 74 -> 75 of 75, within 10% of the own best step
/// 64 -> 67, ahead of windowed sinc's best 57 -> 59; with isotropic noise
/// 75, 47 -> 48 and 40.  Where the surface has few points the result still
/// depends on the probe's draw: over the corpus another bit of the same
/// hash gave 74, 66 and 59.)
/// The whole run counts (the operator is rebuilt from the noisy points, the
/// invariant restored), not only its linear part: on bunny00 with noise of
/// 0.3% of the diagonal, the divergence of the steps with the operator held
/// fixed was a fraction of the run's, and its risk 0 where the error was
/// half the noise.  The steps tried are unit 2^(j/2): from j = 0 downhill
/// by factors of 4 (between unit 2^-16 and unit 2^12), then refined at the
/// vertex of the parabola through the GCV of the last three (in j); 0 when
/// no step is estimated to come closer than the input (with `noise`, or
/// where Stein's estimate with it is above the input's risk, with GCV's
/// own estimate of the noise at the step where that is larger).  `moving`: per
/// vertex, non-zero where the run may move it.  Collective on a split
/// surface (the sums over the owned points of all).
StepChoice ChooseTimeStep(const SmoothingRun& run, const std::vector<double>& x, const std::vector<double>& perturbed,
  double epsilon, const std::vector<std::uint8_t>& moving, double noise, double tangential, double unit,
  const Partition* split);

/// The operator of a step at the points p with the options o, into L
/// (Fairing.cxx's AssembleOperator, with the run's roles and split).
using OperatorAssembly = std::function<void(const double* p, const FairingOptions& o, GraphLaplacian& L)>;

/// TimeStep 0: the noise of the input's geometry and the step of least
/// estimated error (ChooseTimeStep) for the run's steps with the isotropic
/// weights (an anisotropic run's weights depend on the step) and the
/// invariant; into the report, the step in physical units.  No step is
/// searched below NoNoise; the noise is taken as isotropic where
/// IsotropicNoise says so.  `order`: the solver's renumbering of the
/// surface graph, computed here if empty.  `warn` gets the sentences for
/// the user (a step at the search's end; a surface left as it is).  The
/// choice's Start: where the run of the chosen step may start.
StepChoice ChooseStep(const MeshTopology& topo, const double* x, const FairingOptions& opt, const VertexRoles& roles,
  const std::vector<std::uint8_t>& held, const InvariantState& inv, const OperatorAssembly& assemble, double unit,
  std::vector<Index>& order, const Partition* split, std::ostringstream& warn, FairingReport& report);

/// A chosen step on a surface of more than SampledSearchRatio times
/// FairingOptions::StepSearchPoints points is chosen on a sample of
/// StepSearchPoints of them, SampledPatches balls around points spread by
/// a hash of their coordinates (cut out with the cut held fixed, no
/// invariant), and the whole surface run once with it: the search's runs,
/// two per step tried, cost the sample's size instead of the surface's.  On
/// bunny00 Loop-subdivided twice (1.2M triangles) with noise of 0.075% of
/// the diagonal, the whole surface's search took 71 s for the umbrella's
/// step 22.6; four patches of 30k points each chose 22.6 in 1.6-1.8 s (with
/// noise of 0.3%: 256 on three, 181 on one, the whole surface's 256).  With
/// the sample: 7.2 s, 0.249 of the noise from the clean surface in RMS (the
/// whole search 0.252); 2.3 s at 0.3% (8.2 s), the same step; Loop-
/// subdivided four times (19.3M triangles) with noise of 0.075%, 20-27 s
/// and 5.0 GB instead of 116-119 s and 9.05 GB.
constexpr std::int64_t SampledSearchRatio = 4;
constexpr std::size_t SampledPatches = 8;

/// The unit of the time step for mean edge length h: h^(2k) for an operator
/// of degree k (a combination's terms are c_k (h^2 L)^k), 1 for the
/// dimensionless umbrella.
inline double StepUnitOf(double h, int degree, FairingOperator op)
{
  double unit = 1.0;
  for (int k = 0; k < 2 * degree && op != FairingOperator::Umbrella; ++k)
  {
    unit *= h;
  }
  return unit;
}

/// FairSurface with TimeStep 0 on a surface of more than SampledSearchRatio
/// times StepSearchPoints points: the step, and with LeastEstimatedError the
/// operator, chosen on a sample of it (the sample's own run with the
/// options, on process 0 where the surface is split: the serial sample and
/// choice), the whole surface then run with them; the report the whole
/// run's with the choice's figures (the noise, the estimated error) and
/// SampledPoints.  None where it does not apply.  Collective on a split
/// surface.
std::optional<FairingReport> FairWithSampledSearch(const MeshTopology& topology, double* points,
  const FairingOptions& options, const FairingConstraints& constraints, const ProgressCallback& progress,
  const Partition* split);

/// FairSurface with FairingOperator::LeastEstimatedError: the curvature flow,
/// or with a chosen time step both it and the umbrella, the run of the lower
/// estimated error kept (see FairingOperator).
FairingReport FairWithEitherOperator(const MeshTopology& topology, double* points, const FairingOptions& options,
  const FairingConstraints& constraints, const ProgressCallback& progress, const Partition* split);

} // namespace beltrami::detail
