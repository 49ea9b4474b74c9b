#include "Flows/Fairing.h"

#include "Flows/FairingAnisotropy.h"
#include "Flows/FairingInvariants.h"
#include "Solvers/ConjugateGradient.h"
#include "Solvers/GraphSolvers.h"
#include "Mesh/Curvatures.h"
#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <sstream>
#include <tuple>

namespace beltrami
{

using namespace detail;

namespace
{

/// Section 3.2.7's axis and plane constraints: which part of a vertex's
/// motion is allowed.
struct Motions
{
  enum : std::uint8_t
  {
    Free = 0,
    OnAxis = 1, ///< only the component along Direction
    OnPlane = 2 ///< only the components normal to Direction
  };
  std::vector<std::uint8_t> Kind;
  std::vector<Vec3> Direction; ///< unit
  bool Any = false;

  /// v (3 values per vertex) reduced to its allowed part, in place.
  void Project(double* v) const
  {
    for (std::size_t i = 0; Any && i < Kind.size(); ++i)
    {
      if (Kind[i] != Free)
      {
        const Vec3 a(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        const Vec3 along = a.dot(Direction[i]) * Direction[i];
        const Vec3 kept = Kind[i] == OnAxis ? along : Vec3(a - along);
        std::copy(kept.data(), kept.data() + 3, v + 3 * i);
      }
    }
  }
  /// x = before + P (x - before): the allowed part of a move.
  void KeepAllowed(const std::vector<double>& before, double* x) const
  {
    if (!Any)
    {
      return;
    }
    std::vector<double> move(before.size());
    for (std::size_t k = 0; k < move.size(); ++k)
    {
      move[k] = x[k] - before[k];
    }
    Project(move.data());
    for (std::size_t k = 0; k < move.size(); ++k)
    {
      x[k] = before[k] + move[k];
    }
  }
};

/// The Laplacian of a step and what it is applied to.
struct Stage
{
  const GraphLaplacian& L;
  std::vector<std::uint8_t> Fixed; ///< rows that must not move
  std::vector<double> Omega;       ///< per-row weight (may be < 0 for anisotropy)
  const Index* Order = nullptr;    ///< LocalityOrder of L's graph, if known
  const Motions* Moves = nullptr;  ///< axis and plane constraints, if any
};

bool Constrained(const Stage& st)
{
  return st.Moves && st.Moves->Any;
}

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

/// The flow's operator, a polynomial in -L = M^-1 S: the velocity is
/// -sum_k C[k-1] (-L)^k X (order k: C[k-1] = 1, the others 0).
struct Powers
{
  double C[4] = { 0.0, 0.0, 0.0, 0.0 };
  int Degree = 0;

  static Powers Single(int order)
  {
    Powers p;
    p.C[order - 1] = 1.0;
    p.Degree = order;
    return p;
  }
  static Powers Of(const FairingOptions& o)
  {
    if (o.Order >= 1)
    {
      return Single(o.Order);
    }
    Powers p;
    for (int k = 1; k <= 4; ++k)
    {
      p.C[k - 1] = o.OrderWeights[k - 1];
      p.Degree = p.C[k - 1] != 0.0 ? k : p.Degree;
    }
    return p;
  }
  /// sum_k C[k-1] w^k.
  double operator()(double w) const
  {
    double sum = 0.0;
    for (int k = Degree; k >= 1; --k)
    {
      sum = (sum + C[k - 1]) * w;
    }
    return sum;
  }
  /// Only the term of order k, with a positive weight.
  bool Pure(int k) const
  {
    double others = 0.0;
    for (int j = 1; j <= 4; ++j)
    {
      others += j == k ? 0.0 : std::abs(C[j - 1]);
    }
    return Degree == k && C[k - 1] > 0.0 && others == 0.0;
  }
  bool NonNegative() const { return std::min({ C[0], C[1], C[2], C[3] }) >= 0.0; }
  /// The least and the largest value on [0, wmax] (wmax may be infinite).
  std::pair<double, double> Range(double wmax) const
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

