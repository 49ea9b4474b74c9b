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
  if (!(o.ContrastScale >= 0.0) || !std::isfinite(o.ContrastScale))
  {
    return "the contrast scale (alpha) must be positive (or 0: automatic) and finite";
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

void PositionProbeSigns(int components, const double* points, double lengthScale, std::size_t begin, std::size_t end,
  UninitializedVector<double>& b)
{
  const auto mix = [](std::uint64_t x) { // splitmix64's finaliser
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  };
  b.resize(end - begin);
  for (std::size_t k = begin; k < end; ++k)
  {
    const std::size_t i = k / static_cast<std::size_t>(components);
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int a = 0; a < 3; ++a)
    {
      h = mix(h ^ static_cast<std::uint64_t>(std::llround(1024.0 * points[3 * i + a] / lengthScale)));
    }
    b[k - begin] = (mix(h + static_cast<std::uint64_t>(k % components)) >> 63) ? 1.0 : -1.0;
  }
}

void GridPieceProbeSigns(const FlowDiscretization& disc, const GridPiece& piece, std::int64_t w, std::int64_t h,
  std::int64_t d, UninitializedVector<double>& b)
{
  const std::size_t nc = static_cast<std::size_t>(disc.Components), row = static_cast<std::size_t>(w) * nc;
  b.resize(static_cast<std::size_t>(w * h * d) * nc);
  UninitializedVector<double> signs;
  for (std::int64_t r = 0; r < h * d; ++r)
  {
    const std::int64_t y = r % h + piece.Origin[1], z = r / h + piece.Origin[2];
    const std::size_t first = static_cast<std::size_t>((z * piece.Whole[1] + y) * piece.Whole[0] + piece.Origin[0]) * nc;
    disc.FlowDiscretization::ProbeSigns(first, first + row, signs);
    std::copy(signs.begin(), signs.end(), b.begin() + static_cast<std::ptrdiff_t>(r * row));
  }
}

void FlowDiscretization::ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const
{
  // A linear congruential sequence, the sign of value k from its state
  // k + 1: the state at `begin` by jumping ahead (Brown 1994: the step's
  // multiplier and increment composed by squaring).
  constexpr std::uint64_t A = 6364136223846793005ull, C = 1442695040888963407ull;
  std::uint64_t multiplier = 1, increment = 0, stepA = A, stepC = C;
  for (std::uint64_t n = begin; n > 0; n >>= 1)
  {
    if (n & 1)
    {
      multiplier *= stepA;
      increment = increment * stepA + stepC;
    }
    stepC *= stepA + 1;
    stepA *= stepA;
  }
  std::uint64_t state = multiplier * 0x9E3779B97F4A7C15ull + increment;
  b.resize(end - begin);
  for (double& sign : b)
  {
    state = state * A + C;
    sign = (state >> 63) ? 1.0 : -1.0;
  }
}

namespace
{

/// One run of the flow: its discretization and its state (scaled data).
struct FlowRun
{
  std::unique_ptr<FlowDiscretization> Disc;
  UninitializedVector<double> U, Next; // (every value written before it is read)
};

/// The size of the probe of the risk estimate, relative to the noise.
constexpr double ProbeSize = 0.01;

/// The state of the time loop (section 3.8.5) and its stages.  With the
/// MinimumRisk stop a second run (the probe) flows the data plus
/// ProbeSize * sigma * b (b = +-1 at random, in the noise's space) with the
/// same steps: b . (f(y + eps b) - f(y)) / eps estimates the divergence of
/// the flow in Monte-Carlo SURE.
class FlowIntegrator
{
public:
  FlowIntegrator(const DiscretizationFactory& make, const GraphFlowOptions& o, const ProbeWindow& window)
    : Make(make)
    , Window(window)
    , O(o)
    , Threads(o.NumberOfThreads)
    , Stop(o.Stop == GraphFlowStop::Iterations && o.NoiseLevel > 0.0 ? GraphFlowStop::NoiseLevel : o.Stop)
  {
  }

