#include "Flows/FairingSteps.h"

#include "Mesh/Curvatures.h"

#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <complex>
#include <functional>
#include <limits>

namespace beltrami::detail
{

namespace
{

/// y = L x = -M^-1 S x (rows without mass: 0).
void ApplyLaplacian(const GraphLaplacian& L, const double* x, double* y, int threads)
{
  L.ApplyStiffness(x, y, 3, threads);
  ParallelFor(L.NumberOfVertices, threads, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      const double s = L.Mass[i] > 0.0 ? -1.0 / L.Mass[i] : 0.0;
      for (int c = 0; c < 3; ++c)
      {
        y[3 * i + c] *= s;
      }
    }
  });
}

} // namespace

std::pair<double, double> Powers::Range(double wmax) const
{
  // The least is at 0 or at a root of p' = sum_k k C_k w^(k-1), within
  // Fujiwara's bound of those, 2 max_k |k C_k / (K C_K)|^(1/(K-k)) (in the
  // units of w, whatever the mesh's size).
  double bound = 0.0;
  for (int k = 1; k < Degree; ++k)
  {
    bound = std::max(bound,
      2.0 * std::pow(std::abs(k * C[k - 1] / (Degree * C[Degree - 1])), 1.0 / (Degree - k)));
  }
  const double lo = bound > 0.0 ? Least(std::min(wmax, bound)) : 0.0;
  return { lo, std::isfinite(wmax) ? std::max((*this)(wmax), -Least(wmax, -1.0)) : HUGE_VAL };
}

/// Sampled (a polynomial of degree 4 at most; the end points exact), refined
/// by a ternary search between the neighbours of the least sample.
double Powers::Least(double w, double sign) const
{
  constexpr int samples = 4096;
  const auto f = [&](double v) { return sign * (*this)(v); };
  double lo = 0.0;
  int least = 0;
  for (int j = 0; j <= samples; ++j)
  {
    const double v = f(w * j / samples);
    least = v < lo ? j : least;
    lo = std::min(lo, v);
  }
  double a = w * std::max(0, least - 1) / samples, b = w * std::min(samples, least + 1) / samples;
  for (int it = 0; it < 100 && least > 0; ++it)
  {
    const double m1 = a + (b - a) / 3.0, m2 = b - (b - a) / 3.0;
    if (f(m1) < f(m2))
    {
      b = m2;
    }
    else
    {
      a = m1;
    }
  }
  return std::min(lo, f(0.5 * (a + b)));
}

std::vector<double> Velocity(const Stage& st, const Powers& p, const double* x, int threads)
{
  const Index n = st.L.NumberOfVertices;
  const std::size_t size = 3 * static_cast<std::size_t>(n);
  std::vector<double> v(size, 0.0), u(x, x + size), next(size);
  for (int k = 1; k <= p.Degree; ++k)
  {
    // (-L) u, with L = 0 at held vertices (boundaries, constraints), where it is undefined.
    ApplyLaplacian(st.L, u.data(), next.data(), threads);
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        next[3 * i + c] = st.Fixed[i] ? 0.0 : -next[3 * i + c];
      }
    }
    if (st.Split)
    {
      st.Split->UpdateGhosts(next.data(), 3); // the ghosts' rows of L are incomplete here
    }
    u.swap(next);
    for (std::size_t j = 0; j < size; ++j)
    {
      v[j] -= p.C[k - 1] * u[j];
    }
  }
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      v[3 * i + c] *= st.Fixed[i] ? 0.0 : st.Omega[i];
    }
  }
  if (Constrained(st))
  {
    st.Moves->Project(v.data());
  }
  return v;
}

namespace
{

void ExplicitStep(const Stage& st, const Powers& p, double dt, double* x, int threads)
{
  const std::vector<double> v = Velocity(st, p, x, threads);
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    x[k] += dt * v[k];
  }
}

/// Gershgorin's bound on the frequencies of the moving rows:
/// rho(W M^-1 S) <= 2 max |w| S_ii / a_i.
double LargestFrequency(const Stage& st)
{
  double m = 0.0;
  for (Index i = 0; i < st.L.NumberOfVertices; ++i)
  {
    if (!st.Fixed[i] && st.L.Mass[i] > 0.0 && (!st.Split || st.Split->IsOwned(i)))
    {
      m = std::max(m, std::abs(st.Omega[i]) * st.L.Diagonal[i] / st.L.Mass[i]);
    }
  }
  return 2.0 * (st.Split ? st.Split->Max(m) : m);
}

