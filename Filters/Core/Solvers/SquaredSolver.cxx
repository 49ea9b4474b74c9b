// Beltrami core: the order-2 graph solver, SolveSquaredLaplacian's
// COCG on D + i sqrt(t) K (see GraphSolvers.h), preconditioned by Jacobi
// or by a V-cycle of the same complex operator (SurfaceMultigrid).
#include "Solvers/GraphSolversDetail.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cmath>
#include <complex>

namespace beltrami
{

namespace
{

/// y = K x for W values per row, all rows.
template <int W>
void StiffnessProduct(const ShiftedLaplacianProblem& pb, const double* x, double* y)
{
  ApplyGraphStiffness(pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, x, y, W, pb.NumberOfThreads);
}

/// a b without the checks of std::complex's operator* for infinities
/// (a library call per product unless -fcx-limited-range).
inline std::complex<double> Times(std::complex<double> a, std::complex<double> b)
{
  return { a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real() };
}

/// The rows a SquaredSolver works on: the caller's (distributed), or a copy
/// renumbered in LocalityOrder (pb.Order, or computed), whose products find
/// a row's neighbours near in memory: one default fairing step on the bunny
/// Loop-subdivided three times (4.8M triangles) took 27-33 s in the mesh's
/// order and 18-22 s renumbered.  X: the solution in the working order (the
/// caller's x when not renumbered); B: the caller's right-hand side, whose
/// row for working row i is Row(i).
class SquaredSystem
{
public:
  SquaredSystem(const ShiftedLaplacianProblem& pb, const double* b, double* x)
    : Problem(pb)
    , B(b)
    , X(x)
  {
    if (!pb.Split && pb.Rows > 0)
    {
      Renumber(pb, x);
    }
  }

  /// The caller's row of working row i.
  std::int64_t Row(std::int64_t i) const { return Order ? Order[i] : i; }

  /// The working solution into the caller's x.
  void Return(double* x) const
  {
    const int nc = Problem.Columns;
    if (Order)
    {
      ParallelForStatic(Problem.Rows, Problem.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
        for (std::int64_t i = s; i < e; ++i)
        {
          std::copy_n(X + i * nc, nc, x + static_cast<std::int64_t>(Order[i]) * nc);
        }
      });
    }
  }

  ShiftedLaplacianProblem Problem; ///< the working rows
  const double* B;
  double* X;

private:
  void Renumber(const ShiftedLaplacianProblem& pb, const double* x)
  {
    const std::int64_t n = pb.Rows;
    const int nc = pb.Columns;
    Order = detail::OrderOf(pb, Computed);
    detail::RenumberEntries(pb, Order, [](Index) { return true; }, [&](std::int64_t k) { return pb.Weights[k]; }, Offsets,
      Neighbors, Weights);
    Diagonal.resize(n);
    Shift.resize(n);
    Fixed.resize(pb.Fixed ? n : 0);
    Solution.resize(n * nc);
    ParallelForStatic(n, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const std::int64_t v = Order[i];
        Diagonal[i] = pb.Diagonal[v];
        Shift[i] = pb.Shift[v];
        if (pb.Fixed)
        {
          Fixed[i] = pb.Fixed[v];
        }
        std::copy_n(x + v * nc, nc, Solution.data() + i * nc);
      }
    });
    Problem.Offsets = Offsets.data();
    Problem.Neighbors = Neighbors.data();
    Problem.Weights = Weights.data();
    Problem.Diagonal = Diagonal.data();
    Problem.Shift = Shift.data();
    Problem.Fixed = pb.Fixed ? Fixed.data() : nullptr;
    Problem.Order = nullptr;
    X = Solution.data();
  }

  std::vector<Index> Computed;
  const Index* Order = nullptr; ///< working row i is the caller's row Order[i]
  LargeVector<std::int64_t> Offsets;
  LargeVector<Index> Neighbors;
  LargeVector<double> Weights, Diagonal, Shift, Solution;
  LargeVector<std::uint8_t> Fixed;
};