  GraphFlowResult Run(double* values, const ProgressCallback& progress);

private:
  const DiscretizationFactory& Make;
  const ProbeWindow& Window;
  const GraphFlowOptions& O;
  double Alpha = 1.0; // the contrast scale
  double Sigma = 0.0; // the noise level of the stops
  const int Threads;
  const GraphFlowStop Stop;
  FlowRun Main, Probe;
  bool Windowed = false;
  Index N = 0;
  int NC = 1;
  std::size_t Size = 0;
  const Partition* Split = nullptr; // meshes split over processes
  double Counted = 0.0;             // values counted over all processes (Size in serial)
  GraphFlowResult Result;
  /// The input (the caller's values, unchanged until Finish writes the
  /// result): the flow's start is U0(k) = Alpha * Input[k], recomputed
  /// where needed rather than kept in an array of its own.
  const double* Input = nullptr;
  double U0(std::int64_t k) const { return Alpha * Input[k]; }
  LargeVector<double> Rhs, Shift, Diag;
  std::vector<Index> Order; // the graph solver's renumbering (meshes)
  std::vector<double> Scratch, Y; // the data in noise space
  UninitializedVector<double> Best; // risk: the best state, when the flow has gone past it
  UninitializedVector<double> B; // risk: b, of the values of the probe's window (windowed), else of all

  bool Start(const double* values);
  /// Explicit fixed-size steps fused with the evaluation (the
  /// discretization's FusedStep): a step then evaluates the state it steps
  /// from, so the figures (Area, MaxRate) lag one step behind.
  bool Fused = false;
  /// The figures (and velocity) of a run's state.
  void Evaluate(FlowRun& run);
  /// One step of a run and, unfused, the evaluation of the new state.
  void Advance(FlowRun& run, double dt);
  void Step(FlowRun& run, double dt);
  void ExplicitStep(FlowRun& run, double dt);
  void SemiImplicitStep(FlowRun& run, double dt);
  void SolveOnGraph(FlowRun& run, const GraphLaplacian& graph, const std::vector<double>& scale);
  void SolveMatrixFree(FlowRun& run, const std::vector<double>& scale);
  /// Counts a solve's iterations, and whether it reached the tolerance.
  void Solved(const ConjugateGradientResult& r);
  /// The solver tolerance: with the least-risk stop the main run's solves
  /// go to 1e-8 (the stop then comes at the same step in every layout of a
  /// split run); the probe's solve only resolves its change of the
  /// difference to the main run (SemiImplicitStep), to the tolerance.
  double SolveTolerance(const FlowRun& run) const
  {
    return &run == &Probe || Stop != GraphFlowStop::MinimumRisk ? O.SolverTolerance : std::min(O.SolverTolerance, 1e-8);
  }
  /// Section 3.8.5: the step grows with the relative decrease of the area.
  void AdaptStep(double previousArea, double& dt, double& previousRate) const;
  /// The fraction of the last step (Next -> U) at which the change reaches the noise level.
  double NoiseLevelFraction();
  /// The estimated mean squared error of the main run's state (SURE).
  /// swept: the fused steps took its sums as they wrote the states
  /// (SweepRiskSums); else a pass over the values.
  double Risk(bool swept = false);
  /// Lets the fused steps of the main and probe runs take the risk's sums
  /// (the fit, the divergence) as they write their rows; false where they
  /// cannot (then Risk reads the states).
  bool SweepRiskSums();
  void Finish(double* values, const ProgressCallback& progress);
  int Limit() const { return O.Stop == GraphFlowStop::Iterations ? O.NumberOfIterations : O.MaximumNumberOfIterations; }

  /// Sums of `width` terms over the values (k = row * NC + component) this
  /// process counts, over all processes: add(k, acc).
  template <typename Add>
  std::vector<double> SumOverValues(int width, Add&& add) const
  {
    const FlowDiscretization& disc = *Main.Disc;
    const bool all = !Split; // (serial: no test per value)
    std::vector<double> s = ParallelSum(static_cast<std::int64_t>(Size), width, Threads,
      [&](std::int64_t b, std::int64_t e, double* acc) {
        for (std::int64_t k = b; k < e; ++k)
        {
          if (all || disc.Counts(static_cast<Index>(k / NC)))
          {
            add(k, acc);
          }
        }
      });
    if (Split)
    {
      Split->Sum(s.data(), width);
    }
    return s;
  }
  /// Whether `flag` holds on some process (on this one in serial runs).
  bool Anywhere(bool flag) const { return Split ? Split->Max(flag ? 1.0 : 0.0) > 0.0 : flag; }

