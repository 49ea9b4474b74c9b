#include "Drawing/FieldSmoothing.h"

#include "Flows/Fairing.h"

#include <algorithm>
#include <cmath>

namespace beltrami
{

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
  std::vector<double> copy(points, points + 3 * static_cast<std::size_t>(topology.NumberOfVertices()));
  for (double& x : copy)
  {
    x = std::ldexp(x, -exponent);
  }
  FairingOptions options;
  options.Operator = FairingOperator::CurvatureFlow;
  options.Order = 1;
  options.Integration = FairingIntegration::Implicit;
  options.Units = LengthUnit::Physical;
  options.TimeStep = std::ldexp(length, -exponent) * std::ldexp(length, -exponent);
  options.Invariant = FairingInvariant::None;
  options.Boundary = FairingBoundary::Fixed;
  options.SolverTolerance = 1e-8; // (split runs: the serial copy to about 1e-9 of the diagonal)
  options.OperatorMollification = 0.0;
  options.NumberOfThreads = numThreads;
  const FairingReport report = FairSurface(topology, copy.data(), options, {}, {}, split);
  if (!report.Error.empty())
  {
    warning = report.Error;
    return {};
  }
  for (double& x : copy)
  {
    x = std::ldexp(x, exponent);
  }
  return copy;
}

} // namespace beltrami