/// The solve of SolveSquaredLaplacian for NC columns: one COCG run on
/// (D + i a K_ff) dz = res (res: the initial real residual); x = x0 + Re dz,
/// accumulated into x as it goes (only Re dz is ever needed).
/// The real residual of Re dz is the complex one amplified (by up to
/// ~ a ||K|| / D), so the complex residual is first asked for two orders of
/// magnitude more than the real one needs; where that was not enough, the
/// same run goes on with a tighter target (no restart).  Vectors: the
/// complex R, P and Q = A P (Q also the scratch of the real residual), and
/// the Jacobi inverses; Z = M^-1 R is formed where it is used.
template <int NC>
class SquaredSolver
{
public:
  using Complex = std::complex<double>;
  static constexpr int W = 2 * NC; // complex vectors: per row NC real parts, then NC imaginary parts

  SquaredSolver(const ShiftedLaplacianProblem& pb, const double* b, double* x, const detail::ComplexCycle& cycle)
    : Cycle(cycle)
    , System(pb, b, x)
    , Pb(System.Problem)
    , B(System.B)
    , X(System.X)
    , Xout(x)
    , N(pb.Rows)
    , Threads(pb.NumberOfThreads)
    , T(pb.Factor)
    , A(std::sqrt(pb.Factor))
    , Size(static_cast<std::size_t>(pb.Rows) * NC)
    , R(2 * Size)
    , P(2 * Size)
    , KP(2 * Size)
    , Z(cycle ? 2 * Size : 0)
    , Inverse(static_cast<std::size_t>(pb.Rows))
  {
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) { // Jacobi: 1 / (D_i + i a K_ii)
      for (std::int64_t i = s; i < e; ++i)
      {
        Inverse[i] = IsFree(i) ? 1.0 / Complex(Pb.Shift[i], A * Pb.Diagonal[i]) : Complex(0.0);
      }
    });
  }

  ConjugateGradientResult Run()
  {
    Iterate();
    System.Return(Xout);
    return Result;
  }

