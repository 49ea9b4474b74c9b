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
  if (!(o.TimeStep > 0.0) || !std::isfinite(o.TimeStep))
  {
    return "the time step must be positive and finite";
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


GraphFlowResult Integrate(FlowDiscretization& disc, double* values, const GraphFlowOptions& o,
  const ProgressCallback& progress)
{
  GraphFlowResult result;
  const int nc = disc.Components;
  const Index n = disc.Size;
  const std::size_t size = static_cast<std::size_t>(n) * nc;
  const double alpha = o.ContrastScale;
  const int threads = o.NumberOfThreads;
  for (std::size_t k = 0; k < size; ++k)
  {
    if (!std::isfinite(values[k]))
    {
      result.Error = "the data contain NaN or infinite values";
      return result;
    }
  }
  LargeVector<double> u(size), u0(size), next(size), rhs, shift, diag;
  std::vector<Index> order; // the graph solver's renumbering (meshes)
  if (o.Integration == GraphFlowIntegration::SemiImplicit)
  {
    rhs.resize(size);
    shift.resize(n);
  }
  for (std::size_t k = 0; k < size; ++k)
  {
    u0[k] = u[k] = alpha * values[k];
  }
  std::vector<double> scratch;
  const auto measured = [&](const LargeVector<double>& x) {
    // The user's measure, on the values in data units.
    scratch.resize(size);
    for (std::size_t k = 0; k < size; ++k)
    {
      scratch[k] = x[k] / alpha;
    }
    return o.ChangeMeasure(scratch.data());
  };
  const auto rmsChange = [&]() {
    if (o.ChangeMeasure)
    {
      return measured(u);
    }
    const double s = ParallelSum(static_cast<std::int64_t>(size), 1, threads,
      [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t k = b; k < e; ++k)
        {
          acc[0] += (u[k] - u0[k]) * (u[k] - u0[k]);
        }
      })[0];
    return size ? std::sqrt(s / static_cast<double>(size)) / alpha : 0.0;
  };

  disc.Update(u.data());
  result.InitialArea = result.FinalArea = disc.Area;
  result.SmallestStableStep = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
  double dt = o.TimeStep;
  if (o.AdaptiveTimeStep && o.Integration == GraphFlowIntegration::Explicit)
  {
    dt = std::min(dt, 0.9 * result.SmallestStableStep);
  }
  double previousRate = -1.0; // relative area decrease per unit time, last step
  for (int it = 0; it < o.NumberOfIterations; ++it)
  {
    if (progress && !progress(static_cast<double>(it) / o.NumberOfIterations))
    {
      result.Cancelled = true;
      break;
    }
    const double stable = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
    result.SmallestStableStep = std::min(result.SmallestStableStep, stable);
    if (o.Integration == GraphFlowIntegration::Explicit)
    {
      if (o.AdaptiveTimeStep)
      {
        dt = std::min(dt, 0.9 * stable);
      }
      else if (dt > stable)
      {
        ++result.UnstableSteps;
      }
      // Velocity is zero at fixed vertices: one flat loop over all values.
      ParallelFor(static_cast<std::int64_t>(size), threads, [&](std::int64_t b, std::int64_t e) {
        const double* __restrict v = disc.Velocity.data();
        const double* __restrict x = u.data();
        double* __restrict y = next.data();
        for (std::int64_t j = b; j < e; ++j)
        {
          y[j] = x[j] - dt * v[j];
        }
      });
    }
    else
    {
      // (D + K_int) u' = D u - (K u - K_int u), D_i = a_i / (dt s_i): the
      // ghost values beyond the image border are those of the current state.
      disc.Apply(u.data(), next.data(), false);
      ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i)
        {
          const double d = disc.Mass[i] / (dt * disc.Speed[i]);
          shift[i] = d;
          for (int k = 0; k < nc; ++k)
          {
            const std::int64_t j = i * nc + k;
            rhs[j] = d * u[j] - (disc.KU[j] - next[j]);
          }
        }
      });
      std::vector<double> scale = ParallelSum(n, nc, threads, [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t i = b; i < e; ++i)
        {
          for (int k = 0; k < nc; ++k)
          {
            acc[k] += rhs[i * nc + k] * rhs[i * nc + k];
          }
        }
      });
      for (double& s : scale)
      {
        s = std::sqrt(s) + 1e-300;
      }
      next = u; // initial guess and fixed values
      if (const GraphLaplacian* graph = disc.Graph())
      {
        ShiftedLaplacianProblem sl = graph->Problem(nc);
        sl.Shift = shift.data();
        sl.Fixed = disc.Fixed.data();
        if (order.empty())
        {
          order = LocalityOrder(n, graph->Offsets, graph->Neighbors); // the graph stays
        }
        sl.Order = order.data();
        sl.Scale = scale;
        sl.Tolerance = o.SolverTolerance;
        sl.MaximumIterations = o.MaximumSolverIterations;
        sl.NumberOfThreads = threads;
        result.SolverIterations += SolveShiftedLaplacian(sl, rhs.data(), next.data()).Iterations;
      }
      else
      {
        diag.resize(n);
        ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
          for (std::int64_t i = b; i < e; ++i)
          {
            diag[i] = shift[i] + disc.Diagonal[i]; // Jacobi
          }
        });
        ConjugateGradientProblem cg;
        cg.Rows = n;
        cg.Columns = nc;
        cg.Diagonal = diag.data();
        cg.Fixed = disc.Fixed.data();
        cg.Scale = scale;
        cg.Tolerance = o.SolverTolerance;
        cg.MaximumIterations = o.MaximumSolverIterations;
        cg.NumberOfThreads = threads;
        cg.Apply = [&](const double* x, double* y) {
          disc.Apply(x, y, false);
          ParallelFor(n, threads, [&](std::int64_t b, std::int64_t e) {
            for (std::int64_t i = b; i < e; ++i)
            {
              for (int k = 0; k < nc; ++k)
              {
                y[i * nc + k] += shift[i] * x[i * nc + k];
              }
            }
          });
        };
        result.SolverIterations += SolveConjugateGradient(cg, rhs.data(), next.data()).Iterations;
      }
    }
    u.swap(next);
    const double previousArea = disc.Area;
    disc.Update(u.data());
    ++result.Iterations;
    result.Time += dt;
    result.LastTimeStep = dt;
    result.FinalArea = disc.Area;
    if (o.AdaptiveTimeStep)
    {
      // Section 3.8.5: a large change of the total area means much noise was
      // removed and a larger step is safe; when the change slows down the
      // step shrinks so that the structure of the data is not flattened.
      const double rate = previousArea > 0.0 ? (previousArea - disc.Area) / (previousArea * dt) : 0.0;
      if (previousRate > 0.0 && rate > 0.0)
      {
        dt *= std::min(2.0, std::max(0.5, rate / previousRate));
      }
      previousRate = rate;
    }
    if (o.NoiseLevel > 0.0 && rmsChange() >= o.NoiseLevel)
    {
      // Discrepancy reached within this step: go back along it to the point
      // where the RMS change equals the noise level, |a + t d|^2 = target.
      std::vector<double> s = ParallelSum(static_cast<std::int64_t>(size), 3, threads,
        [&](std::int64_t b, std::int64_t e, double* acc) {
          for (std::int64_t k = b; k < e; ++k)
          {
            const double a = next[k] - u0[k], d = u[k] - next[k];
            acc[0] += a * a;
            acc[1] += a * d;
            acc[2] += d * d;
          }
        });
      const double target = static_cast<double>(size) * std::pow(o.NoiseLevel * alpha, 2);
      double t = 1.0;
      if (o.ChangeMeasure)
      {
        // A measure of its own: its square taken as quadratic along the step,
        // through t = 0, 1/2 and 1.
        const double m0 = std::pow(measured(next), 2), m1 = std::pow(rmsChange(), 2);
        LargeVector<double> half(size);
        for (std::size_t k = 0; k < size; ++k)
        {
          half[k] = 0.5 * (next[k] + u[k]);
        }
        const double mh = std::pow(measured(half), 2), goal = o.NoiseLevel * o.NoiseLevel;
        // m(t) = m0 + b t + c t^2
        const double c = 2.0 * (m1 + m0 - 2.0 * mh), b = m1 - m0 - c;
        if (std::abs(c) > 1e-300)
        {
          const double d2 = b * b - 4.0 * c * (m0 - goal);
          t = d2 >= 0.0 ? (-b + (c > 0 ? 1 : -1) * std::sqrt(d2)) / (2.0 * c) : 1.0;
        }
        else if (std::abs(b) > 0.0)
        {
          t = (goal - m0) / b;
        }
        t = std::isfinite(t) ? std::min(1.0, std::max(0.0, t)) : 1.0;
      }
      else
      {
        const double disc2 = s[1] * s[1] - s[2] * (s[0] - target);
        t = s[2] > 0.0 && disc2 >= 0.0 ? std::min(1.0, std::max(0.0, (-s[1] + std::sqrt(disc2)) / s[2])) : 1.0;
      }
      if (t < 1.0)
      {
        for (std::size_t k = 0; k < size; ++k)
        {
          u[k] = next[k] + t * (u[k] - next[k]);
        }
        result.Time -= (1.0 - t) * dt;
        result.LastTimeStep = t * dt;
        disc.Update(u.data());
        result.FinalArea = disc.Area;
      }
      break;
    }
  }
  result.RMSChange = rmsChange();
  for (Index i = 0; i < n; ++i)
  {
    if (!disc.Fixed[i]) // fixed values stay bit-exact (no round trip through alpha)
    {
      for (int k = 0; k < nc; ++k)
      {
        values[i * nc + k] = u[i * nc + k] / alpha;
      }
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return result;
}

} // namespace beltrami::detail