  /// The least of sign * p on [0, w] (w finite): sampled (a polynomial of
  /// degree 4 at most; the end points exact), refined by a ternary search
  /// between the neighbours of the least sample.
  double Least(double w, double sign = 1.0) const
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
};

/// The flow velocity without the time step: -W sum_k C[k-1] (-L)^k X.
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
    if (!st.Fixed[i] && st.L.Mass[i] > 0.0)
    {
      m = std::max(m, std::abs(st.Omega[i]) * st.L.Diagonal[i] / st.L.Mass[i]);
    }
  }
  return 2.0 * m;
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
  std::vector<double> Diagonal, InverseMass;
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
/// vertex's coordinates); a vertex's three Jacobi values are equal, so the
/// preconditioner commutes with P.
ConjugateGradientResult SolveProjected(const Stage& st, const std::function<void(const double*, double*)>& apply,
  const std::vector<double>& diag, const StepSystem& sys, const FairingOptions& opt, const std::vector<double>& b,
  double* x)
{
  const std::size_t size = 3 * static_cast<std::size_t>(st.L.NumberOfVertices);
  std::vector<double> rhs(size), d(size, 0.0), projected(size), diag3(size);
  std::vector<std::uint8_t> fixed3(size);
  apply(x, rhs.data());
  for (std::size_t k = 0; k < size; ++k)
  {
    rhs[k] = b[k] - rhs[k];
    diag3[k] = diag[k / 3];
    fixed3[k] = sys.Fixed[k / 3];
  }
  st.Moves->Project(rhs.data());
  ConjugateGradientProblem pb;
  pb.Rows = static_cast<Index>(size);
  pb.Columns = 1;
  pb.Diagonal = diag3.data();
  pb.Fixed = fixed3.data();
  pb.Scale = { Eigen::Vector3d(sys.Scale[0], sys.Scale[1], sys.Scale[2]).norm() };
  pb.Tolerance = opt.SolverTolerance;
  pb.MaximumIterations = opt.MaximumSolverIterations;
  pb.NumberOfThreads = opt.NumberOfThreads;
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
  const std::vector<double>& invMass = sys.InverseMass;
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
  return SolveConjugateGradient(pb, b.data(), x);
}

/// One solve of the step system for p and dt, x (the positions) in place:
/// order 1 by the graph solver, pure order 2 with unit weights by the
/// complex-shift solver, anything else (or what they leave unconverged)
/// matrix-free.
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
  if (Constrained(st))
  {
    return SolvePolynomial(st, p, dt, sys, opt, b, x);
  }
  if (p.Pure(1))
  {
    // A graph Laplacian plus a diagonal: the fast solver (renumbered rows,
    // single-precision corrections of a double-precision residual).
    sl.Order = st.Order;
    return SolveShiftedLaplacian(sl, b.data(), x);
  }
  ConjugateGradientResult r;
  if (p.Pure(2) && sys.UnitWeights)
  {
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

/// A step may amplify a frequency at most this much: beyond, its matrix is
/// nearly singular (or indefinite) and no solve is meaningful.
constexpr double MaximumGain = 100.0;

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
  if (anyNegative)
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
  sys.InverseMass.assign(n, 0.0);
  Index numFree = 0;
  for (Index i = 0; i < n; ++i)
  {
    // The inner M^-1 of the powers: zero at held vertices, where L is taken as 0.
    sys.InverseMass[i] = L.Mass[i] > 0.0 && !st.Fixed[i] ? 1.0 / L.Mass[i] : 0.0;
    if (sys.Fixed[i] || !(st.Omega[i] > 0.0) || !(L.Mass[i] > 0.0))
    {
      sys.Fixed[i] = 1;
      sys.UnitWeights = sys.UnitWeights && sys.InverseMass[i] == 0.0;
      continue;
    }
    sys.Diagonal[i] = L.Mass[i] / st.Omega[i];
    sys.UnitWeights = sys.UnitWeights && std::abs(sys.Diagonal[i] * sys.InverseMass[i] - 1.0) <= 1e-12;
    ++numFree;
  }
  if (numFree == 0)
  {
    return true;
  }
  Vec3 center = Vec3::Zero();
  for (Index i = 0; i < n; ++i)
  {
    center += Point(x, i);
  }
  center /= n;
  sys.Scale.assign(3, 0.0);
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3 && !sys.Fixed[i]; ++c)
    {
      const double d = sys.Diagonal[i] * (x[3 * i + c] - center[c]);
      sys.Scale[c] += d * d;
    }
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

/// One step of the chosen integration; false when it is not defined (a
/// combination whose implicit step is not positive definite): nothing moved.
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

LaplacianWeights WeightsOf(FairingOperator op)
{
  switch (op)
  {
    case FairingOperator::Umbrella:
      return LaplacianWeights::Umbrella;
    case FairingOperator::ScaleDependentUmbrella:
      return LaplacianWeights::InverseEdgeLength;
    default:
      return LaplacianWeights::Cotangent;
  }
}

/// Which part of a displacement d at a vertex of normal n is kept.
enum class Keep
{
  Normal,    ///< (d.n) n
  Tangential ///< d - (d.n) n
};

/// Moves x[i] by the `keep` part of d[i] (both 3 per vertex), with the
/// vertex normals of x before the move; vertices without a normal (no area,
/// NaN) or with a non-finite d[i] do not move.
void MoveAlongNormals(const MeshTopology& topo, double* x, const double* d, Keep keep, int threads)
{
  const Index n = topo.NumberOfVertices();
  std::vector<double> normals(3 * static_cast<std::size_t>(n));
  CurvatureOutputs no;
  no.Normals = normals.data();
  CurvatureOptions co;
  co.NumberOfThreads = threads;
  ComputeCurvatures(topo, static_cast<const double*>(x), co, no);
  for (Index i = 0; i < n; ++i)
  {
    const Vec3 nn = Point(normals.data(), i);
    const Vec3 di = Point(d, i);
    if (nn.allFinite() && di.allFinite())
    {
      const Vec3 along = di.dot(nn) * nn;
      const Vec3 move = keep == Keep::Normal ? along : Vec3(di - along);
      for (int c = 0; c < 3; ++c)
      {
        x[3 * i + c] += move[c];
      }
    }
  }
}

/// A copy of x after one implicit order-1 step of `time` with the `kind`
/// Laplacian (assembled into `lap` at x; `order` gives its LocalityOrder or
/// null): the pre-mollified geometries of the anisotropic weights and of
/// OperatorMollification.
template <typename OrderOf>
std::vector<double> SmoothedCopy(const MeshTopology& topo, const double* x, LaplacianWeights kind, double time,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt,
  GraphLaplacian& lap, OrderOf&& order)
{
  std::vector<double> copy(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  AssembleSurfaceLaplacian(topo, copy.data(), kind, lap, opt.NumberOfThreads);
  FairingOptions so = opt;
  so.Integration = FairingIntegration::Implicit;
  so.Order = 1;
  so.TimeStep = time;
  FairingReport ignored;
  ImplicitStep(Stage{ lap, held, weight, order() }, so, copy.data(), ignored);
  return copy;
}

/// What the flows may move: hard constraints (user-fixed or zero weight),
/// soft weights clamped to [0, 1], boundary vertices, and vertices the flows
/// cannot move (non-manifold, duplicate faces, non-finite: kept fixed).
struct VertexRoles
{
  std::vector<std::uint8_t> Fixed, Boundary;
  std::vector<double> Weight;
  Motions Moves; ///< axis and plane constraints of the vertices that are not fixed
  bool HardConstraints = false;
};

/// Reads the axis and plane constraints (a non-zero finite direction; the
/// axis first) of the vertices that are not fixed.
Motions ReadMotions(const FairingConstraints& cons, const std::vector<std::uint8_t>& fixed)
{
  const Index n = static_cast<Index>(fixed.size());
  Motions m;
  m.Kind.assign(n, Motions::Free);
  m.Direction.assign(n, Vec3::Zero());
  for (Index i = 0; i < n && (cons.AxisDirections || cons.PlaneNormals); ++i)
  {
    for (const auto& [array, kind] : { std::pair{ cons.AxisDirections, Motions::OnAxis },
           std::pair{ cons.PlaneNormals, Motions::OnPlane } })
    {
      const Vec3 d = array ? Point(array, i) : Vec3::Zero();
      if (!fixed[i] && m.Kind[i] == Motions::Free && d.allFinite() && d.norm() > 0.0)
      {
        m.Kind[i] = kind;
        m.Direction[i] = d.normalized();
        m.Any = true;
      }
    }
  }
  return m;
}

VertexRoles ClassifyVertices(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const FairingConstraints& cons, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  VertexRoles r;
  r.Fixed.assign(n, 0);
  r.Boundary.assign(n, 0);
  r.Weight.assign(n, 1.0);
  for (Index i = 0; i < n; ++i)
  {
    const std::uint8_t flags = topo.VertexFlags(i);
    r.Boundary[i] = (flags & VertexBoundary) != 0;
    if (cons.Weights)
    {
      const double w = cons.Weights[i];
      r.Weight[i] = std::isfinite(w) ? std::clamp(w, 0.0, 1.0) : 1.0;
    }
    const bool user = (cons.Fixed && cons.Fixed[i]) || r.Weight[i] == 0.0;
    r.HardConstraints = r.HardConstraints || user;
    const bool unusable = (flags & (VertexNonManifold | VertexDuplicateFace | VertexIsolated)) ||
      !Point(x, i).allFinite();
    report.UnusableVertices += unusable && !(flags & VertexIsolated);
    r.Fixed[i] = user || unusable || (r.Boundary[i] && opt.Boundary == FairingBoundary::Fixed);
  }
  r.Moves = ReadMotions(cons, r.Fixed);
  r.HardConstraints = r.HardConstraints || r.Moves.Any;
  return r;
}

/// Section 3.3.1: the invariant restored after every step (Automatic: the
/// volume of closed oriented surfaces without hard constraints), with its
/// initial value; remarks for the user go to `warn`.
InvariantState ChooseInvariant(const MeshTopology& topo, const double* x, const FairingOptions& opt,
  const VertexRoles& roles, std::ostringstream& warn, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  const TopologySummary& info = topo.Summary();
  InvariantState inv;
  inv.Kind = opt.Invariant;
  const bool closed = info.IsClosed() && info.IsManifold() && info.IsOriented();
  if (inv.Kind == FairingInvariant::Automatic)
  {
    inv.Kind = closed && !roles.HardConstraints ? FairingInvariant::Volume : FairingInvariant::None;
  }
  if (inv.Kind == FairingInvariant::Volume && !closed)
  {
    warn << "Volume preservation needs a closed, manifold, consistently oriented surface; this one is "
         << topo.Describe() << ": no invariant is preserved. ";
    inv.Kind = FairingInvariant::None;
  }
  const bool referenced =
    inv.Kind == FairingInvariant::HeightFieldVolume || inv.Kind == FairingInvariant::RevolutionVolume;
  if (referenced)
  {
    inv.PlaneNormal = Vec3(opt.ReferencePlaneNormal[0], opt.ReferencePlaneNormal[1], opt.ReferencePlaneNormal[2]);
    if (!(inv.PlaneNormal.norm() > 0.0))
    {
      inv.PlaneNormal = Vec3::UnitZ();
    }
    inv.PlaneNormal.normalize();
    // The reference plane passes through the mean of the boundary (of all points if closed).
    Vec3 sum = Vec3::Zero();
    Index count = 0;
    for (Index i = 0; i < n; ++i)
    {
      if (roles.Boundary[i] && Point(x, i).allFinite())
      {
        sum += Point(x, i);
        ++count;
      }
    }
    inv.PlaneOrigin = count ? Vec3(sum / count) : VertexCentroid(topo, x);
  }
  if (inv.Kind == FairingInvariant::RevolutionVolume)
  {
    // The axis passes through the area centroid (on the axis of a surface of revolution).
    AreaAndCentroid(topo, x, opt.NumberOfThreads, &inv.PlaneOrigin);
  }
  if (roles.HardConstraints && inv.Kind != FairingInvariant::None)
  {
    warn << "The invariant is restored by scaling, which also moves the fixed and the axis- or plane-constrained "
            "points (section 3.3.1). ";
  }
  report.InvariantUsed = inv.Kind;
  inv.Initial = MeasureInvariant(inv, topo, x, opt.NumberOfThreads, nullptr);
  report.InitialInvariant = report.FinalInvariant = inv.Initial;
  return inv;
}

/// The operator's geometry (OperatorMollification): x moved by the normal
/// part of one implicit umbrella step.  On a noisy scan the cotangents of the
/// noisy triangles are noise too; the copy damps the noise across the
/// surface and keeps the sampling, so a flat region's copy is the region
/// itself and flat regions still never move.
std::vector<double> MollifiedOperatorPoints(const MeshTopology& topo, const double* x,
  const std::vector<std::uint8_t>& held, const std::vector<double>& weight, const FairingOptions& opt)
{
  GraphLaplacian U;
  std::vector<double> step = SmoothedCopy(topo, x, LaplacianWeights::Umbrella, opt.OperatorMollification, held,
    weight, opt, U, [] { return static_cast<const Index*>(nullptr); });
  std::vector<double> regular(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  for (std::size_t k = 0; k < step.size(); ++k)
  {
    step[k] -= x[k];
  }
  MoveAlongNormals(topo, regular.data(), step.data(), Keep::Normal, opt.NumberOfThreads);
  return regular;
}

/// Section 3.6, by operator splitting: the tangential part (at the new
/// surface) of an umbrella step, which evens out the sampling.  The umbrella
/// is dimensionless: its step is lambda*dt in units of the mean edge length
/// squared (L_umbrella ~ h^2/4 Laplace, L_K ~ Laplace/2), at most 1 so that
/// it stays a local relaxation.
void RegulariseSampling(const MeshTopology& topo, double* x, const std::vector<std::uint8_t>& fixed,
  const std::vector<double>& weight, const Motions& moves, const FairingOptions& opt)
{
  const std::vector<double> before(x, x + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
  const int threads = opt.NumberOfThreads;
  GraphLaplacian U;
  AssembleSurfaceLaplacian(topo, x, LaplacianWeights::Umbrella, U, threads);
  const double h = MeanEdgeLength(topo, x);
  const double relax = std::min(1.0, 2.0 * opt.TimeStep / (h * h));
  const Stage tangential{ U, fixed, weight };
  std::vector<double> v = Velocity(tangential, Powers::Single(1), x, threads);
  for (double& vk : v)
  {
    vk *= relax;
  }
  MoveAlongNormals(topo, x, v.data(), Keep::Tangential, threads);
  moves.KeepAllowed(before, x);
}

/// The curve-smoothing pass along the detected feature edges (directions
/// `along` from the anisotropic weights).
bool SmoothFeatures(const MeshTopology& topo, double* x, const std::vector<Vec3>& along, const VertexRoles& roles,
  const FairingOptions& opt, GraphLaplacian& curveL, FairingReport& report)
{
  const Index n = topo.NumberOfVertices();
  std::vector<std::vector<Index>> chains;
  std::vector<std::uint8_t> onCurve;
  FeatureChains(topo, x, along, chains, onCurve);
  CurveGraph features;
  features.Build(n, {}, chains);
  AssembleCurveLaplacian(features, x, LaplacianWeights::InverseEdgeLength, curveL);
  Stage curve{ curveL, roles.Fixed, roles.Weight, nullptr, &roles.Moves };
  for (Index i = 0; i < n; ++i)
  {
    curve.Fixed[i] = roles.Fixed[i] || roles.Boundary[i] || !onCurve[i];
  }
  return Integrate(curve, opt, x, report);
}

/// A combination's step that is not positive definite ends the run at the
/// last defined step, with an error at the first step (nothing was done).
void UndefinedStep(int step, int steps, std::ostringstream& warn, FairingReport& report)
{
  std::ostringstream why;
  why << "The combination of orders would amplify some frequencies of this mesh more than " << MaximumGain
      << "-fold or without bound in one step (1 + dt p(w) < " << 1.0 / MaximumGain
      << ": the implicit step is not defined or nearly singular); use a smaller time step or a smaller negative "
         "weight";
  if (step == 0)
  {
    report.Error = why.str() + ". The points are unchanged.";
  }
  else
  {
    warn << why.str() << ": stopped after " << step << " of " << steps << " steps. ";
  }
  report.Completed = false;
}

/// The counts and the warning sentence of a finished run.
void FinishReport(const MeshTopology& topo, const VertexRoles& roles, const FairingOptions& opt,
  std::ostringstream& warn, FairingReport& report)
{
  for (Index i = 0; i < topo.NumberOfVertices(); ++i)
  {
    report.FixedVertices += roles.Fixed[i] && topo.Valence(i) > 0;
  }
  if (report.ExplicitUnstable)
  {
    warn << "Explicit integration with time step " << opt.TimeStep
         << " is above the stability limit (about " << report.StabilityLimit
         << "): the result oscillates; use implicit integration or a smaller step. ";
  }
  if (!report.Converged)
  {
    warn << "The linear solver did not reach the tolerance " << opt.SolverTolerance << " (relative residual "
         << report.LargestResidual << "). ";
  }
  report.Warning = warn.str();
}

FairingReport FairClosedOrFixed(const MeshTopology& topo, double* x, const FairingOptions& opt,
  const FairingConstraints& cons, const ProgressCallback& progress)
{
  FairingReport report;
  const Index n = topo.NumberOfVertices();
  const int threads = opt.NumberOfThreads;
  const VertexRoles roles = ClassifyVertices(topo, x, opt, cons, report);
  const std::vector<std::uint8_t>& fixed = roles.Fixed;
  const std::vector<double>& weight = roles.Weight;
  std::ostringstream warn;
  const InvariantState inv = ChooseInvariant(topo, x, opt, roles, warn, report);

  const std::vector<std::vector<Index>> loops =
    opt.Boundary == FairingBoundary::SmoothCurve ? topo.BoundaryLoops() : std::vector<std::vector<Index>>{};
  CurveGraph boundaryCurves;
  boundaryCurves.Build(n, loops, {});
  GraphLaplacian L, curveL, first;
  // The solver's renumbering of the surface graph, the same for every step.
  std::vector<Index> order;
  const auto localOrder = [&]() {
    if (order.empty())
    {
      order = LocalityOrder(n, L.Offsets, L.Neighbors);
    }
    return order.data();
  };
  // Rows that do not move in the surface stages.
  std::vector<std::uint8_t> held(n);
  for (Index i = 0; i < n; ++i)
  {
    held[i] = fixed[i] || roles.Boundary[i];
  }
  // A combination with a negative weight: each step's start, kept in case
  // the step is not defined there (section 3.2.6's amplification).
  const bool amplifies = !Powers::Of(opt).NonNegative();
  std::vector<double> start;
  for (int step = 0; step < opt.NumberOfIterations; ++step)
  {
    if (amplifies)
    {
      start.assign(x, x + 3 * static_cast<std::size_t>(n));
    }
    bool defined = true;
    std::vector<double> omega = weight;
    std::vector<Vec3> along;
    if (opt.Anisotropic)
    {
      // Curvatures of a pre-mollified copy (section 3.7.1 cites [PR99]): one
      // isotropic implicit curvature-flow step of the same size, so that the
      // weights see the shape rather than the noise.
      const std::vector<double> mollified = opt.Mollification > 0.0
        ? SmoothedCopy(topo, x, LaplacianWeights::Cotangent, opt.TimeStep * opt.Mollification, held, weight, opt, L,
            [&] { return localOrder(); })
        : std::vector<double>(x, x + 3 * static_cast<std::size_t>(n));
      const std::vector<double> a = AnisotropicWeights(topo, mollified.data(), opt,
        opt.SmoothFeatureCurves ? &along : nullptr, report.FeatureVertices);
      for (Index i = 0; i < n; ++i)
      {
        omega[i] *= a[i];
      }
    }
    // Boundary loops first (they do not depend on the interior), then the
    // interior with the new boundary as fixed values (section 3.5.2).
    if (!loops.empty())
    {
      AssembleCurveLaplacian(boundaryCurves, x, WeightsOf(opt.Operator), curveL);
      Stage curve{ curveL, fixed, weight, nullptr, &roles.Moves };
      for (Index i = 0; i < n; ++i)
      {
        curve.Fixed[i] = fixed[i] || boundaryCurves.Offsets[i + 1] - boundaryCurves.Offsets[i] < 2;
      }
      defined = Integrate(curve, opt, x, report);
    }
    // The operator's geometry: the current positions (the thesis'
    // linearisation, sections 3.4.3/3.5.3), or a mollified copy.
    std::vector<double> regular;
    if (step > 0 && opt.KeepFirstOperator)
    {
      L = first; // section 3.4.3: relative to the input mesh
    }
    else
    {
      if (opt.OperatorMollification > 0.0 && opt.Operator != FairingOperator::Umbrella)
      {
        regular = MollifiedOperatorPoints(topo, x, held, weight, opt);
      }
      AssembleSurfaceLaplacian(topo, regular.empty() ? x : regular.data(), WeightsOf(opt.Operator), L, threads);
      if (opt.KeepFirstOperator && opt.NumberOfIterations > 1)
      {
        first = L;
      }
    }
    report.DegenerateTriangles = std::max(report.DegenerateTriangles, L.DegenerateTriangles);
    const bool solves = opt.Integration == FairingIntegration::Implicit && Powers::Of(opt).Pure(1);
    const Stage surface{ L, held, omega, solves ? localOrder() : nullptr, &roles.Moves };
    defined = defined && Integrate(surface, opt, x, report);
    if (opt.Operator == FairingOperator::CurvatureFlowAndSampling)
    {
      RegulariseSampling(topo, x, surface.Fixed, weight, roles.Moves, opt);
    }
    if (opt.Anisotropic && opt.SmoothFeatureCurves)
    {
      defined = defined && SmoothFeatures(topo, x, along, roles, opt, curveL, report);
    }
    if (!defined)
    {
      std::copy(start.begin(), start.end(), x);
      UndefinedStep(step, opt.NumberOfIterations, warn, report);
      break;
    }
    if (inv.Kind != FairingInvariant::None)
    {
      report.FinalInvariant = RestoreInvariant(inv, topo, x, threads);
    }
    if (progress && !progress(static_cast<double>(step + 1) / opt.NumberOfIterations))
    {
      report.Completed = false;
      break;
    }
  }
  FinishReport(topo, roles, opt, warn, report);
  return report;
}

/// Order 0: finite weights, the highest non-zero one positive.
bool CheckOrderWeights(const FairingOptions& opt)
{
  const Powers p = Powers::Of(opt);
  bool finite = true;
  for (double c : p.C)
  {
    finite = finite && std::isfinite(c);
  }
  return finite && p.Degree > 0 && p.C[p.Degree - 1] > 0.0;
}

} // namespace

FairingReport FairSurface(const MeshTopology& topo, double* points, const FairingOptions& options,
  const FairingConstraints& cons, const ProgressCallback& progress)
{
  FairingOptions opt = options;
  opt.Order = std::clamp(opt.Order, 0, 4);
  opt.NumberOfIterations = std::max(0, opt.NumberOfIterations);
  opt.TimeStep = std::isfinite(opt.TimeStep) ? std::max(0.0, opt.TimeStep) : 0.0;
  const int degree = Powers::Of(opt).Degree;
  if (opt.Order == 0 && !CheckOrderWeights(opt))
  {
    FairingReport failed;
    failed.Error = "OrderWeights must be finite, with a positive weight on the highest order used.";
    return failed;
  }
  if (opt.Units == LengthUnit::MeanEdgeLength && topo.NumberOfTriangles() > 0)
  {
    const double h = MeanEdgeLength(topo, points);
    if (!(h > 0.0) || !std::isfinite(h))
    {
      FairingReport failed;
      failed.Error = "The mean edge length of the input is " + std::to_string(h) + ": cannot scale the time step.";
      return failed;
    }
    if (opt.Operator != FairingOperator::Umbrella)
    {
      // L^k: 1/length^(2k); a combination's terms are c_k (h^2 L)^k.
      double unit = 1.0;
      for (int k = 0; k < 2 * degree; ++k)
      {
        unit *= h;
      }
      opt.TimeStep *= unit;
      for (int k = 1; k <= 4; ++k)
      {
        opt.OrderWeights[k - 1] *= std::pow(h * h, k - degree);
      }
    }
    opt.FeatureThreshold /= h;
    opt.Units = LengthUnit::Physical;
  }
  if (opt.Boundary != FairingBoundary::VirtualVertex || topo.Summary().NumberOfBoundaryLoops == 0)
  {
    return FairClosedOrFixed(topo, points, opt, cons, progress);
  }
  // Section 3.5.2: close each boundary loop with a fan of virtual triangles to
  // a virtual vertex at its barycentre, smooth the closed surface, drop them.
  const Index n = topo.NumberOfVertices();
  const std::vector<std::vector<Index>> loops = topo.BoundaryLoops();
  IndexArray triangles = topo.TriangleList();
  std::vector<double> x(points, points + 3 * static_cast<std::size_t>(n));
  Index next = n;
  for (const auto& loop : loops)
  {
    if (loop.size() < 3)
    {
      continue;
    }
    Vec3 center = Vec3::Zero();
    for (Index v : loop)
    {
      center += Point(points, v);
    }
    center /= static_cast<double>(loop.size());
    x.insert(x.end(), center.data(), center.data() + 3);
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      // The loop runs with the surface on its left: the virtual triangle
      // uses the boundary edge in the opposite direction.
      triangles.insert(triangles.end(), { loop[(k + 1) % loop.size()], loop[k], next });
    }
    ++next;
  }
  const MeshTopology closed(next, std::move(triangles), opt.NumberOfThreads);
  std::vector<std::uint8_t> fixed;
  std::vector<double> weights;
  FairingConstraints extended;
  if (cons.Fixed)
  {
    fixed.assign(cons.Fixed, cons.Fixed + n);
    fixed.resize(next, 0);
    extended.Fixed = fixed.data();
  }
  if (cons.Weights)
  {
    weights.assign(cons.Weights, cons.Weights + n);
    weights.resize(next, 1.0);
    extended.Weights = weights.data();
  }
  std::vector<double> axes, normals;
  for (auto [given, copy, to] : { std::tuple{ cons.AxisDirections, &axes, &extended.AxisDirections },
         std::tuple{ cons.PlaneNormals, &normals, &extended.PlaneNormals } })
  {
    if (given)
    {
      copy->assign(given, given + 3 * static_cast<std::size_t>(n));
      copy->resize(3 * static_cast<std::size_t>(next), 0.0);
      *to = copy->data();
    }
  }
  opt.Boundary = FairingBoundary::Fixed; // anything left open (e.g. non-manifold) stays fixed
  FairingReport report = FairClosedOrFixed(closed, x.data(), opt, extended, progress);
  std::copy(x.begin(), x.begin() + 3 * static_cast<std::size_t>(n), points);
  return report;
}

} // namespace beltrami