/// Largest stable explicit time step: dt p(w) <= 2 on the frequencies (for
/// the umbrella this is the thesis' lambda*dt < 1).
double StabilityLimit(const Stage& st, const Powers& p)
{
  const double top = p.Range(LargestFrequency(st)).second;
  return top > 0.0 ? 2.0 / top : std::numeric_limits<double>::infinity();
}

/// The rows of an implicit step's system M W^-1 + dt sum_k c_k S (N S)^(k-1):
/// the diagonal M W^-1 (m), the inner N (M^-1, zero at held rows), the rows
/// that do not move, the size of the solution per column.
struct StepSystem
{
  std::vector<double> Diagonal;
  std::vector<std::uint8_t> Fixed;
  std::vector<double> Scale;
  /// N = (M W^-1)^-1 on the moving rows and 0 on the others: then the step
  /// is a polynomial in one operator, and may be factored.
  bool UnitWeights = true;
};

/// Section 3.2.7's axis and plane constraints in the solve (Baraff and
/// Witkin's filtered conjugate gradient): the correction d solves
/// P A P d = P (b - A x), P the per-vertex projector on the allowed
/// directions, by one conjugate gradient over all 3n values (P couples a
/// vertex's coordinates: the columns as one vector); a vertex's three
/// Jacobi values are equal, so the preconditioner commutes with P.
ConjugateGradientResult SolveProjected(const Stage& st, const std::function<void(const double*, double*)>& apply,
  const std::vector<double>& diag, const StepSystem& sys, const FairingOptions& opt, const std::vector<double>& b,
  double* x)
{
  const Index n = st.L.NumberOfVertices;
  const std::size_t size = 3 * static_cast<std::size_t>(n);
  std::vector<double> rhs(size), d(size, 0.0), projected(size);
  apply(x, rhs.data());
  for (std::size_t k = 0; k < size; ++k)
  {
    rhs[k] = b[k] - rhs[k];
  }
  st.Moves->Project(rhs.data());
  ConjugateGradientProblem pb;
  pb.Rows = n;
  pb.Columns = 3;
  pb.CoupledColumns = true;
  pb.Diagonal = diag.data();
  pb.Fixed = sys.Fixed.data();
  pb.Scale.assign(3, Eigen::Vector3d(sys.Scale[0], sys.Scale[1], sys.Scale[2]).norm());
  pb.Tolerance = opt.SolverTolerance;
  pb.MaximumIterations = opt.MaximumSolverIterations;
  pb.NumberOfThreads = opt.NumberOfThreads;
  pb.Split = st.Split;
  pb.Apply = [&](const double* in, double* out) {
    std::copy(in, in + size, projected.begin());
    st.Moves->Project(projected.data());
    apply(projected.data(), out);
    st.Moves->Project(out);
  };
  const ConjugateGradientResult r = SolveConjugateGradient(pb, rhs.data(), d.data());
  for (std::size_t k = 0; k < size; ++k)
  {
    x[k] += d[k];
  }
  return r;
}

/// The inner N = M^-1 of the powers: zero at held rows, where L is taken
/// as 0 (distributed: the ghosts' too).
double InnerInverseMass(const Stage& st, Index i)
{
  return st.L.Mass[i] > 0.0 && !st.Fixed[i] ? 1.0 / st.L.Mass[i] : 0.0;
}

std::vector<double> InnerInverseMass(const Stage& st)
{
  std::vector<double> inverse(static_cast<std::size_t>(st.L.NumberOfVertices));
  for (Index i = 0; i < st.L.NumberOfVertices; ++i)
  {
    inverse[i] = InnerInverseMass(st, i);
  }
  if (st.Split)
  {
    st.Split->UpdateGhosts(inverse);
  }
  return inverse;
}

