#include "Flows/GraphFlowDiscretization.h"

#include "Mesh/Laplacian.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>

namespace beltrami::detail
{


std::string CheckOptions(const GraphFlowOptions& o, int components, int maximum, const std::string& what)
{
  if (components < 1 || components > maximum)
  {
    return what + " with 1 to " + std::to_string(maximum) + " components are supported";
  }
  if (!(o.ContrastScale > 0.0) || !std::isfinite(o.ContrastScale))
  {
    return "the contrast scale (alpha) must be positive and finite";
  }
  if (!(o.EdgeContrast >= -1.0) || !(o.EdgeContrast <= 10.0))
  {
    return "the edge contrast (gamma) must be in [-1, 10]";
  }
  if (!(o.TimeStep >= 0.0) || !std::isfinite(o.TimeStep))
  {
    return "the time step must be positive (or 0: automatic) and finite";
  }
  if (o.NumberOfIterations < 0)
  {
    return "the number of iterations must not be negative";
  }
  if (!(o.NoiseLevel >= 0.0) || !std::isfinite(o.NoiseLevel))
  {
    return "the noise level must be >= 0 and finite";
  }
  return {};
}


namespace
{

/// The state of one run of the time loop (section 3.8.5) and its stages.
class FlowIntegrator
{
public:
  FlowIntegrator(FlowDiscretization& disc, const GraphFlowOptions& o)
    : Disc(disc)
    , O(o)
    , N(disc.Size)
    , NC(disc.Components)
    , Size(static_cast<std::size_t>(disc.Size) * disc.Components)
    , Alpha(o.ContrastScale)
    , Threads(o.NumberOfThreads)
  {
  }

  GraphFlowResult Run(double* values, const ProgressCallback& progress);

private:
  FlowDiscretization& Disc;
  const GraphFlowOptions& O;
  const Index N;
  const int NC;
  const std::size_t Size;
  const double Alpha;
  const int Threads;
  GraphFlowResult Result;
  LargeVector<double> U, U0, Next, Rhs, Shift, Diag;
  std::vector<Index> Order; // the graph solver's renumbering (meshes)
  std::vector<double> Scratch;

  bool Start(const double* values);
  void ExplicitStep(double dt);
  void SemiImplicitStep(double dt);
  void SolveOnGraph(const GraphLaplacian& graph, const std::vector<double>& scale);
  void SolveMatrixFree(const std::vector<double>& scale);
  /// Section 3.8.5: the step grows with the relative decrease of the area.
  void AdaptStep(double previousArea, double& dt, double& previousRate) const;
  /// The fraction of the last step (Next -> U) at which the change reaches the noise level.
  double NoiseLevelFraction();
  void Finish(double* values, const ProgressCallback& progress);

  /// The user's measure, on the values in data units.
  double Measured(const LargeVector<double>& x)
  {
    Scratch.resize(Size);
    for (std::size_t k = 0; k < Size; ++k)
    {
      Scratch[k] = x[k] / Alpha;
    }
    return O.ChangeMeasure(Scratch.data());
  }

  double RMSChange()
  {
    if (O.ChangeMeasure)
    {
      return Measured(U);
    }
    const double s = ParallelSum(static_cast<std::int64_t>(Size), 1, Threads,
      [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t k = b; k < e; ++k)
        {
          acc[0] += (U[k] - U0[k]) * (U[k] - U0[k]);
        }
      })[0];
    return Size ? std::sqrt(s / static_cast<double>(Size)) / Alpha : 0.0;
  }
};

bool FlowIntegrator::Start(const double* values)
{
  for (std::size_t k = 0; k < Size; ++k)
  {
    if (!std::isfinite(values[k]))
    {
      Result.Error = "the data contain NaN or infinite values";
      return false;
    }
  }
  U.resize(Size);
  U0.resize(Size);
  Next.resize(Size);
  if (O.Integration == GraphFlowIntegration::SemiImplicit)
  {
    Rhs.resize(Size);
    Shift.resize(N);
  }
  for (std::size_t k = 0; k < Size; ++k)
  {
    U0[k] = U[k] = Alpha * values[k];
  }
  return true;
}

void FlowIntegrator::ExplicitStep(double dt)
{
  // Velocity is zero at fixed vertices: one flat loop over all values.
  ParallelFor(static_cast<std::int64_t>(Size), Threads, [&](std::int64_t b, std::int64_t e) {
    const double* __restrict v = Disc.Velocity.data();
    const double* __restrict x = U.data();
    double* __restrict y = Next.data();
    for (std::int64_t j = b; j < e; ++j)
    {
      y[j] = x[j] - dt * v[j];
    }
  });
}

void FlowIntegrator::SemiImplicitStep(double dt)
{
  // (D + K_int) u' = D u - (K u - K_int u), D_i = a_i / (dt s_i): the
  // ghost values beyond the image border are those of the current state.
  Disc.Apply(U.data(), Next.data(), false);
  ParallelFor(N, Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      const double d = Disc.Mass[i] / (dt * Disc.Speed[i]);
      Shift[i] = d;
      for (int k = 0; k < NC; ++k)
      {
        const std::int64_t j = i * NC + k;
        Rhs[j] = d * U[j] - (Disc.KU[j] - Next[j]);
      }
    }
  });
  std::vector<double> scale = ParallelSum(N, NC, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
    for (std::int64_t i = b; i < e; ++i)
    {
      for (int k = 0; k < NC; ++k)
      {
        acc[k] += Rhs[i * NC + k] * Rhs[i * NC + k];
      }
    }
  });
  for (double& s : scale)
  {
    s = std::sqrt(s) + 1e-300;
  }
  Next = U; // initial guess and fixed values
  if (const GraphLaplacian* graph = Disc.Graph())
  {
    SolveOnGraph(*graph, scale);
  }
  else
  {
    SolveMatrixFree(scale);
  }
}

