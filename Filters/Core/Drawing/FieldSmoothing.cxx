#include "Drawing/FieldSmoothing.h"

#include "Flows/Fairing.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace beltrami
{

namespace
{

/// The farthest, in smoothing lengths, that the faired copy may move a point.
/// Over the corpus and the generated hard shapes the step moves points at
/// most 0.83 lengths (the mechanical part's slivers); where triangles of no
/// area sit beside folded ones (a bunny with a thousandth of its triangles
/// flattened onto an edge, as exports and marching cubes leave them), the
/// cotangents of the folds, millions in size and of either sign, made the
/// step move points 2.5e8 lengths, and the visibility's tests along such
/// lines took all memory.
constexpr double MostFairedMove = 8.0;

/// The largest distance of a point of `copy` from its point in `points`, in
/// units of `length` (infinite where a point is not finite; split: over every
/// process' owned points).
double LargestMove(const std::vector<double>& copy, const double* points, double length, const Partition* split)
{
  double largest = 0.0;
  for (std::size_t i = 0; i < copy.size() / 3; ++i)
  {
    if (split && !split->IsOwned(static_cast<Index>(i)))
    {
      continue;
    }
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      d2 += (copy[3 * i + k] - points[3 * i + k]) * (copy[3 * i + k] - points[3 * i + k]);
    }
    largest = std::isfinite(d2) ? std::max(largest, std::sqrt(d2) / length) : std::numeric_limits<double>::infinity();
  }
  return split ? split->Max(largest) : largest;
}

/// One implicit curvature-flow step of time length^2 of the copy, at the
/// scale of the length by `exponent` (`mollified`: its operator on the
/// mollified copy of the points, FairingOptions::OperatorMollification).
FairingReport FairOnce(const MeshTopology& topology, std::vector<double>& copy, double length, int exponent,
  bool mollified, int numThreads, const Partition* split)
{
  FairingOptions options; // (its OperatorMollification where `mollified`)
  options.Operator = FairingOperator::CurvatureFlow;
  options.Order = 1;
  options.Integration = FairingIntegration::Implicit;
  options.Units = LengthUnit::Physical;
  options.TimeStep = std::ldexp(length, -exponent) * std::ldexp(length, -exponent);
  options.Invariant = FairingInvariant::None;
  options.Boundary = FairingBoundary::Fixed;
  options.SolverTolerance = 1e-8; // (split runs: the serial copy to about 1e-9 of the diagonal)
  options.OperatorMollification = mollified ? options.OperatorMollification : 0.0;
  options.NumberOfThreads = numThreads;
  return FairSurface(topology, copy.data(), options, {}, {}, split);
}

} // namespace

std::vector<double> FairedCopy(const MeshTopology& topology, const double* points, double length, int numThreads,
  const Partition* split, std::string& warning)
{
  warning.clear();
  if (!(length > 0.0) || !std::isfinite(length))
  {
    warning = "no length to smooth over";
    return {};
  }
  const int exponent = std::ilogb(length); // (length = m 2^exponent, 1 <= m < 2)
  std::vector<double> scaled(points, points + 3 * static_cast<std::size_t>(topology.NumberOfVertices()));
  for (double& x : scaled)
  {
    x = std::ldexp(x, -exponent);
  }
  // The operator on the points themselves; where that step is unstable
  // (MostFairedMove), on the mollified copy, which evens out the folds.
  double moved = 0.0;
  for (const bool mollified : { false, true })
  {
    std::vector<double> copy = scaled;
    const FairingReport report = FairOnce(topology, copy, length, exponent, mollified, numThreads, split);
    if (!report.Error.empty())
    {
      warning = report.Error;
      return {};
    }
    for (double& x : copy)
    {
      x = std::ldexp(x, exponent);
    }
    moved = LargestMove(copy, points, length, split);
    if (moved <= MostFairedMove)
    {
      return copy;
    }
  }
  std::ostringstream said;
  said << "the smoothing step moved points " << moved
       << " times its length (triangles of no area beside folded ones make its operator unstable)";
  warning = said.str();
  return {};
}

} // namespace beltrami