  /// The state x in the noise's space (data units): a view of Scratch.
  const double* InNoiseSpace(const UninitializedVector<double>& x)
  {
    Scratch.resize(Size);
    ParallelFor(static_cast<std::int64_t>(Size), Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k)
      {
        Scratch[k] = x[k] / Alpha;
      }
    });
    if (O.ToNoiseSpace)
    {
      O.ToNoiseSpace(Scratch.data());
    }
    return Scratch.data();
  }

  /// The RMS difference of x to the input, in the noise's space.
  double ChangeOf(const UninitializedVector<double>& x)
  {
    if (O.ToNoiseSpace)
    {
      const double* f = InNoiseSpace(x);
      const double sum = SumOverValues(1, [&](std::int64_t k, double* acc) { acc[0] += (f[k] - Y[k]) * (f[k] - Y[k]); })[0];
      return std::sqrt(sum / Counted);
    }
    const double s = SumOverValues(1, [&](std::int64_t k, double* acc) { acc[0] += (x[k] - U0(k)) * (x[k] - U0(k)); })[0];
    return std::sqrt(s / Counted) / Alpha;
  }
};

bool FlowIntegrator::Start(const double* values)
{
  Main.Disc = Make();
  N = Main.Disc->Size;
  NC = Main.Disc->Components;
  Size = static_cast<std::size_t>(N) * NC;
  Split = Main.Disc->Split;
  double counted = 0.0;
  for (Index i = 0; i < N; ++i)
  {
    counted += Main.Disc->Counts(i);
  }
  Counted = (Split ? Split->Sum(counted) : counted) * NC;
  const double nonFinite = ParallelSum(static_cast<std::int64_t>(Size), 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
    for (std::int64_t k = b; k < e; ++k)
    {
      acc[0] += !std::isfinite(values[k]);
    }
  })[0];
  if (Anywhere(nonFinite > 0.0))
  {
    Result.Error = "the data contain NaN or infinite values";
    return false;
  }
  // The noise, estimated in its own space, and the automatic settings.
  if (O.ToNoiseSpace)
  {
    Y.assign(values, values + Size);
    O.ToNoiseSpace(Y.data());
  }
  Result.EstimatedNoiseLevel = Main.Disc->EstimateNoise(O.ToNoiseSpace ? Y.data() : values);
  Sigma = O.NoiseLevel > 0.0 ? O.NoiseLevel : Result.EstimatedNoiseLevel;
  // The automatic contrast scale is relative to the noise where the data
  // flow: in another space, the noise there is the estimate there, scaled
  // like a given noise level.
  double flowSigma = Sigma;
  if (O.ToNoiseSpace && O.ContrastScale <= 0.0 && Result.EstimatedNoiseLevel > 0.0)
  {
    flowSigma = Sigma * Main.Disc->EstimateNoise(values) / Result.EstimatedNoiseLevel;
  }
  Alpha = O.ContrastScale > 0.0 ? O.ContrastScale
    : flowSigma > 0.0           ? Main.Disc->AutomaticContrast * Main.Disc->LengthScale / flowSigma
                                : 1.0;
  Result.NoiseLevel = Sigma;
  Result.ContrastScale = Alpha;
  Input = values;
  Main.U.resize(Size);
  Main.Next.resize(Size);
  if (O.Integration == GraphFlowIntegration::SemiImplicit)
  {
    Rhs.resize(Size);
    Shift.resize(N);
  }
  ParallelFor(static_cast<std::int64_t>(Size), Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t k = b; k < e; ++k)
    {
      Main.U[k] = U0(k);
    }
  });
  if (Stop == GraphFlowStop::MinimumRisk && Sigma > 0.0)
  {
    // The probe: y + eps b in the noise's space, b = +-1.
    const double eps = ProbeSize * Sigma;
    Windowed = Window.Make && !O.ToNoiseSpace && O.Integration == GraphFlowIntegration::Explicit;
    const std::size_t begin = Windowed ? static_cast<std::size_t>(Window.Begin) * NC : 0;
    const std::size_t end = Windowed ? static_cast<std::size_t>(Window.End) * NC : Size;
    Main.Disc->ProbeSigns(begin, end, B);
    Probe.Disc = Windowed ? Window.Make() : Make();
    Probe.U.resize(end - begin);
    Probe.Next.resize(end - begin);
    if (O.ToNoiseSpace)
    {
      Scratch.resize(Size);
      for (std::size_t k = 0; k < Size; ++k)
      {
        Scratch[k] = Y[k] + eps * B[k];
      }
      if (O.FromNoiseSpace)
      {
        O.FromNoiseSpace(Scratch.data());
      }
    }
    const double* probe = O.ToNoiseSpace ? Scratch.data() : values;
    const double shift = O.ToNoiseSpace ? 0.0 : eps;
    ParallelFor(static_cast<std::int64_t>(end - begin), Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k)
      {
        Probe.U[k] = Alpha * (probe[begin + k] + shift * B[k]);
      }
    });
  }
  return true;
}