void FlowIntegrator::SolveOnGraph(const GraphLaplacian& graph, const std::vector<double>& scale)
{
  ShiftedLaplacianProblem sl = graph.Problem(NC);
  sl.Shift = Shift.data();
  sl.Fixed = Disc.Fixed.data();
  if (Order.empty())
  {
    Order = LocalityOrder(N, graph.Offsets, graph.Neighbors); // the graph stays
  }
  sl.Order = Order.data();
  sl.Scale = scale;
  sl.Tolerance = O.SolverTolerance;
  sl.MaximumIterations = O.MaximumSolverIterations;
  sl.NumberOfThreads = Threads;
  Result.SolverIterations += SolveShiftedLaplacian(sl, Rhs.data(), Next.data()).Iterations;
}

void FlowIntegrator::SolveMatrixFree(const std::vector<double>& scale)
{
  Diag.resize(N);
  ParallelFor(N, Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      Diag[i] = Shift[i] + Disc.Diagonal[i]; // Jacobi
    }
  });
  ConjugateGradientProblem cg;
  cg.Rows = N;
  cg.Columns = NC;
  cg.Diagonal = Diag.data();
  cg.Fixed = Disc.Fixed.data();
  cg.Scale = scale;
  cg.Tolerance = O.SolverTolerance;
  cg.MaximumIterations = O.MaximumSolverIterations;
  cg.NumberOfThreads = Threads;
  cg.Apply = [&](const double* x, double* y) {
    Disc.Apply(x, y, false);
    ParallelFor(N, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        for (int k = 0; k < NC; ++k)
        {
          y[i * NC + k] += Shift[i] * x[i * NC + k];
        }
      }
    });
  };
  Result.SolverIterations += SolveConjugateGradient(cg, Rhs.data(), Next.data()).Iterations;
}

void FlowIntegrator::AdaptStep(double previousArea, double& dt, double& previousRate) const
{
  // A large change of the total area means much noise was removed and a
  // larger step is safe; when the change slows down the step shrinks so that
  // the structure of the data is not flattened.
  const double rate = previousArea > 0.0 ? (previousArea - Disc.Area) / (previousArea * dt) : 0.0;
  if (previousRate > 0.0 && rate > 0.0)
  {
    dt *= std::min(2.0, std::max(0.5, rate / previousRate));
  }
  previousRate = rate;
}