/// (StepSystem) x = b for the polynomial p, through the system's action,
/// Jacobi-preconditioned (the diagonal of S N S exactly, higher powers
/// estimated from it; with |c_k| the preconditioner stays positive).
ConjugateGradientResult SolvePolynomial(const Stage& st, const Powers& p, double dt, const StepSystem& sys,
  const FairingOptions& opt, const std::vector<double>& b, double* x)
{
  const GraphLaplacian& L = st.L;
  const Index n = L.NumberOfVertices;
  const int threads = opt.NumberOfThreads;
  const std::vector<double>& m = sys.Diagonal;
  const std::vector<double> invMass = InnerInverseMass(st);
  std::vector<double> power(3 * static_cast<std::size_t>(n)), tmp(power.size()), diag(n);
  for (Index i = 0; i < n; ++i)
  {
    double s2 = L.Diagonal[i] * L.Diagonal[i] * invMass[i];
    for (std::int64_t k = L.Offsets[i]; k < L.Offsets[i + 1]; ++k)
    {
      s2 += L.Weights[k] * L.Weights[k] * invMass[L.Neighbors[k]];
    }
    double sk = L.Diagonal[i], sum = 0.0;
    for (int k = 1; k <= p.Degree; ++k)
    {
      sum += std::abs(p.C[k - 1]) * sk;
      sk = k == 1 ? s2 : sk * L.Diagonal[i] * invMass[i];
    }
    diag[i] = m[i] + dt * sum;
  }
  const auto apply = [&](const double* in, double* out) {
    const double* source = in;
    for (int k = 1; k <= p.Degree; ++k)
    {
      L.ApplyStiffness(source, power.data(), 3, threads); // S (N S)^(k-1) in
      ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
        for (std::int64_t j = 3 * s; j < 3 * e; ++j)
        {
          out[j] = (k == 1 ? 0.0 : out[j]) + p.C[k - 1] * power[j];
          tmp[j] = k < p.Degree ? power[j] * invMass[j / 3] : 0.0;
        }
      });
      if (st.Split && k < p.Degree)
      {
        st.Split->UpdateGhosts(tmp.data(), 3); // the ghosts' rows of S are incomplete here
      }
      source = tmp.data();
    }
    ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = 3 * s; k < 3 * e; ++k)
      {
        out[k] = m[k / 3] * in[k] + dt * out[k];
      }
    });
  };
  if (Constrained(st))
  {
    return SolveProjected(st, apply, diag, sys, opt, b, x);
  }
  ConjugateGradientProblem pb;
  pb.Rows = n;
  pb.Columns = 3;
  pb.Diagonal = diag.data();
  pb.Fixed = sys.Fixed.data();
  pb.Scale = sys.Scale;
  pb.Tolerance = opt.SolverTolerance;
  pb.MaximumIterations = opt.MaximumSolverIterations;
  pb.NumberOfThreads = threads;
  pb.Apply = apply;
  pb.Split = st.Split;
  return SolveConjugateGradient(pb, b.data(), x);
}