void FlowIntegrator::Evaluate(FlowRun& run)
{
  Fused ? run.Disc->FusedStep(run.U.data(), 0.0, nullptr) : run.Disc->Update(run.U.data());
}

void FlowIntegrator::Advance(FlowRun& run, double dt)
{
  if (!Fused)
  {
    Step(run, dt);
    run.Disc->Update(run.U.data());
    return;
  }
  run.Disc->FusedStep(run.U.data(), dt, run.Next.data());
  run.U.swap(run.Next);
  if (Split)
  {
    Split->UpdateGhosts(run.U.data(), NC);
  }
}

void FlowIntegrator::Step(FlowRun& run, double dt)
{
  O.Integration == GraphFlowIntegration::Explicit ? ExplicitStep(run, dt) : SemiImplicitStep(run, dt);
  run.U.swap(run.Next);
  if (Split)
  {
    Split->UpdateGhosts(run.U.data(), NC); // rows of other processes' pieces: their owners' values
  }
}

void FlowIntegrator::ExplicitStep(FlowRun& run, double dt)
{
  // Velocity is zero at fixed vertices: one flat loop over all values.
  ParallelFor(static_cast<std::int64_t>(run.U.size()), Threads, [&](std::int64_t b, std::int64_t e) {
    const double* __restrict v = run.Disc->Velocity.data();
    const double* __restrict x = run.U.data();
    double* __restrict y = run.Next.data();
    for (std::int64_t j = b; j < e; ++j)
    {
      y[j] = x[j] - dt * v[j];
    }
  });
}

void FlowIntegrator::SemiImplicitStep(FlowRun& run, double dt)
{
  // (D + K_int) u' = D u - (K u - K_int u), D_i = a_i / (dt s_i): the
  // ghost values beyond the image border are those of the current state.
  FlowDiscretization& disc = *run.Disc;
  disc.Apply(run.U.data(), run.Next.data(), false);
  ParallelFor(N, Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      const double d = disc.Mass[i] / (dt * disc.Speed[i]);
      Shift[i] = d;
      for (int k = 0; k < NC; ++k)
      {
        const std::int64_t j = i * NC + k;
        Rhs[j] = d * run.U[j] - (disc.KU[j] - run.Next[j]);
      }
    }
  });
  std::vector<double> scale = ParallelSum(N, NC, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
    for (std::int64_t i = b; i < e; ++i)
    {
      for (int k = 0; k < NC && disc.Counts(static_cast<Index>(i)); ++k)
      {
        acc[k] += Rhs[i * NC + k] * Rhs[i * NC + k];
      }
    }
  });
  if (Split)
  {
    Split->Sum(scale.data(), NC);
  }
  for (double& s : scale)
  {
    s = std::sqrt(s) + 1e-300;
  }
  if (&run == &Probe)
  {
    // The initial guess: the main run's new state plus the probe's last
    // difference to it.  The solve then only resolves how that difference
    // changes, to the tolerance of its own size: the divergence of the risk
    // needs the difference, not the states, to the solver's tolerance.
    ParallelFor(static_cast<std::int64_t>(Size), Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k)
      {
        run.Next[k] = Main.U[k] + (run.U[k] - Main.Next[k]);
      }
    });
  }
  else
  {
    run.Next = run.U; // initial guess and fixed values
  }
  const GraphLaplacian* graph = disc.Graph();
  if (graph && !Split) // (its renumbering is per process: split rows take the generic CG)
  {
    SolveOnGraph(run, *graph, scale);
  }
  else
  {
    SolveMatrixFree(run, scale);
  }
}

void FlowIntegrator::SolveOnGraph(FlowRun& run, const GraphLaplacian& graph, const std::vector<double>& scale)
{
  ShiftedLaplacianProblem sl = graph.Problem(NC);
  sl.Shift = Shift.data();
  sl.Fixed = run.Disc->Fixed.data();
  if (Order.empty())
  {
    Order = LocalityOrder(N, graph.Offsets, graph.Neighbors); // the graph stays
  }
  sl.Order = Order.data();
  sl.Scale = scale;
  sl.Tolerance = SolveTolerance(run);
  sl.MaximumIterations = O.MaximumSolverIterations;
  sl.NumberOfThreads = Threads;
  sl.Preconditioner = Preconditioning::Automatic; // (Jacobi, going on with the algebraic multigrid where it stops short)
  Solved(SolveShiftedLaplacian(sl, Rhs.data(), run.Next.data()));
}

