#include "Mesh/HarmonicExtension.h"

#include <algorithm>
#include <vector>

namespace beltrami
{

HarmonicExtensionReport ExtendHarmonically(const GraphLaplacian& laplacian, const std::uint8_t* known,
  int columns, double* values, double tolerance, int maximumIterations, int numThreads)
{
  HarmonicExtensionReport report;
  const Index n = laplacian.NumberOfVertices;
  const std::vector<double> zero(static_cast<std::size_t>(n) * std::min(columns, 8), 0.0);
  for (int first = 0; first < columns; first += 8) // the graph solver takes up to 8 columns
  {
    const int nc = std::min(8, columns - first);
    std::vector<double> x(static_cast<std::size_t>(n) * nc);
    for (Index i = 0; i < n; ++i)
    {
      std::copy(values + i * columns + first, values + i * columns + first + nc, &x[i * nc]);
    }
    ShiftedLaplacianProblem pb = laplacian.Problem(nc); // K x = 0 off the known rows
    pb.Fixed = known;
    pb.Scale.assign(nc, 1.0);
    pb.Tolerance = tolerance;
    pb.MaximumIterations = maximumIterations;
    pb.NumberOfThreads = numThreads;
    const ConjugateGradientResult r = SolveShiftedLaplacian(pb, zero.data(), x.data());
    report.Iterations += r.Iterations;
    report.Converged = report.Converged && r.Converged;
    for (Index i = 0; i < n; ++i)
    {
      if (!known[i])
      {
        std::copy(&x[i * nc], &x[i * nc] + nc, values + i * columns + first);
      }
    }
  }
  return report;
}

} // namespace beltrami