private:
  void Iterate()
  {
    Norms = RealResidual(true);
    for (int c = 0; c < NC; ++c)
    {
      Initial[c] = std::sqrt(std::max(0.0, Norms[c]));
      Threshold[c] = std::max(Pb.Tolerance * Initial[c], ResidualRoundOff * Pb.Scale[c]);
    }
    if (Pb.Guess)
    {
      StartAtGuess();
      Norms = RealResidual(true);
    }
    double needed = Check();
    if (Result.Converged)
    {
      return;
    }
    Start();
    double target = 0.01 * needed, lastRelative = Result.RelativeResidual;
    while (Result.Iterations < Pb.MaximumIterations)
    {
      Complex alpha[NC], beta[NC];
      ApplyOperator(alpha);
      const bool reached = Advance(alpha, beta, target);
      if (reached || Stalled || Result.Iterations >= Pb.MaximumIterations)
      {
        Norms = RealResidual(false);
        needed = Check();
        if (Result.Converged || Stalled || !(Result.RelativeResidual < 0.5 * lastRelative))
        {
          return; // not converged: no progress left in this run, the caller decides
        }
        lastRelative = Result.RelativeResidual;
        target *= std::max(1e-4, 0.1 * needed);
      }
      NewDirection(beta);
    }
  }

  /// The free rows of X from Pb.Guess (ShiftedLaplacianProblem::Guess).
  void StartAtGuess()
  {
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        if (IsFree(i))
        {
          std::copy_n(Pb.Guess + System.Row(i) * NC, NC, X + i * NC);
        }
      }
    });
  }

  /// Distributed (Pb.Split): only the owned rows are unknowns; the ghost
  /// rows of an operand are refreshed before each product, sums are summed
  /// over the processes.
  bool IsFree(std::int64_t i) const { return IsHeld(i) ? false : !Pb.Split || Pb.Split->IsOwned(static_cast<Index>(i)); }
  bool IsHeld(std::int64_t i) const { return Pb.Fixed && Pb.Fixed[i]; }
  std::vector<double> Total(std::vector<double> sums) const
  {
    if (Pb.Split)
    {
      Pb.Split->Sum(sums.data(), static_cast<int>(sums.size()));
    }
    return sums;
  }
  void Refresh(double* v, int columns) const
  {
    if (Pb.Split)
    {
      Pb.Split->UpdateGhosts(v, columns);
    }
  }

  /// b - A x on the free rows, also into R (real parts; imaginary parts 0)
  /// when `start`; returns the column norms.  The products use KP as scratch.
  std::vector<double> RealResidual(bool start)
  {
    double* kx = KP.data();
    double* nkx = KP.data() + Size;
    Refresh(X, NC);
    StiffnessProduct<NC>(Pb, X, kx);
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const double f = IsHeld(i) ? 0.0 : 1.0 / Pb.Shift[i];
        for (int c = 0; c < NC; ++c)
        {
          nkx[i * NC + c] = f * kx[i * NC + c];
        }
      }
    });
    Refresh(nkx, NC); // the ghosts' rows of K x are not all here
    StiffnessProduct<NC>(Pb, nkx, kx);
    return Total(ParallelSum(N, NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = IsFree(i);
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t k = i * NC + c;
          const double res = f ? B[System.Row(i) * NC + c] - Pb.Shift[i] * X[k] - T * kx[k] : 0.0;
          if (start)
          {
            R[i * W + c] = res;
            R[i * W + NC + c] = 0.0;
          }
          acc[c] += res * res;
        }
      }
    }));
  }

  /// Whether every column is below its threshold (Result.Converged) and the
  /// fraction of the current real residual the columns still above it need
  /// (the smallest over those columns).
  double Check()
  {
    bool done = true;
    double relative = 0.0, needed = 1.0;
    for (int c = 0; c < NC; ++c)
    {
      const double norm = std::sqrt(std::max(0.0, Norms[c]));
      if (Initial[c] > 0.0)
      {
        relative = std::max(relative, norm / Initial[c]);
      }
      if (norm > Threshold[c])
      {
        done = false;
        needed = std::min(needed, Threshold[c] / norm);
      }
    }
    Result.RelativeResidual = relative;
    Result.Converged = done;
    return needed;
  }

  /// The COCG start from the real residual in R: P = M^-1 R.
  void Start()
  {
    if (Cycle)
    {
      Cycle(R.data(), P.data(), W);
      const std::vector<double> sums = RhoAndNorms(P.data());
      for (int c = 0; c < NC; ++c)
      {
        Rho[c] = Complex(sums[2 * c], sums[2 * c + 1]);
        StartNorm[c] = std::sqrt(sums[2 * NC + c]);
      }
      return;
    }
    const std::vector<double> sums = Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < NC; ++c)
        {
          const double r = R[i * W + c];
          const Complex z = Times(Inverse[i], r);
          P[i * W + c] = z.real();
          P[i * W + NC + c] = z.imag();
          acc[2 * c] += r * z.real(); // rho = r^T z, unconjugated
          acc[2 * c + 1] += r * z.imag();
          acc[2 * NC + c] += r * r;
        }
      }
    }));
    for (int c = 0; c < NC; ++c)
    {
      Rho[c] = Complex(sums[2 * c], sums[2 * c + 1]);
      StartNorm[c] = std::sqrt(sums[2 * NC + c]);
    }
  }

  /// q = D p + i a K p (into KP) and alpha = rho / p^T q.
  void ApplyOperator(Complex* alpha)
  {
    Refresh(P.data(), W);
    StiffnessProduct<W>(Pb, P.data(), KP.data());
    const std::vector<double> pq = Total(ParallelSum(N, 2 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = IsFree(i);
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          const Complex p(P[re], P[im]);
          const Complex q = f ? Pb.Shift[i] * p + Complex(-A * KP[im], A * KP[re]) : Complex(0.0);
          KP[re] = q.real();
          KP[im] = q.imag();
          const Complex product = Times(p, q);
          acc[2 * c] += f ? product.real() : 0.0;
          acc[2 * c + 1] += f ? product.imag() : 0.0;
        }
      }
    }));
    for (int c = 0; c < NC; ++c)
    {
      const Complex d(pq[2 * c], pq[2 * c + 1]);
      alpha[c] = std::abs(d) > 0.0 ? Rho[c] / d : Complex(0.0);
    }
  }

  /// x += Re(alpha P) on the free rows, R -= alpha Q, the new rho (with
  /// Z = M^-1 R) and beta; true when every column's complex residual
  /// reached `target` of its start.
  bool Advance(const Complex* alpha, Complex* beta, double target)
  {
    std::vector<double> sums = Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = IsFree(i);
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          X[i * NC + c] += f ? alpha[c].real() * P[re] - alpha[c].imag() * P[im] : 0.0;
          const Complex r = Complex(R[re], R[im]) - Times(alpha[c], Complex(KP[re], KP[im]));
          R[re] = r.real();
          R[im] = r.imag();
          const Complex rz = Cycle ? Complex(0.0) : Times(r, Times(Inverse[i], r));
          acc[2 * c] += f ? rz.real() : 0.0;
          acc[2 * c + 1] += f ? rz.imag() : 0.0;
          acc[2 * NC + c] += f ? std::norm(r) : 0.0;
        }
      }
    }));
    ++Result.Iterations;
    if (Cycle)
    {
      Cycle(R.data(), Z.data(), W);
      const std::vector<double> rz = RhoAndNorms(Z.data());
      std::copy(rz.begin(), rz.begin() + 2 * NC, sums.begin());
    }
    bool reached = true;
    for (int c = 0; c < NC; ++c)
    {
      const Complex rhoNew(sums[2 * c], sums[2 * c + 1]);
      const double current = std::sqrt(sums[2 * NC + c]);
      reached = reached && current <= target * StartNorm[c];
      Stalled = Stalled || (current > 0.0 && !(std::abs(Rho[c]) > 0.0));
      beta[c] = std::abs(Rho[c]) > 0.0 ? rhoNew / Rho[c] : Complex(0.0);
      Rho[c] = rhoNew;
    }
    return reached;
  }

  /// P = M^-1 R + beta P.
  void NewDirection(const Complex* beta)
  {
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          const Complex z = Cycle ? Complex(Z[re], Z[im]) : Times(Inverse[i], Complex(R[re], R[im]));
          const Complex p = z + Times(beta[c], Complex(P[re], P[im]));
          P[re] = p.real();
          P[im] = p.imag();
        }
      }
    });
  }

  /// With a preconditioner: the sums r^T z (unconjugated; real and
  /// imaginary part per column) over the free rows, then ||r||^2 per column.
  std::vector<double> RhoAndNorms(const double* z) const
  {
    return Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        if (!IsFree(i))
        {
          continue;
        }
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          const Complex r(R[re], R[im]);
          const Complex rz = Times(r, Complex(z[re], z[im]));
          acc[2 * c] += rz.real();
          acc[2 * c + 1] += rz.imag();
          acc[2 * NC + c] += std::norm(r);
        }
      }
    }));
  }

  const detail::ComplexCycle& Cycle;
  SquaredSystem System;
  const ShiftedLaplacianProblem& Pb;
  const double* B;
  double* X;
  double* Xout;
  const std::int64_t N;
  const int Threads;
  const double T, A;
  const std::size_t Size;
  LargeVector<double> R, P, KP, Z; // Z = M^-1 R with a preconditioner
  LargeVector<Complex> Inverse;
  ConjugateGradientResult Result;
  std::vector<double> Norms;
  double Initial[NC] = {}, Threshold[NC] = {}, StartNorm[NC] = {};
  Complex Rho[NC];
  bool Stalled = false;
};

} // namespace

ConjugateGradientResult detail::SolveSquaredComplex(
  const ShiftedLaplacianProblem& pb, const double* b, double* x, const ComplexCycle& cycle)
{
  return WithCount<4>(pb.Columns, [&](auto k) { return SquaredSolver<decltype(k)::value>(pb, b, x, cycle).Run(); });
}

} // namespace beltrami