void FlowIntegrator::SolveMatrixFree(FlowRun& run, const std::vector<double>& scale)
{
  FlowDiscretization& disc = *run.Disc;
  Diag.resize(N);
  ParallelFor(N, Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      Diag[i] = Shift[i] + disc.Diagonal[i]; // Jacobi
    }
  });
  ConjugateGradientProblem cg;
  cg.Rows = N;
  cg.Columns = NC;
  cg.Diagonal = Diag.data();
  cg.Fixed = disc.Fixed.data();
  cg.Scale = scale;
  cg.Tolerance = SolveTolerance(run);
  cg.MaximumIterations = O.MaximumSolverIterations;
  cg.NumberOfThreads = Threads;
  cg.Split = Split;
  cg.Apply = [&](const double* x, double* y) {
    disc.Apply(x, y, false);
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
  Solved(SolveConjugateGradient(cg, Rhs.data(), run.Next.data()));
}

void FlowIntegrator::Solved(const ConjugateGradientResult& r)
{
  Result.SolverIterations += r.Iterations;
  if (!r.Converged)
  {
    Result.SolverConverged = false;
    Result.LargestSolverResidual = std::max(Result.LargestSolverResidual, r.RelativeResidual);
  }
}

void FlowIntegrator::AdaptStep(double previousArea, double& dt, double& previousRate) const
{
  // A large change of the total area means much noise was removed and a
  // larger step is safe; when the change slows down the step shrinks so that
  // the structure of the data is not flattened.
  const double area = Main.Disc->Area;
  const double rate = previousArea > 0.0 ? (previousArea - area) / (previousArea * dt) : 0.0;
  if (previousRate > 0.0 && rate > 0.0)
  {
    dt *= std::min(2.0, std::max(0.5, rate / previousRate));
  }
  previousRate = rate;
}

