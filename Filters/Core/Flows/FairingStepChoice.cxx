#include "Flows/FairingStepChoice.h"

#include <algorithm>
#include <utility>
#include <cmath>
#include <limits>
#include <map>

namespace beltrami::detail
{

namespace
{

/// The sums of the risk over the moving points this process owns (and over
/// the processes): |f(x) - x|^2, the divergence, the points.
struct RiskTerms
{
  double Moved = 0.0, Divergence = 0.0, Points = 0.0;
  bool Defined = true;
};

RiskTerms TermsAt(const SmoothingRun& run, const std::vector<double>& x, const std::vector<double>& perturbed,
  double epsilon, const std::vector<std::uint8_t>& moving, const Partition* split, double dt)
{
  std::vector<double> f = x, g = perturbed;
  if (!run(dt, f.data()) || !run(dt, g.data()))
  {
    RiskTerms undefined;
    undefined.Defined = false;
    return undefined;
  }
  double sums[3] = { 0.0, 0.0, 0.0 };
  for (std::size_t i = 0; i < moving.size(); ++i)
  {
    if (moving[i] && (!split || split->IsOwned(static_cast<Index>(i))))
    {
      for (std::size_t k = 3 * i; k < 3 * i + 3; ++k)
      {
        sums[0] += (f[k] - x[k]) * (f[k] - x[k]);
        sums[1] += (perturbed[k] - x[k]) * (g[k] - f[k]) / (epsilon * epsilon);
      }
      sums[2] += 1.0;
    }
  }
  for (double& s : sums)
  {
    s = split ? split->Sum(s) : s;
  }
  return { sums[0], sums[1], sums[2], true };
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
  const double variance = noise * noise;
  const double directions = 1.0 + 2.0 * tangential * tangential; // the input's risk per point, in noise^2
  double points = 0.0;
  std::map<int, double> risks; // by j, the step unit 2^(j/2)
  const auto risk = [&](int j) {
    const auto known = risks.find(j);
    if (known != risks.end())
    {
      return known->second;
    }
    const RiskTerms t = TermsAt(run, x, perturbed, epsilon, moving, split, unit * std::exp2(0.5 * j));
    ++choice.Evaluations;
    points = std::max(points, t.Points);
    return risks[j] = t.Defined ? t.Moved + 2.0 * variance * t.Divergence - directions * variance * t.Points
                                : std::numeric_limits<double>::infinity();
  };
  constexpr int Lowest = -32, Highest = 24;
  int best = 0;
  const int direction = risk(4) < risk(0) ? 4 : -4;
  while (best + direction >= Lowest && best + direction <= Highest && risk(best + direction) < risk(best))
  {
    best += direction;
  }
  choice.AtLimit = best == Lowest || best == Highest;
  for (int d : { 2, 1 })
  {
    if (best + d <= Highest && risk(best + d) < risk(best))
    {
      best += d;
    }
    else if (best - d >= Lowest && risk(best - d) < risk(best))
    {
      best -= d;
    }
  }
  // The input's own risk is noise^2 per moving point and direction.  White noise is what
  // the flows remove best; where the best step is estimated to leave more
  // than MostKeptNoise of it, most of the "noise" is the shape's own detail
  // at the scale of the triangles (coarse meshes), which the flows cannot
  // tell from noise: the points are left as they are.
  const double input = noise * std::sqrt(directions);
  const double error = points > 0.0 ? std::sqrt(std::max(0.0, risk(best)) / points) : input;
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
  return choice;
}

/// Operator LeastEstimatedError: the curvature flow, or with a chosen time
/// step both it and the umbrella, the run of the lower estimated error kept.
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
  if (report.Completed && report.Error.empty() && report.MedianDihedral < 52.0)
  {
    std::vector<double> curvature(points, points + size);
    opt.Operator = FairingOperator::CurvatureFlow;
    opt.KnownNoise = report.Noise; // (the same input)
    opt.KnownMedianDihedral = report.MedianDihedral;
    FairingReport flow = FairSurface(topo, curvature.data(), opt, cons, progress, split);
    if (flow.Error.empty() && flow.EstimatedError <= report.EstimatedError)
    {
      report = std::move(flow);
      umbrella.swap(curvature);
    }
  }
  std::copy(umbrella.begin(), umbrella.end(), points);
  return report;
}

} // namespace beltrami::detail