/// One solve of the step system for p and dt, x (the positions) in place:
/// order 1 by the graph solver, pure order 2 with unit weights by the
/// complex-shift solver, anything else (or what they leave unconverged)
/// matrix-free; distributed (st.Split) the same, except order 1 with Jacobi
/// (matrix-free: the graph solver's renumbering is per process).
ConjugateGradientResult SolveStep(
  const Stage& st, const Powers& p, double dt, const StepSystem& sys, const FairingOptions& opt, double* x)
{
  const Index n = st.L.NumberOfVertices;
  std::vector<double> b(3 * static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < b.size(); ++k)
  {
    b[k] = sys.Diagonal[k / 3] * x[k];
  }
  ShiftedLaplacianProblem sl = st.L.Problem(3);
  sl.Shift = sys.Diagonal.data();
  sl.Factor = dt * p.C[p.Degree - 1];
  sl.Fixed = sys.Fixed.data();
  sl.Scale = sys.Scale;
  sl.Tolerance = opt.SolverTolerance;
  sl.MaximumIterations = opt.MaximumSolverIterations;
  sl.NumberOfThreads = opt.NumberOfThreads;
  sl.Preconditioner = opt.Preconditioner;
  sl.Hierarchy = opt.Hierarchy;
  sl.KeptHierarchy = opt.KeptHierarchy.get();
  sl.Points = x; // (without a hierarchy) read before the solve moves them
  sl.Split = st.Split;
  if (Constrained(st))
  {
    return SolvePolynomial(st, p, dt, sys, opt, b, x);
  }
  if (st.Split && p.Pure(1) && !UsesMultigrid(sl))
  {
    // Distributed order 1 with Jacobi; where it stops short, Automatic goes
    // on from there as SolveShiftedLaplacian's does (the algebraic multigrid).
    const ConjugateGradientResult r = SolvePolynomial(st, p, dt, sys, opt, b, x);
    if (r.Converged || opt.Preconditioner != Preconditioning::Automatic)
    {
      return r;
    }
    sl.Preconditioner = Preconditioning::Multigrid;
    ConjugateGradientResult more = SolveShiftedLaplacian(sl, b.data(), x);
    more.Iterations += r.Iterations;
    return more;
  }
  sl.Order = st.Order; // the graph solvers' renumbering, if known
  if (p.Pure(1))
  {
    // A graph Laplacian plus a diagonal: the fast solver (renumbered rows,
    // single-precision corrections of a double-precision residual).
    return SolveShiftedLaplacian(sl, b.data(), x);
  }
  ConjugateGradientResult r;
  if (p.Pure(2) && sys.UnitWeights)
  {
    sl.Guess = st.Guess;
    r = SolveSquaredLaplacian(sl, b.data(), x);
  }
  if (!r.Converged)
  {
    const int before = r.Iterations;
    r = SolvePolynomial(st, p, dt, sys, opt, b, x);
    r.Iterations += before;
  }
  return r;
}

/// 1 + dt p(w) as a product of real factors 1 + a w (a > 0) and
/// 1 + a w + b w^2 (complex roots: positive for every w), from the roots of
/// the polynomial; empty if a root is real and non-negative (a combination
/// with a negative weight that the factors cannot hold) or two coincide.
std::vector<Powers> Factors(const Powers& p, double dt)
{
  const int K = p.Degree;
  // In units of sigma = (dt c_K)^(-1/K), w = sigma u, the polynomial in u is
  // monic (coefficients near 1 whatever the mesh's size): its companion.
  const double sigma = std::pow(dt * p.C[K - 1], -1.0 / K);
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(K, K);
  for (int k = 0; k < K; ++k)
  {
    // Row 0: minus the coefficients of u^(K-1), ..., u^0 (the latter 1).
    const int power = K - 1 - k;
    companion(0, k) = power == 0 ? -1.0 : -dt * p.C[power - 1] * std::pow(sigma, power);
    if (k + 1 < K)
    {
      companion(k + 1, k) = 1.0;
    }
  }
  const Eigen::VectorXcd roots = sigma * Eigen::EigenSolver<Eigen::MatrixXd>(companion, false).eigenvalues();
  std::vector<Powers> factors;
  for (int j = 0; j < K; ++j)
  {
    const std::complex<double> r = roots[j];
    for (int i = 0; i < j; ++i)
    {
      if (std::abs(roots[i] - r) <= 1e-6 * std::abs(r))
      {
        return {};
      }
    }
    Powers f;
    if (std::abs(r.imag()) <= 1e-9 * std::abs(r))
    {
      if (!(r.real() < 0.0))
      {
        return {};
      }
      f.C[0] = -1.0 / r.real(); // 1 - w / r
      f.Degree = 1;
    }
    else if (r.imag() > 0.0)
    {
      f.C[0] = -2.0 * r.real() / std::norm(r); // (1 - w / r)(1 - w / conj r)
      f.C[1] = 1.0 / std::norm(r);
      f.Degree = 2;
    }
    else
    {
      continue; // the conjugate's factor
    }
    factors.push_back(f);
  }
  return factors;
}

/// A combination with a negative weight: whether the step's matrix is
/// positive definite on the frequencies of `st`, 1 + dt p(w) >= 1 /
/// MaximumGain up to Gershgorin's bound; the largest gain 1 / min(1 + dt
/// p(w)) goes to the report.
bool StepIsDefined(const Stage& st, const Powers& p, double dt, FairingReport& report)
{
  if (p.NonNegative())
  {
    return true;
  }
  const double lowest = 1.0 + dt * p.Range(LargestFrequency(st)).first;
  report.LargestGain = std::max(report.LargestGain, lowest > 0.0 ? 1.0 / lowest : HUGE_VAL);
  return lowest >= 1.0 / MaximumGain;
}

} // namespace