double FlowIntegrator::NoiseLevelFraction()
{
  const UninitializedVector<double>& u = Main.U;
  const UninitializedVector<double>& previous = Main.Next;
  if (O.ToNoiseSpace)
  {
    // Another space: the squared change taken as quadratic along the step,
    // through t = 0, 1/2 and 1.
    const double m0 = std::pow(ChangeOf(previous), 2), m1 = std::pow(ChangeOf(u), 2);
    UninitializedVector<double> half(Size);
    for (std::size_t k = 0; k < Size; ++k)
    {
      half[k] = 0.5 * (previous[k] + u[k]);
    }
    const double mh = std::pow(ChangeOf(half), 2), goal = Sigma * Sigma;
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
  std::vector<double> s = SumOverValues(3, [&](std::int64_t k, double* acc) {
    const double a = previous[k] - U0(k), d = u[k] - previous[k];
    acc[0] += a * a;
    acc[1] += a * d;
    acc[2] += d * d;
  });
  const double target = Counted * std::pow(Sigma * Alpha, 2);
  const double disc2 = s[1] * s[1] - s[2] * (s[0] - target);
  return s[2] > 0.0 && disc2 >= 0.0 ? std::min(1.0, std::max(0.0, (-s[1] + std::sqrt(disc2)) / s[2])) : 1.0;
}

/// The sum of term(k), k in [begin, end), in 8 interleaved partial sums
/// (so that the loop vectorizes), added in a fixed order.
template <typename Term>
double LaneSum(std::int64_t begin, std::int64_t end, Term&& term)
{
  constexpr int Lanes = 8;
  double lanes[Lanes] = {};
  std::int64_t k = begin;
  for (; k + Lanes <= end; k += Lanes)
  {
    for (int l = 0; l < Lanes; ++l)
    {
      lanes[l] += term(k + l);
    }
  }
  for (; k < end; ++k)
  {
    lanes[0] += term(k);
  }
  return std::accumulate(lanes, lanes + Lanes, 0.0);
}

bool FlowIntegrator::SweepRiskSums()
{
  if (!Fused || O.ToNoiseSpace || !Main.Disc->SumsRows() || !Probe.Disc->SumsRows())
  {
    return false;
  }
  // (A split grid's discretization calls them on the samples it owns; Risk
  // sums over the processes.)
  Main.Disc->RowSum = [this](std::int64_t first, std::int64_t count, const double* next) {
    const double* start = Input + first;
    const double alpha = Alpha;
    // The next row's data asked for ahead (rows come in order; a row's
    // sum stalled on them).
    for (std::int64_t k = count; k < 2 * count && first + k < static_cast<std::int64_t>(Size); k += 8)
    {
      __builtin_prefetch(start + k);
    }
    return LaneSum(0, count, [&](std::int64_t k) { return (next[k] - alpha * start[k]) * (next[k] - alpha * start[k]); });
  };
  // The probe's rows are the window's (windowed): its inner part counts,
  // against the main run's new state (the main run steps first).
  const std::int64_t begin = Windowed ? static_cast<std::int64_t>(Window.Begin) * NC : 0;
  const std::int64_t first = Windowed ? static_cast<std::int64_t>(Window.InnerBegin) * NC : 0;
  const std::int64_t last = Windowed ? static_cast<std::int64_t>(Window.InnerEnd) * NC : static_cast<std::int64_t>(Size);
  Probe.Disc->RowSum = [this, begin, first, last](std::int64_t row, std::int64_t count, const double* next) {
    const std::int64_t k0 = begin + row;
    const double* b = B.data() - begin;
    const double* u = Main.U.data();
    return LaneSum(std::max(k0, first), std::min(k0 + count, last),
      [&](std::int64_t k) { return b[k] * (next[k - k0] - u[k]); });
  };
  return true;
}

double FlowIntegrator::Risk(bool swept)
{
  // SURE = |f(y) - y|^2 / M - sigma^2 + 2 sigma^2 div f / M, in the noise's
  // space, div f = b . (f(y + eps b) - f(y)) / eps.
  double fit = 0.0, divergence = 0.0;
  if (swept)
  {
    // (the window's inner part scaled to the whole; an empty piece of a
    // split grid has no window and no values)
    const double scale = Windowed ? static_cast<double>(Size) / (static_cast<double>(Window.InnerEnd - Window.InnerBegin) * NC) : 1.0;
    double sums[2] = { Main.Disc->StepSum, Probe.Disc->StepSum };
    if (Split)
    {
      Split->Sum(sums, 2);
    }
    fit = sums[0] / (Alpha * Alpha);
    divergence = sums[1] / Alpha * scale;
  }
  else if (O.ToNoiseSpace)
  {
    const double* main = InNoiseSpace(Main.U);
    const std::vector<double> f(main, main + Size);
    const double* p = InNoiseSpace(Probe.U);
    const std::vector<double> sums = SumOverValues(2, [&](std::int64_t k, double* acc) {
      acc[0] += (f[k] - Y[k]) * (f[k] - Y[k]);
      acc[1] += B[k] * (p[k] - f[k]);
    });
    fit = sums[0];
    divergence = sums[1];
  }
  else if (Windowed)
  {
    // The fit over everything, the divergence over the window's inner part
    // (the probe against the main run there), scaled to the whole.  The
    // window's own border makes its run differ from the main one a margin
    // away (the flow's reach: a few voxels); that difference does not
    // depend on the signs b, so it adds to the sum only a zero-mean term,
    // far below the divergence's (no unperturbed run of the window needed).
    const std::int64_t begin = static_cast<std::int64_t>(Window.Begin) * NC;
    const std::int64_t first = static_cast<std::int64_t>(Window.InnerBegin) * NC;
    const std::int64_t last = static_cast<std::int64_t>(Window.InnerEnd) * NC;
    fit = ParallelSum(static_cast<std::int64_t>(Size), 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t k = b; k < e; ++k)
      {
        acc[0] += (Main.U[k] - U0(k)) * (Main.U[k] - U0(k));
      }
    })[0] / (Alpha * Alpha);
    divergence = ParallelSum(last - first, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t k = first + b; k < first + e; ++k)
      {
        acc[0] += B[k - begin] * (Probe.U[k - begin] - Main.U[k]);
      }
    })[0] / Alpha * static_cast<double>(Size) / static_cast<double>(last - first);
  }
  else
  {
    const std::vector<double> s = SumOverValues(2, [&](std::int64_t k, double* acc) {
      const double d = Main.U[k] - U0(k);
      acc[0] += d * d;
      acc[1] += B[k] * (Probe.U[k] - Main.U[k]);
    });
    fit = s[0] / (Alpha * Alpha);
    divergence = s[1] / Alpha;
  }
  const double m = Counted, var = Sigma * Sigma;
  return fit / m - var + 2.0 * var * divergence / (ProbeSize * Sigma * m);
}