double FlowIntegrator::NoiseLevelFraction()
{
  if (O.ChangeMeasure)
  {
    // A measure of its own: its square taken as quadratic along the step,
    // through t = 0, 1/2 and 1.
    const double m0 = std::pow(Measured(Next), 2), m1 = std::pow(RMSChange(), 2);
    LargeVector<double> half(Size);
    for (std::size_t k = 0; k < Size; ++k)
    {
      half[k] = 0.5 * (Next[k] + U[k]);
    }
    const double mh = std::pow(Measured(half), 2), goal = O.NoiseLevel * O.NoiseLevel;
    // m(t) = m0 + b t + c t^2
    const double c = 2.0 * (m1 + m0 - 2.0 * mh), b = m1 - m0 - c;
    double t = 1.0;
    if (std::abs(c) > 1e-300)
    {
      const double d2 = b * b - 4.0 * c * (m0 - goal);
      t = d2 >= 0.0 ? (-b + (c > 0 ? 1 : -1) * std::sqrt(d2)) / (2.0 * c) : 1.0;
    }
    else if (std::abs(b) > 0.0)
    {
      t = (goal - m0) / b;
    }
    return std::isfinite(t) ? std::min(1.0, std::max(0.0, t)) : 1.0;
  }
  // The RMS change: |a + t d|^2 = target along the step.
  std::vector<double> s = ParallelSum(static_cast<std::int64_t>(Size), 3, Threads,
    [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t k = b; k < e; ++k)
      {
        const double a = Next[k] - U0[k], d = U[k] - Next[k];
        acc[0] += a * a;
        acc[1] += a * d;
        acc[2] += d * d;
      }
    });
  const double target = static_cast<double>(Size) * std::pow(O.NoiseLevel * Alpha, 2);
  const double disc2 = s[1] * s[1] - s[2] * (s[0] - target);
  return s[2] > 0.0 && disc2 >= 0.0 ? std::min(1.0, std::max(0.0, (-s[1] + std::sqrt(disc2)) / s[2])) : 1.0;
}

void FlowIntegrator::Finish(double* values, const ProgressCallback& progress)
{
  Result.RMSChange = RMSChange();
  for (Index i = 0; i < N; ++i)
  {
    if (!Disc.Fixed[i]) // fixed values stay bit-exact (no round trip through alpha)
    {
      for (int k = 0; k < NC; ++k)
      {
        values[i * NC + k] = U[i * NC + k] / Alpha;
      }
    }
  }
  if (progress)
  {
    progress(1.0);
  }
}

GraphFlowResult FlowIntegrator::Run(double* values, const ProgressCallback& progress)
{
  if (!Start(values))
  {
    return Result;
  }
  const bool explicitSteps = O.Integration == GraphFlowIntegration::Explicit;
  Disc.Update(U.data());
  Result.InitialArea = Result.FinalArea = Disc.Area;
  Result.SmallestStableStep = Disc.MaxRate > 0.0 ? 1.0 / Disc.MaxRate : HUGE_VAL;
  double dt = O.TimeStep > 0.0 ? O.TimeStep : Disc.AutomaticTimeStep;
  if (O.AdaptiveTimeStep && explicitSteps)
  {
    dt = std::min(dt, 0.9 * Result.SmallestStableStep);
  }
  double previousRate = -1.0; // relative area decrease per unit time, last step
  for (int it = 0; it < O.NumberOfIterations; ++it)
  {
    if (progress && !progress(static_cast<double>(it) / O.NumberOfIterations))
    {
      Result.Completed = false;
      break;
    }
    const double stable = Disc.MaxRate > 0.0 ? 1.0 / Disc.MaxRate : HUGE_VAL;
    Result.SmallestStableStep = std::min(Result.SmallestStableStep, stable);
    if (explicitSteps && O.AdaptiveTimeStep)
    {
      dt = std::min(dt, 0.9 * stable);
    }
    else if (explicitSteps && dt > stable)
    {
      ++Result.UnstableSteps;
    }
    explicitSteps ? ExplicitStep(dt) : SemiImplicitStep(dt);
    U.swap(Next);
    const double previousArea = Disc.Area;
    Disc.Update(U.data());
    ++Result.Iterations;
    Result.Time += dt;
    Result.LastTimeStep = dt;
    Result.FinalArea = Disc.Area;
    if (O.AdaptiveTimeStep)
    {
      AdaptStep(previousArea, dt, previousRate);
    }
    if (O.NoiseLevel > 0.0 && RMSChange() >= O.NoiseLevel)
    {
      // Discrepancy reached within this step: go back along it to the point
      // where the change equals the noise level.
      const double t = NoiseLevelFraction();
      if (t < 1.0)
      {
        for (std::size_t k = 0; k < Size; ++k)
        {
          U[k] = Next[k] + t * (U[k] - Next[k]);
        }
        Result.Time -= (1.0 - t) * dt;
        Result.LastTimeStep = t * dt;
        Disc.Update(U.data());
        Result.FinalArea = Disc.Area;
      }
      break;
    }
  }
  Finish(values, progress);
  return Result;
}

} // namespace

GraphFlowResult Integrate(FlowDiscretization& disc, double* values, const GraphFlowOptions& o,
  const ProgressCallback& progress)
{
  return FlowIntegrator(disc, o).Run(values, progress);
}

} // namespace beltrami::detail