/// One backward Euler step in the symmetric form of Fairing.h.  Rows with a
/// negative weight (inverse diffusion of the anisotropic flow) are advanced
/// explicitly and then held, so the system stays positive definite.  False
/// (nothing moved) when a combination's step is not positive definite.
/// Above order 2 (unit weights) the step is the product of its factors of
/// degree 1 and 2, taken one after the other: each one is conditioned like an
/// order-1 or order-2 step, where the whole polynomial's condition number
/// grows as (dt w_max^k) - on the bunny scan (4 h^6, 1e-8): order 3 took
/// 22552 iterations at once and takes 1500 by factors; order 4 did not
/// converge in 200000 and takes 2375.  With held rows the product is exact:
/// each factor's boundary terms compose into the polynomial's.
bool ImplicitStep(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report)
{
  const GraphLaplacian& L = st.L;
  const Index n = L.NumberOfVertices;
  const Powers p = Powers::Of(opt);
  const double dt = opt.TimeStep;
  if (!StepIsDefined(st, p, dt, report))
  {
    return false;
  }
  StepSystem sys;
  sys.Fixed = st.Fixed;
  bool anyNegative = false;
  for (Index i = 0; i < n; ++i)
  {
    anyNegative = anyNegative || (!sys.Fixed[i] && st.Omega[i] < 0.0);
  }
  if (st.Split ? st.Split->Max(anyNegative ? 1.0 : 0.0) > 0.0 : anyNegative) // (distributed: all or none)
  {
    const std::vector<double> v = Velocity(st, p, x, opt.NumberOfThreads);
    for (Index i = 0; i < n; ++i)
    {
      if (!sys.Fixed[i] && st.Omega[i] < 0.0)
      {
        for (int c = 0; c < 3; ++c)
        {
          x[3 * i + c] += dt * v[3 * i + c];
        }
      }
    }
  }
  sys.Diagonal.assign(n, 0.0);
  Index numFree = 0;
  for (Index i = 0; i < n; ++i)
  {
    const double inverseMass = InnerInverseMass(st, i);
    if (sys.Fixed[i] || !(st.Omega[i] > 0.0) || !(L.Mass[i] > 0.0))
    {
      sys.Fixed[i] = 1;
      sys.UnitWeights = sys.UnitWeights && inverseMass == 0.0;
      continue;
    }
    sys.Diagonal[i] = L.Mass[i] / st.Omega[i];
    sys.UnitWeights = sys.UnitWeights && std::abs(sys.Diagonal[i] * inverseMass - 1.0) <= 1e-12;
    ++numFree;
  }
  // (Distributed: over the owned rows of all processes, so that every
  // process takes the same branches and solves together.)
  const auto counted = [&](Index i) { return !st.Split || st.Split->IsOwned(i); };
  double totals[6] = { static_cast<double>(numFree), sys.UnitWeights ? 0.0 : 1.0 };
  for (Index i = 0; i < n; ++i)
  {
    totals[2] += counted(i);
    for (int c = 0; c < 3 && counted(i); ++c)
    {
      totals[3 + c] += x[3 * i + c];
    }
  }
  if (st.Split)
  {
    st.Split->Sum(totals, 6);
  }
  sys.UnitWeights = totals[1] == 0.0;
  if (totals[0] == 0.0)
  {
    return true;
  }
  const Vec3 center = Vec3(totals[3], totals[4], totals[5]) / totals[2];
  sys.Scale.assign(3, 0.0);
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3 && !sys.Fixed[i] && counted(i); ++c)
    {
      const double d = sys.Diagonal[i] * (x[3 * i + c] - center[c]);
      sys.Scale[c] += d * d;
    }
  }
  if (st.Split)
  {
    st.Split->Sum(sys.Scale.data(), 3);
  }
  for (double& s : sys.Scale)
  {
    s = std::sqrt(s);
  }
  const bool factored = sys.UnitWeights && !Constrained(st) && !p.Pure(1) && !p.Pure(2);
  const std::vector<Powers> factors = factored ? Factors(p, dt) : std::vector<Powers>{};
  ConjugateGradientResult r;
  r.Converged = true;
  for (const Powers& f : factors.size() > 1 ? factors : std::vector<Powers>{ p })
  {
    const ConjugateGradientResult fr = SolveStep(st, f, factors.size() > 1 ? 1.0 : dt, sys, opt, x);
    r.Iterations += fr.Iterations;
    r.RelativeResidual = std::max(r.RelativeResidual, fr.RelativeResidual);
    r.Converged = r.Converged && fr.Converged;
  }
  report.Iterations.push_back(r.Iterations);
  report.LargestResidual = std::max(report.LargestResidual, r.RelativeResidual);
  report.Converged = report.Converged && r.Converged;
  return true;
}