void FlowIntegrator::Finish(double* values, const ProgressCallback& progress)
{
  Result.RMSChange = ChangeOf(Main.U);
  const LargeVector<std::uint8_t>& fixed = Main.Disc->Fixed;
  // No step (none asked for, no noise, or the input the least-risk state):
  // the data stay bit-exact, without a round trip through alpha.
  ParallelFor(Result.Iterations > 0 ? N : 0, Threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      if (!fixed[i]) // fixed values stay bit-exact (no round trip through alpha)
      {
        for (int k = 0; k < NC; ++k)
        {
          values[i * NC + k] = Main.U[i * NC + k] / Alpha;
        }
      }
    }
  });
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
  FlowDiscretization& disc = *Main.Disc;
  const bool explicitSteps = O.Integration == GraphFlowIntegration::Explicit;
  Fused = explicitSteps && !O.AdaptiveTimeStep && disc.FusesSteps();
  // Fused steps evaluate the state they step from: the figures of the
  // input come with the first step (one pass over the data less).
  const bool evaluated = !Fused || Limit() == 0;
  if (evaluated)
  {
    Evaluate(Main);
  }
  if (Stop != GraphFlowStop::Iterations && !(Sigma > 0.0))
  {
    // No noise given or found (too small a domain, or clean data): nothing
    // to remove (Finish leaves the data as they are).
    Result.Completed = true;
    Finish(values, progress);
    return Result;
  }
  const bool risk = Stop == GraphFlowStop::MinimumRisk;
  if (risk)
  {
    if (!Fused) // (their first step's velocity)
    {
      Probe.Disc->Update(Probe.U.data());
    }
    Result.InitialRisk = Result.FinalRisk = std::sqrt(std::max(0.0, Risk()));
  }
  const bool swept = risk && SweepRiskSums();
  double bestRisk = Result.InitialRisk * Result.InitialRisk, bestTime = 0.0;
  int bestIterations = 0;
  double bestArea = disc.Area; // (fused: known once the step after the best is taken)
  Result.InitialArea = Result.FinalArea = disc.Area;
  Result.SmallestStableStep = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
  double dt = O.TimeStep > 0.0 ? O.TimeStep : disc.AutomaticTimeStep;
  if (O.AdaptiveTimeStep && explicitSteps)
  {
    dt = std::min(dt, 0.9 * Result.SmallestStableStep);
  }
  double previousRate = -1.0; // relative area decrease per unit time, last step
  const int limit = Limit();
  bool ruleMet = false;
  for (int it = 0; it < limit && !ruleMet; ++it)
  {
    const double done = Stop == GraphFlowStop::Iterations ? static_cast<double>(it) / limit : 1.0 - std::exp(-it / 50.0);
    if (Anywhere(progress && !progress(done))) // (all processes stop together)
    {
      Result.Completed = false;
      break;
    }
    // The stability of the step from the state's figures (fused: known
    // once the step is taken; only counted there, the step is fixed).
    const auto checkStability = [&]() {
      const double stable = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
      Result.SmallestStableStep = std::min(Result.SmallestStableStep, stable);
      if (explicitSteps && O.AdaptiveTimeStep)
      {
        dt = std::min(dt, 0.9 * stable);
      }
      else if (explicitSteps && dt > stable)
      {
        ++Result.UnstableSteps;
      }
    };
    if (!Fused)
    {
      checkStability();
    }
    const double previousArea = disc.Area;
    Advance(Main, dt);
    if (Fused)
    {
      checkStability();
    }
    ++Result.Iterations;
    Result.Time += dt;
    Result.LastTimeStep = dt;
    Result.FinalArea = disc.Area;
    if (!evaluated && Result.Iterations == 1)
    {
      Result.InitialArea = disc.Area;
    }
    if (Fused && bestIterations == Result.Iterations - 1)
    {
      bestArea = disc.Area;
    }
    if (risk)
    {
      Advance(Probe, dt);
      const double r = Risk(swept);
      // Past the minimum: the risk rose 0.1% above it (it can rise by less
      // and fall again: 0.04% on the clean camera photograph), or the flow
      // ran twice as long as to the minimum without a lower one.
      const bool rose = r > bestRisk + 1e-3 * std::abs(bestRisk);
      if (r < bestRisk)
      {
        bestRisk = r;
        bestTime = Result.Time;
        bestIterations = Result.Iterations; // the state is Main.U: kept when the next step is not better
      }
      ruleMet = rose || Result.Time > 2.0 * bestTime + 2.0 * dt;
      if (r >= bestRisk && bestIterations == Result.Iterations - 1 && !ruleMet)
      {
        Best.assign(Main.Next.begin(), Main.Next.end()); // the state before this step
      }
    }
    if (O.AdaptiveTimeStep)
    {
      AdaptStep(previousArea, dt, previousRate);
    }
    if (Stop == GraphFlowStop::NoiseLevel && ChangeOf(Main.U) >= Sigma)
    {
      // Discrepancy reached within this step: go back along it to the point
      // where the change equals the noise level.
      ruleMet = true;
      const double t = NoiseLevelFraction();
      if (t < 1.0)
      {
        for (std::size_t k = 0; k < Size; ++k)
        {
          Main.U[k] = Main.Next[k] + t * (Main.U[k] - Main.Next[k]);
        }
        Result.Time -= (1.0 - t) * dt;
        Result.LastTimeStep = t * dt;
        Evaluate(Main);
        Result.FinalArea = disc.Area;
      }
    }
  }
  Result.StoppedByLimit = Stop != GraphFlowStop::Iterations && !ruleMet && Result.Completed;
  if (!evaluated && Result.Iterations == 0) // (cancelled at once)
  {
    Evaluate(Main);
    Result.InitialArea = Result.FinalArea = bestArea = disc.Area;
    Result.SmallestStableStep = disc.MaxRate > 0.0 ? 1.0 / disc.MaxRate : HUGE_VAL;
  }
  if (risk)
  {
    // Back to the state of least risk: the input, the last state, or the
    // one kept.
    if (bestIterations == 0)
    {
      ParallelFor(static_cast<std::int64_t>(Size), Threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t k = b; k < e; ++k)
        {
          Main.U[k] = U0(k);
        }
      });
    }
    else if (bestIterations == Result.Iterations - 1 && ruleMet)
    {
      std::swap(Main.U, Main.Next); // the state before the last step (not kept in Best)
    }
    else if (bestIterations < Result.Iterations)
    {
      std::copy(Best.begin(), Best.end(), Main.U.begin());
    }
    const bool known = Fused && bestIterations < Result.Iterations; // (the next step evaluated it)
    Result.Time = bestTime;
    Result.Iterations = bestIterations;
    Result.FinalRisk = std::sqrt(std::max(0.0, bestRisk));
    if (!known)
    {
      Evaluate(Main);
      bestArea = disc.Area;
    }
    Result.FinalArea = bestArea;
  }
  else if (Fused && Result.Iterations > 0)
  {
    Evaluate(Main); // the figures of the last state
    Result.FinalArea = disc.Area;
  }
  Finish(values, progress);
  return Result;
}

} // namespace

