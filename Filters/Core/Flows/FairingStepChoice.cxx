#include "Flows/FairingStepChoice.h"

#include "Flows/FairingSteps.h"
#include "Flows/NoiseEstimation.h"
#include "Mesh/Curvatures.h"
#include "Mesh/MeshMeasures.h"
#include "Solvers/SparseGraph.h"

#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <limits>
#include <map>

namespace beltrami::detail
{

namespace
{

/// x with each point moved by epsilon times a sign along its unit normal
/// and, times `tangentialShare`, times signs along two unit vectors of its
/// tangent plane (the signs from a hash of the point, so a split surface
/// draws the serial ones): a perturbation of deviation epsilon along the
/// normals (and tangentialShare epsilon across) for the risk's divergence,
/// of the same length at every point.
std::vector<double> PerturbedAlongNormals(const std::vector<double>& normals, const double* x, double epsilon,
  double tangentialShare, const Partition* split)
{
  const std::size_t size = normals.size();
  std::vector<double> perturbed(x, x + size);
  for (std::size_t i = 0; i < size; i += 3)
  {
    const Vec3 n = Point(normals.data(), static_cast<Index>(i / 3));
    if (!n.allFinite() || !(n.squaredNorm() > 0.25))
    {
      continue; // (no normal: not perturbed, and not counted in RiskTerms::Probe)
    }
    const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const std::uint64_t hash = PointHash(x + i);
    const auto sign = [&](int bit) { return (hash >> bit) & 1 ? epsilon : -epsilon; };
    const Vec3 move = sign(0) * n + tangentialShare * (sign(1) * t1 + sign(2) * t2);
    for (int c = 0; c < 3; ++c)
    {
      perturbed[i + c] += move[c];
    }
  }
  if (split)
  {
    split->UpdateGhosts(perturbed.data(), 3); // the ghosts' normals are not all here
  }
  return perturbed;
}

/// The octaves of a point's |f(x)_i - x_i|^2 over the mean of all that
/// RiskTerms counts (from 2^-MoveOctaves/2 of the mean; the last open).
constexpr int MoveOctaves = 64;

/// Octaves above the median's that RiskNoise still counts as noise (a
/// point's move 32-64 times the median move: white noise's square moves
/// lie beyond in one case of 10^4).
constexpr int NoiseOctaves = 5;

/// The sums of the risk over the moving points this process owns (and over
/// the processes): |f(x) - x|^2, the divergence, the points, and the
/// probe's |perturbed - x|^2 / epsilon^2 (the same estimate of the trace of
/// the identity: d per point that has a normal).
struct RiskTerms
{
  double Moved = 0.0, Divergence = 0.0, Points = 0.0, Probe = 0.0;
  bool Defined = true;
  /// The points' |f(x)_i - x_i|^2 by octave of their ratio to the mean
  /// (MoveOctaves): how many in each, and their sum.
  std::array<double, 2 * MoveOctaves> Octaves{};
};

/// Where the next runs from x and from the perturbed points start
/// (SmoothingRun's `start`).
struct RunStarts
{
  RunStart F, G;
};

/// The deviation of the noise, per direction, that cross-validation's
/// terms imply: |f(x) - x|^2 over the trace of the identity less f's (the
/// residual's expected part of white noise; Wahba 1990, 4.7), of the
/// points whose moves are white noise's: those more than NoiseOctaves
/// octaves above the median move are the shape's outliers (needles one
/// vertex wide, which every step shrinks), and the trace is taken in
/// proportion to the points counted.  On a sphere with 100 such needles
/// and noise of 1% of the diagonal along the normals, the needles' moves
/// were half of |f(x) - x|^2 at the chosen step and took the estimate to
/// 1.48 times the added noise, and the step that flattened them left the
/// mesh 1.08 times as far from the clean one as the input; without them
/// 1.0 times, and the mesh is left as it is.  Over the corpus with noise
/// along the normals or in every direction (150 cases) and 16 other
/// generated shapes with noise along the normals (48), nothing else changes.
double RiskNoise(const RiskTerms& t)
{
  const double freedom = t.Probe - t.Divergence;
  if (!t.Defined || !(freedom > 0.0) || !(t.Points > 0.0))
  {
    return 0.0;
  }
  int median = 0;
  for (double below = t.Octaves[0]; below < 0.5 * t.Points && median + 1 < MoveOctaves;)
  {
    below += t.Octaves[++median];
  }
  double points = 0.0, moved = 0.0;
  for (int k = 0; k <= std::min(median + NoiseOctaves, MoveOctaves - 1); ++k)
  {
    points += t.Octaves[k];
    moved += t.Octaves[MoveOctaves + k];
  }
  return points > 0.0 ? std::sqrt(moved / (freedom * points / t.Points)) : 0.0;
}

RiskTerms TermsAt(const SmoothingRun& run, const std::vector<double>& x, const std::vector<double>& perturbed,
  double epsilon, const std::vector<std::uint8_t>& moving, const Partition* split, double dt, RunStarts& starts)
{
  std::vector<double> f = x, g = perturbed;
  if (!run(dt, f.data(), starts.F) || !run(dt, g.data(), starts.G))
  {
    RiskTerms undefined;
    undefined.Defined = false;
    return undefined;
  }
  double sums[4] = { 0.0, 0.0, 0.0, 0.0 };
  for (std::size_t i = 0; i < moving.size(); ++i)
  {
    if (moving[i] && (!split || split->IsOwned(static_cast<Index>(i))))
    {
      for (std::size_t k = 3 * i; k < 3 * i + 3; ++k)
      {
        sums[0] += (f[k] - x[k]) * (f[k] - x[k]);
        sums[1] += (perturbed[k] - x[k]) * (g[k] - f[k]) / (epsilon * epsilon);
        sums[3] += (perturbed[k] - x[k]) * (perturbed[k] - x[k]) / (epsilon * epsilon);
      }
      sums[2] += 1.0;
    }
  }
  for (double& s : sums)
  {
    s = split ? split->Sum(s) : s;
  }
  RiskTerms terms{ sums[0], sums[1], sums[2], sums[3], true };
  const double mean = sums[2] > 0.0 ? sums[0] / sums[2] : 0.0;
  for (std::size_t i = 0; mean > 0.0 && i < moving.size(); ++i)
  {
    if (moving[i] && (!split || split->IsOwned(static_cast<Index>(i))))
    {
      const double move = (Point(f.data(), static_cast<Index>(i)) - Point(x.data(), static_cast<Index>(i))).squaredNorm();
      const int octave = move > 0.0 ? std::clamp(std::ilogb(move / mean) + MoveOctaves / 2, 0, MoveOctaves - 1) : 0;
      terms.Octaves[octave] += 1.0;
      terms.Octaves[MoveOctaves + octave] += move;
    }
  }
  if (split)
  {
    split->Sum(terms.Octaves.data(), 2 * MoveOctaves);
  }
  return terms;
}

/// A warning of the step's choice: to the run's warnings and the report's
/// StepWarning (which a sampled choice carries to the whole surface).
void WarnOfStep(const std::string& said, std::ostringstream& warn, FairingReport& report)
{
  warn << said;
  report.StepWarning += said;
}

/// The warning for a surface left as it is because its variation at the
/// scale of the triangles looks like its shape rather than noise (only
/// where the variation is one a user could see: CleanVariation).
void WarnShapeDetail(double variation, double h, std::ostringstream& warn, FairingReport& report)
{
  if (variation >= CleanVariation * h)
  {
    std::ostringstream said;
    said << "The surface varies at the scale of its triangles by about " << variation
         << " (standard deviation along the normals), which smoothing cannot tell from noise: it was left as it "
            "is. Set TimeStep to smooth it. ";
    WarnOfStep(said.str(), warn, report);
  }
}

/// The search's last stage, from `best` (j of the step unit 2^(j/2)), whose
/// risk is at most that of best - 4 and best + 4 where they are in range:
/// the risk as a parabola in j through those three, one run at its vertex
/// rounded (kept where it is lower).  The risk is smooth in log dt near its
/// minimum.  Trying best +- 2 and then +- 1 took 2-4 runs where this takes
/// 0-1: over the corpus with noise of 0.1-1% along the normals (75 cases)
/// the defaults' times summed 22.5 -> 15.5 s, 65 cases gave the same
/// results, 7 came 0.8-5.7% nearer the clean mesh and 3 0.4-1.1% further.
/// The risk is not symmetric in j: on a shrinkage whose best step is unit
/// 2^(2/2) the vertex is 3, 1.2% further in RMS.  A second parabola (through
/// the new best and its nearest tried steps) found 2 there, but over the
/// corpus changed 3 cases, two for the worse (5.5% and 0.8% further, one
/// 0.4% nearer): the risk estimate's own error is larger than what a finer
/// step gains.  Where a neighbour is out of range or its risk not finite (a
/// step not defined), those steps of 2 and 1 instead.
template <typename Risk>
int Refined(Risk& risk, int best, int lowest, int highest)
{
  if (best - 4 >= lowest && best + 4 <= highest && std::isfinite(risk(best - 4)) && std::isfinite(risk(best + 4)))
  {
    const double below = risk(best - 4), at = risk(best), above = risk(best + 4);
    const double curvature = below - 2.0 * at + above; // >= |below - above|: the vertex within best +- 2
    const int vertex = curvature > 0.0 ? best + static_cast<int>(std::lround(2.0 * (below - above) / curvature)) : best;
    return vertex != best && risk(vertex) < at ? vertex : best;
  }
  for (int d : { 2, 1 })
  {
    if (best + d <= highest && risk(best + d) < risk(best))
    {
      best += d;
    }
    else if (best - d >= lowest && risk(best - d) < risk(best))
    {
      best -= d;
    }
  }
  return best;
}

} // namespace

StepChoice ChooseTimeStep(const SmoothingRun& run, const std::vector<double>& x, const std::vector<double>& perturbed,
  double epsilon, const std::vector<std::uint8_t>& moving, double noise, double tangential, double unit,
  const Partition* split)
{
  StepChoice choice;
  if (!(noise > 0.0) || !(unit > 0.0) || !(epsilon > 0.0))
  {
    return choice;
  }
  double variance = noise * noise;
  const double directions = 1.0 + 2.0 * tangential * tangential; // the input's risk per point, in noise^2
  double points = 0.0;
  constexpr double Undefined = std::numeric_limits<double>::infinity();
  const auto gcvOf = [&](const RiskTerms& t) { // generalized cross-validation (ChooseTimeStep)
    const double freedom = t.Probe - t.Divergence; // the trace of (I - f') by the same probe
    return t.Defined && freedom > 0.0 ? t.Moved / (freedom * freedom) : Undefined;
  };
  std::map<int, RiskTerms> terms; // by j, the step unit 2^(j/2)
  RunStarts starts;
  double least = Undefined; // the least GCV so far, whose run's start is kept (the search ends there)
  const auto at = [&](int j) -> const RiskTerms& {
    auto known = terms.find(j);
    if (known == terms.end())
    {
      known = terms.emplace(j, TermsAt(run, x, perturbed, epsilon, moving, split, unit * std::exp2(0.5 * j), starts))
                .first;
      ++choice.Evaluations;
      points = std::max(points, known->second.Points);
      if (gcvOf(known->second) < least)
      {
        least = gcvOf(known->second);
        choice.Start = starts.F;
      }
    }
    return known->second;
  };
  const auto sure = [&](int j) {
    const RiskTerms& t = at(j);
    return t.Defined ? t.Moved + 2.0 * variance * t.Divergence - directions * variance * t.Points : Undefined;
  };
  const auto gcv = [&](int j) { return gcvOf(at(j)); };
  constexpr int Lowest = -32, Highest = 24;
  int best = 0;
  const int direction = gcv(4) < gcv(0) ? 4 : -4;
  while (best + direction >= Lowest && best + direction <= Highest && gcv(best + direction) < gcv(best))
  {
    best += direction;
  }
  choice.AtLimit = best == Lowest || best == Highest;
  best = Refined(gcv, best, Lowest, Highest);
  // Where Stein's risk of the best step exceeds the input's, the noise
  // estimate is too low to account for what the step removes (noise that
  // crumples part of the surface, EstimateSurfaceNoise): the noise is taken
  // as cross-validation's own estimate at that step where larger
  // (RiskNoise).  The locally refined cylinder with noise of 1% of the
  // diagonal, its noise estimated at half of it, was left as it was, 0.0100
  // of the diagonal from the clean mesh; so 0.0025 (cross-validation's
  // estimate 1.00 of the noise).  Over the corpus it changes nothing else
  // with noise along the normals; with isotropic noise, in every direction,
  // two more cases come near their best step (larger_sphere at 1%: 0.0128
  // -> 0.0036 of the diagonal, the cylinder at 0.1%), none further.
  if (points > 0.0 && sure(best) >= directions * variance * points)
  {
    variance = std::max(variance, RiskNoise(at(best)) * RiskNoise(at(best)));
    noise = std::sqrt(variance);
  }
  // The input's own risk is noise^2 per moving point and direction.  White
  // noise is what the flows remove best; where the best step is estimated to leave more
  // than MostKeptNoise of it, most of the "noise" is the shape's own detail
  // at the scale of the triangles (coarse meshes), which the flows cannot
  // tell from noise: the points are left as they are.
  const double input = noise * std::sqrt(directions);
  choice.InputError = input;
  const double error = points > 0.0 ? std::sqrt(std::max(0.0, sure(best)) / points) : input;
  choice.ShapeDetail = points > 0.0 && error >= MostKeptNoise * input;
  if (points > 0.0 && !choice.ShapeDetail)
  {
    choice.TimeStep = unit * std::exp2(0.5 * best);
    choice.EstimatedError = error;
  }
  else
  {
    choice.EstimatedError = input;
  }
  if (choice.TimeStep == 0.0 || least != gcv(best))
  {
    choice.Start = {};
  }
  return choice;
}

/// Operator LeastEstimatedError: the curvature flow, or with a chosen time
/// step both it and the umbrella, the run of the lower estimated error kept.
namespace
{

/// The estimated error of run `a`, compared with run `b` of the other
/// operator on the same points: where `a` left the points as they are, the
/// input's risk with the larger of the two noises their risks used (the
/// search that raised its noise, RiskNoise, saw more of it than the other;
/// leaving the points costs the same for both).  On a bumpy plane whose
/// triangles shrink a hundredfold towards a corner, with noise of 1% of the
/// diagonal along the normals (estimated at 0.17 of it), the umbrella's
/// search raised its noise to 1.0 of it and chose unit 2^5.5 (estimated
/// error 0.27 of the input), the curvature flow's, at 0.17, left the points
/// (0.17 of the noise, "less"): the plane was left 1.0 of the noise from the
/// clean one, where the umbrella's step brings it to 0.31.
double LeftError(const FairingReport& a, const FairingReport& b)
{
  return a.ChosenTimeStep > 0.0 ? a.EstimatedError : std::max({ a.EstimatedError, a.InputError, b.InputError });
}

} // namespace

FairingReport FairWithEitherOperator(const MeshTopology& topo, double* points, const FairingOptions& options,
  const FairingConstraints& cons, const ProgressCallback& progress, const Partition* split)
{
  FairingOptions opt = options;
  opt.Operator = FairingOperator::CurvatureFlow;
  if (opt.TimeStep != 0.0 || opt.Integration != FairingIntegration::Implicit || opt.Anisotropic)
  {
    return FairSurface(topo, points, opt, cons, progress, split);
  }
  const std::size_t size = 3 * static_cast<std::size_t>(topo.NumberOfVertices());
  std::vector<double> umbrella(points, points + size);
  opt.Operator = FairingOperator::Umbrella;
  FairingReport report = FairSurface(topo, umbrella.data(), opt, cons, progress, split);
  if (report.Completed && report.Error.empty() && report.MedianDihedral < CrumpledDihedral)
  {
    std::vector<double> curvature(points, points + size);
    opt.Operator = FairingOperator::CurvatureFlow;
    opt.KnownNoise = report.Noise; // (the same input)
    opt.KnownMedianDihedral = report.MedianDihedral;
    opt.KnownWiderNoise = report.WiderNoise;
    opt.KnownLocalNoise = report.LocalNoise;
    FairingReport flow = FairSurface(topo, curvature.data(), opt, cons, progress, split);
    if (flow.Error.empty() && LeftError(flow, report) <= LeftError(report, flow))
    {
      report = std::move(flow);
      umbrella.swap(curvature);
    }
  }
  std::copy(umbrella.begin(), umbrella.end(), points);
  return report;
}

MoveCorrelations MoveCoherence(const MeshTopology& topo, const double* before, const double* after,
  const std::vector<std::uint8_t>& held, const Partition* split)
{
  const MeshTopology::VertexGraph& graph = topo.Graph();
  // Area-weighted unit normals of `after` (NaN where undefined); the
  // ghosts' their owners' (an owner holds its points' whole stars).
  std::vector<double> normals(3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  CurvatureOptions co;
  co.Weighting = NormalWeighting::Area;
  CurvatureOutputs out;
  out.Normals = normals.data();
  ComputeCurvatures(topo, after, co, out);
  if (split)
  {
    split->UpdateGhosts(normals.data(), 3);
  }
  const auto normal = [&](Index v) -> Vec3 {
    const Vec3 n = Point(normals.data(), v);
    return n.allFinite() ? n : Vec3::Zero();
  };
  const auto move = [&](Index v) -> Vec3 { return Point(after, v) - Point(before, v); };
  // In space and along the normals: the products over the edges, the
  // squares over the points; the edges and the points.
  double sums[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  for (Index a = 0; a < topo.NumberOfVertices(); ++a)
  {
    if (held[a])
    {
      continue;
    }
    const Vec3 da = move(a);
    const double sa = da.dot(normal(a));
    if (!split || split->IsOwned(a))
    {
      sums[1] += da.squaredNorm();
      sums[3] += sa * sa;
      sums[5] += 1.0;
    }
    for (std::int64_t k = graph.NeighborOffsets[a]; k < graph.NeighborOffsets[a + 1]; ++k)
    {
      const Index b = graph.Neighbors[k];
      if (b > a && !held[b] && (!split || split->CountsEdge(a, b)))
      {
        const Vec3 db = move(b);
        sums[0] += da.dot(db);
        sums[2] += sa * db.dot(normal(b));
        sums[4] += 1.0;
      }
    }
  }
  if (split)
  {
    split->Sum(sums, 6);
  }
  const auto correlation = [&](double products, double squares) {
    return sums[4] > 0.0 && squares > 0.0 && std::isfinite(products) ? (products / sums[4]) / (squares / sums[5])
                                                                     : 0.0;
  };
  return { correlation(sums[0], sums[1]), correlation(sums[2], sums[3]) };
}

StepChoice ChooseStep(const MeshTopology& topo, const double* x, const FairingOptions& opt, const VertexRoles& roles,
  const std::vector<std::uint8_t>& held, const InvariantState& inv, const OperatorAssembly& assemble, double unit,
  std::vector<Index>& order, const Partition* split, std::ostringstream& warn, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  SurfaceNoise noise;
  noise.Deviation = opt.KnownNoise;
  noise.MedianDihedral = opt.KnownMedianDihedral;
  noise.WiderDeviation = opt.KnownWiderNoise;
  noise.LocalDeviation = opt.KnownLocalNoise;
  if (!(noise.Deviation > 0.0))
  {
    noise = EstimateSurfaceNoise(topo, x, roles.Fixed.data(), split, opt.NumberOfThreads);
  }
  report.Noise = noise.Deviation;
  report.MedianDihedral = noise.MedianDihedral;
  report.WiderNoise = noise.WiderDeviation;
  report.LocalNoise = noise.LocalDeviation;
  const double h = MeanEdgeLength(topo, x, split);
  if (!(noise.Deviation >= NoNoise * h)) // nothing to gain (and no runs to pay for)
  {
    report.EstimatedError = report.InputError = noise.Deviation;
    return {};
  }
  if (noise.WiderDeviation > ShapeGrowth * noise.Deviation) // the shape's own detail (ShapeGrowth)
  {
    report.EstimatedError = report.InputError = noise.Deviation;
    WarnShapeDetail(noise.Deviation, h, warn, report);
    return {};
  }
  GraphLaplacian L;
  // The runs solve to the filter's tolerance: the risk's divergence is the
  // difference of two runs a quarter of the noise apart, far above the solver's
  // error (over the corpus with noise of 0.1-1%, 75 cases, a tolerance of
  // 1e-6 chose the same operators and results, 26% slower).
  FairingOptions o = opt;
  // (Runs of one step start from each other: SmoothingRun's `start`.)
  const SmoothingRun run = [&](double dt, double* p, RunStart& start) {
    o.TimeStep = dt;
    FairingReport scratch;
    const bool oneStep = o.NumberOfIterations == 1;
    for (int step = 0; step < o.NumberOfIterations; ++step)
    {
      assemble(p, o, L);
      if (order.empty() && !split)
      {
        order = LocalityOrder(n, L.Offsets, L.Neighbors);
      }
      const double* guess =
        oneStep && o.Operator == FairingOperator::Umbrella && !start.Points.empty() ? start.Points.data() : nullptr;
      if (!Integrate(Stage{ L, held, roles.Weight, split ? nullptr : order.data(), &roles.Moves, split, guess }, o,
            p, scratch))
      {
        start = {};
        return false;
      }
      if (oneStep)
      {
        start.Points.assign(p, p + 3 * static_cast<std::size_t>(n));
        start.Iterations = scratch.Iterations.empty() ? 0 : scratch.Iterations.back();
      }
      if (inv.Kind != FairingInvariant::None)
      {
        RestoreInvariant(inv, topo, p, o.NumberOfThreads, false);
      }
    }
    return true;
  };
  const std::vector<double> points(x, x + 3 * static_cast<std::size_t>(n));
  const double epsilon = ProbeDeviation * noise.Deviation;
  // Isotropic noise (IsotropicNoise): the same deviation in the tangent
  // planes; its part of the divergence comes from the same probe.
  const std::vector<double> normals = UnitNormals(topo, x, opt.NumberOfThreads);
  const double tangential = EstimateTangentialNoise(topo, x, normals.data(), roles.Fixed.data(), split);
  // (Compared on the same rings: LocalDeviation.)
  const double share = IsotropicNoise(noise.LocalDeviation, tangential, h) ? 1.0 : 0.0;
  report.TangentialNoise = share * noise.Deviation;
  const std::vector<double> perturbed = PerturbedAlongNormals(normals, x, epsilon, share, split);
  std::vector<std::uint8_t> moving(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
  {
    moving[i] = !held[i];
  }
  StepChoice choice =
    ChooseTimeStep(run, points, perturbed, epsilon, moving, noise.Deviation, share, unit, split);
  report.ChosenTimeStep = choice.TimeStep;
  report.EstimatedError = choice.EstimatedError;
  report.InputError = choice.InputError;
  if (choice.AtLimit && choice.TimeStep > 0.0)
  {
    std::ostringstream said;
    said << "The time step chosen is the " << (choice.TimeStep > unit ? "largest" : "smallest")
         << " the search tries (" << (choice.TimeStep > unit ? "4096" : "1/65536")
         << " times its unit, h^(2k) for order k with h the mean edge length, 1 for the umbrella); a step "
            "beyond may be better: set TimeStep. ";
    WarnOfStep(said.str(), warn, report);
  }
  if (choice.ShapeDetail)
  {
    WarnShapeDetail(noise.Deviation, h, warn, report);
  }
  return choice;
}

} // namespace beltrami::detail