namespace
{

/// Points with a NaN or infinite coordinate are held (VertexRoles) and their
/// triangles are left out of the operator; their zero weights would still
/// carry the NaN into every product (0 * NaN), so while it lives they take
/// part as the origin, and they get their own values back after.
class NonFinitePointsAsOrigin
{
public:
  NonFinitePointsAsOrigin(double* x, Index n)
    : X(x)
  {
    for (Index i = 0; i < n; ++i)
    {
      if (!Point(x, i).allFinite())
      {
        Saved.emplace_back(i, Point(x, i));
        std::fill(x + 3 * i, x + 3 * i + 3, 0.0);
      }
    }
  }
  ~NonFinitePointsAsOrigin()
  {
    for (const auto& [i, p] : Saved)
    {
      std::copy(p.data(), p.data() + 3, X + 3 * i);
    }
  }
  NonFinitePointsAsOrigin(const NonFinitePointsAsOrigin&) = delete;
  NonFinitePointsAsOrigin& operator=(const NonFinitePointsAsOrigin&) = delete;

private:
  double* X;
  std::vector<std::pair<Index, Vec3>> Saved;
};

} // namespace

bool Integrate(const Stage& st, const FairingOptions& opt, double* x, FairingReport& report)
{
  const NonFinitePointsAsOrigin guard(x, st.L.NumberOfVertices);
  switch (opt.Integration)
  {
    case FairingIntegration::Implicit:
      return ImplicitStep(st, opt, x, report);
    case FairingIntegration::Explicit:
    {
      const Powers p = Powers::Of(opt);
      const double limit = StabilityLimit(st, p);
      report.StabilityLimit = report.StabilityLimit > 0.0 ? std::min(report.StabilityLimit, limit) : limit;
      report.ExplicitUnstable = report.ExplicitUnstable || opt.TimeStep > limit * (1.0 + 1e-12);
      ExplicitStep(st, p, opt.TimeStep, x, opt.NumberOfThreads);
      return true;
    }
    case FairingIntegration::TaubinLambdaMu:
      ExplicitStep(st, Powers::Single(1), opt.TaubinLambda, x, opt.NumberOfThreads);
      ExplicitStep(st, Powers::Single(1), opt.TaubinMu, x, opt.NumberOfThreads);
      return true;
  }
  return true;
}

std::vector<double> UnitNormals(const MeshTopology& topo, const double* x, int threads)
{
  std::vector<double> normals(3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  CurvatureOutputs no;
  no.Normals = normals.data();
  CurvatureOptions co;
  co.NumberOfThreads = threads;
  ComputeCurvatures(topo, x, co, no);
  return normals;
}

void MoveAlongNormals(const std::vector<double>& normals, double* x, const double* d, Keep keep, double tangentialShare)
{
  const Index n = static_cast<Index>(normals.size() / 3);
  for (Index i = 0; i < n; ++i)
  {
    const Vec3 nn = Point(normals.data(), i);
    const Vec3 di = Point(d, i);
    if (nn.allFinite() && di.allFinite())
    {
      const Vec3 along = di.dot(nn) * nn;
      const Vec3 move = keep == Keep::Normal ? Vec3(along + tangentialShare * (di - along)) : Vec3(di - along);
      for (int c = 0; c < 3; ++c)
      {
        x[3 * i + c] += move[c];
      }
    }
  }
}

} // namespace beltrami::detail