ProbeWindow GridProbeWindow(Index layers, Index layerSize, int components, Index fraction, const GraphFlowOptions& o,
  const std::function<std::unique_ptr<FlowDiscretization>(Index first, Index count)>& make)
{
  ProbeWindow w;
  constexpr Index Margin = 8; // layers: the flow's reach (a few of them) and more
  const Index inner = std::max<Index>(16, layers / fraction);
  if (!o.WindowedRisk || o.Stop != GraphFlowStop::MinimumRisk || o.Integration != GraphFlowIntegration::Explicit ||
    o.ToNoiseSpace || static_cast<double>(layers) * layerSize * components <= double(1 << 21) ||
    inner + 2 * Margin >= layers / 2)
  {
    return w;
  }
  const Index innerFirst = (layers - inner) / 2, first = innerFirst - Margin, count = inner + 2 * Margin;
  w.Make = [make, first, count]() { return make(first, count); };
  w.Begin = first * layerSize;
  w.End = (first + count) * layerSize;
  w.InnerBegin = innerFirst * layerSize;
  w.InnerEnd = (innerFirst + inner) * layerSize;
  return w;
}

GraphFlowResult Integrate(const DiscretizationFactory& make, double* values, const GraphFlowOptions& o,
  const ProgressCallback& progress, const ProbeWindow& window)
{
  return FlowIntegrator(make, o, window).Run(values, progress);
}

} // namespace beltrami::detail
