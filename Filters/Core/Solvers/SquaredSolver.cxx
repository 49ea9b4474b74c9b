// Beltrami core: the order-2 graph solver, SolveSquaredLaplacian's
// COCG on D + i sqrt(t) K (see GraphSolvers.h), preconditioned by Jacobi
// or by a V-cycle of the same complex operator (SurfaceMultigrid).
//
// The serial Jacobi solve works in mixed precision, as the order-1 solver
// does: the residual of the real system in double precision, from the
// caller's matrix in the caller's order, and COCG corrections of it in
// single precision on a renumbered single-precision copy of D + i sqrt(t) K,
// restarted from the true residual until it is small enough.  On the bunny
// Loop-subdivided four times (19.3M triangles) a double-precision copy and
// vectors would take 2.9 GB at the default fairing step's peak, these take
// 1.6 GB (and where page faults are slow, first touching fresh memory
// costs 1.5-2 s per GB).
#include "Solvers/GraphSolversDetail.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <new>
#include <stdexcept>
#include <type_traits>

namespace beltrami
{

namespace
{

/// The smallest residual reduction the mixed-precision solve is asked for
/// (ShiftedLaplacianProblem::MixedPrecisionRows); tighter ones are solved in
/// double precision (asked for 1e-6, single-precision corrections of an
/// ill-conditioned system stalled at 4e-6).
constexpr double MixedPrecisionTolerance = 1e-5;

/// Whether the values of the single-precision copy and residuals stay far
/// from its overflow and underflow: D_ii and sqrt(t) K_ii of the free rows,
/// and the right-hand side, within 1e-25 to 1e25 (coordinates of 1e20 or
/// 1e-20: double precision).
bool FitsSinglePrecision(const ShiftedLaplacianProblem& pb, const double* b)
{
  const double a = std::sqrt(pb.Factor);
  const std::vector<double> range = ParallelPartials(pb.Rows, 2, pb.NumberOfThreads,
    [&](std::int64_t s, std::int64_t e, double* partial) { // (the smallest as its negative: maxima alone)
      partial[0] = partial[1] = -HUGE_VAL;
      for (std::int64_t i = s; i < e; ++i)
      {
        double largest = 0.0;
        for (int c = 0; c < pb.Columns; ++c)
        {
          largest = std::max(largest, std::abs(b[i * pb.Columns + c]));
        }
        const bool free = !(pb.Fixed && pb.Fixed[i]) && pb.Shift[i] > 0.0;
        const double k = a * std::abs(pb.Diagonal[i]);
        partial[0] = std::max({ partial[0], largest, free ? pb.Shift[i] : 0.0, free ? k : 0.0 });
        partial[1] = std::max(partial[1], free ? -std::min(pb.Shift[i], k > 0.0 ? k : HUGE_VAL) : -HUGE_VAL);
      }
    });
  double largest = 0.0, smallest = HUGE_VAL;
  for (std::size_t c = 0; c < range.size(); c += 2)
  {
    largest = std::max(largest, range[c]);
    smallest = std::min(smallest, -range[c + 1]);
  }
  return std::isfinite(largest) && largest <= 1e25 && (smallest == HUGE_VAL || smallest >= 1e-25);
}

/// a b without the checks of std::complex's operator* for infinities
/// (a library call per product unless -fcx-limited-range).
inline std::complex<double> Times(std::complex<double> a, std::complex<double> b)
{
  return { a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real() };
}

/// The rows COCG works on, in precision Real: the caller's (distributed;
/// double only), or a copy renumbered in LocalityOrder (pb.Order, or
/// computed), whose products find a row's neighbours near in memory: one
/// default fairing step on the bunny Loop-subdivided three times (4.8M
/// triangles) took 27-33 s in the mesh's order and 18-22 s renumbered.
/// Dx: the correction of the caller's x, per working row.
template <class Real>
class SquaredSystem
{
public:
  SquaredSystem(const ShiftedLaplacianProblem& pb)
  {
    const std::int64_t n = pb.Rows;
    const int threads = pb.NumberOfThreads;
    if (pb.Split)
    {
      if constexpr (std::is_same_v<Real, double>)
      {
        Offsets = pb.Offsets, Neighbors = pb.Neighbors, Weights = pb.Weights, Diagonal = pb.Diagonal;
        Shift = pb.Shift, Fixed = pb.Fixed;
      }
      else
      {
        throw std::logic_error("SquaredSystem: a distributed system in single precision");
      }
    }
    else
    {
      Renumber(pb);
    }
    Dx.resize(static_cast<std::size_t>(n) * pb.Columns);
    Clear(threads);
  }

  /// The caller's row of working row i.
  std::int64_t Row(std::int64_t i) const { return Order ? Order[i] : i; }

  /// x += sign Dx (the caller's rows).
  void Fold(double* x, int nc, int threads, double sign = 1.0) const
  {
    ParallelForStatic(static_cast<std::int64_t>(Dx.size() / nc), threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < nc; ++c)
        {
          x[Row(i) * nc + c] += sign * Dx[i * nc + c];
        }
      }
    });
  }

  /// Dx = 0.
  void Clear(int threads)
  {
    const std::int64_t size = static_cast<std::int64_t>(Dx.size());
    ParallelForStatic(size, threads, [&](std::int64_t s, std::int64_t e) { std::fill(Dx.begin() + s, Dx.begin() + e, Real(0)); });
  }

  const std::int64_t* Offsets = nullptr;
  const Index* Neighbors = nullptr;
  const Real *Weights = nullptr, *Diagonal = nullptr, *Shift = nullptr;
  const std::uint8_t* Fixed = nullptr;
  UninitializedVector<Real> Dx;

private:
  void Renumber(const ShiftedLaplacianProblem& pb)
  {
    const std::int64_t n = pb.Rows;
    Order = detail::OrderOf(pb, Computed);
    detail::RenumberEntries(pb, Order, [](Index) { return true; },
      [&](std::int64_t k) { return static_cast<Real>(pb.Weights[k]); }, OwnOffsets, OwnNeighbors, OwnWeights);
    OwnDiagonal.resize(n);
    OwnShift.resize(n);
    OwnFixed.resize(pb.Fixed ? n : 0);
    ParallelForStatic(n, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const std::int64_t v = Order[i];
        OwnDiagonal[i] = static_cast<Real>(pb.Diagonal[v]);
        OwnShift[i] = static_cast<Real>(pb.Shift[v]);
        if (pb.Fixed)
        {
          OwnFixed[i] = pb.Fixed[v];
        }
      }
    });
    Offsets = OwnOffsets.data();
    Neighbors = OwnNeighbors.data();
    Weights = OwnWeights.data();
    Diagonal = OwnDiagonal.data();
    Shift = OwnShift.data();
    Fixed = pb.Fixed ? OwnFixed.data() : nullptr;
  }

  std::vector<Index> Computed;
  const Index* Order = nullptr; ///< working row i is the caller's row Order[i]
  UninitializedVector<std::int64_t> OwnOffsets;
  UninitializedVector<Index> OwnNeighbors;
  UninitializedVector<Real> OwnWeights, OwnDiagonal, OwnShift;
  UninitializedVector<std::uint8_t> OwnFixed;
};

/// The solve of SolveSquaredLaplacian for NC columns: COCG on
/// (D + i a K_ff) dz = res (res: the real residual); x += Re dz (only Re dz
/// is ever needed), folded into the caller's x where the real residual is
/// measured, in double precision from the caller's matrix.  The real
/// residual of Re dz is the complex one amplified (by up to ~ a ||K|| / D),
/// so the complex residual is first asked for two orders of magnitude more
/// than the real one needs.  In double precision (Real), where that was not
/// enough the same run goes on with a tighter target; in single precision
/// (mixed) it restarts from the true residual, each run asked for no more
/// than single precision resolves.  Vectors: the complex R, P and Q = A P
/// (the Jacobi inverses formed where they are used), with a V-cycle also
/// Z = M^-1 R.
template <int NC, class Real>
class SquaredSolver
{
public:
  using Complex = std::complex<double>;
  static constexpr int W = 2 * NC; // complex vectors: per row NC real parts, then NC imaginary parts
  static constexpr bool Mixed = !std::is_same_v<Real, double>;

  SquaredSolver(const ShiftedLaplacianProblem& pb, const double* b, double* x, const detail::ComplexCycle& cycle)
    : Cycle(cycle)
    , Pb(pb)
    , System(pb)
    , B(b)
    , X(x)
    , N(pb.Rows)
    , Threads(pb.NumberOfThreads)
    , T(pb.Factor)
    , A(std::sqrt(pb.Factor))
    , Size(static_cast<std::size_t>(pb.Rows) * NC)
    , R(2 * Size)
    , P(2 * Size)
    , KP(2 * Size)
    , Z(cycle ? 2 * Size : 0)
  {
  }

  /// The solve; `initial`: the column norms of the residual the tolerance
  /// is relative to, where an earlier run from the caller's start left x.
  ConjugateGradientResult Run(const double* initial = nullptr)
  {
    Iterate(initial); // (its corrections folded into x where it returns)
    return Result;
  }

  /// The column norms of the residual at the caller's start.
  const double* InitialNorms() const { return Initial; }

private:
  void Iterate(const double* initial)
  {
    Norms = RealResidual(true);
    for (int c = 0; c < NC; ++c)
    {
      Initial[c] = initial ? initial[c] : std::sqrt(std::max(0.0, Norms[c]));
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
    // (A run that goes on where an earlier one stopped - `initial` - is not
    // held to halving the residual it starts from by its first check.)
    double target = FirstTarget(needed), lastRelative = initial ? HUGE_VAL : Result.RelativeResidual;
    while (Result.Iterations < Pb.MaximumIterations)
    {
      Complex alpha[NC], beta[NC];
      ApplyOperator(alpha);
      const bool reached = Advance(alpha, beta, target);
      if (reached || Stalled || Result.Iterations >= Pb.MaximumIterations)
      {
        const std::vector<double> before = Norms;
        System.Fold(X, NC, Threads);
        Norms = RealResidual(Mixed);
        needed = Check();
        const bool finite = std::all_of(Norms.begin(), Norms.end(), [](double v) { return std::isfinite(v); });
        if (Mixed && (!finite || (!Result.Converged && !(Result.RelativeResidual < lastRelative))))
        {
          // Single-precision corrections that left x farther (or not
          // finite): taken back (the caller goes on in double precision).
          System.Fold(X, NC, Threads, -1.0);
          Norms = before;
          Check();
          Result.Converged = false;
          return;
        }
        System.Clear(Threads);
        if (Result.Converged || Stalled || !(Result.RelativeResidual < 0.5 * lastRelative) ||
          Result.Iterations >= Pb.MaximumIterations)
        {
          return; // not converged: no progress left in this run, the caller decides
        }
        lastRelative = Result.RelativeResidual;
        if constexpr (Mixed)
        {
          target = FirstTarget(needed);
          Start(); // from the true residual
          continue;
        }
        target *= std::max(1e-4, 0.1 * needed);
      }
      NewDirection(beta);
    }
  }

  /// The complex residual asked of a run: two orders of magnitude below the
  /// fraction of the real one still needed, in single precision not below
  /// what it resolves.
  static double FirstTarget(double needed) { return Mixed ? std::max(1e-7, 0.01 * needed) : 0.01 * needed; }

  /// The free rows of x from Pb.Guess (ShiftedLaplacianProblem::Guess).
  void StartAtGuess()
  {
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t v = s; v < e; ++v)
      {
        if (IsFreeRow(v))
        {
          std::copy_n(Pb.Guess + v * NC, NC, X + v * NC);
        }
      }
    });
  }

  /// Distributed (Pb.Split): only the owned rows are unknowns; the ghost
  /// rows of an operand are refreshed before each product, sums are summed
  /// over the processes.  Working rows (IsFree, IsHeld) and the caller's
  /// (IsFreeRow, IsHeldRow).
  bool IsFree(std::int64_t i) const { return IsHeld(i) ? false : !Pb.Split || Pb.Split->IsOwned(static_cast<Index>(i)); }
  bool IsHeld(std::int64_t i) const { return System.Fixed && System.Fixed[i]; }
  bool IsHeldRow(std::int64_t v) const { return Pb.Fixed && Pb.Fixed[v]; }
  bool IsFreeRow(std::int64_t v) const { return IsHeldRow(v) ? false : !Pb.Split || Pb.Split->IsOwned(static_cast<Index>(v)); }
  std::vector<double> Total(std::vector<double> sums) const
  {
    if (Pb.Split)
    {
      Pb.Split->Sum(sums.data(), static_cast<int>(sums.size()));
    }
    return sums;
  }
  template <class V>
  void Refresh(V* v, int columns) const
  {
    if constexpr (std::is_same_v<V, double>)
    {
      if (Pb.Split)
      {
        Pb.Split->UpdateGhosts(v, columns);
      }
    }
  }

  /// b - A x on the caller's free rows, in double precision from the
  /// caller's matrix, also into R (real parts; imaginary parts 0) when
  /// `start`; returns the column norms.  (Its products: ResidualScratch.)
  std::vector<double> RealResidual(bool start)
  {
    double* y = ResidualScratch();
    Refresh(X, NC);
    ApplyGraphStiffness(N, Pb.Offsets, Pb.Neighbors, Pb.Weights, Pb.Diagonal, X, y, NC, Threads);
    ParallelForStatic(N, Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t v = s; v < e; ++v)
      {
        const double f = IsHeldRow(v) ? 0.0 : 1.0 / Pb.Shift[v];
        for (int c = 0; c < NC; ++c)
        {
          y[v * NC + c] *= f;
        }
      }
    });
    Refresh(y, NC); // the ghosts' rows of K x are not all here
    return Total(ParallelSum(N, NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i) // (working rows: R's writes in order, the caller's rows read whole)
      {
        const std::int64_t v = System.Row(i);
        double ky[NC];
        StiffnessRow<NC>(v, Pb.Offsets, Pb.Neighbors, Pb.Weights, Pb.Diagonal, y, ky);
        const bool f = IsFreeRow(v);
        for (int c = 0; c < NC; ++c)
        {
          const double res = f ? B[v * NC + c] - Pb.Shift[v] * X[v * NC + c] - T * ky[c] : 0.0;
          if (start)
          {
            R[i * W + c] = static_cast<Real>(res);
            R[i * W + NC + c] = Real(0);
          }
          acc[c] += res * res;
        }
      }
    }));
  }

  /// Room for NC doubles a row while the real residual is formed: KP in
  /// double precision; in single precision P, whose bytes hold as many (it
  /// is set anew from R after each residual: Start), as doubles for this
  /// while (their lifetime begun there, and P's ended, by default-initialising
  /// construction).
  double* ResidualScratch()
  {
    if constexpr (Mixed)
    {
      static_assert(2 * sizeof(Real) == sizeof(double), "two single-precision values hold one double");
      double* room = reinterpret_cast<double*>(P.data());
      std::uninitialized_default_construct_n(room, Size); // (no code: a new lifetime, values unspecified)
      return std::launder(room);
    }
    else
    {
      return KP.data();
    }
  }

  /// Starts P's values' lifetime again in its bytes after ResidualScratch.
  void ReclaimP()
  {
    if constexpr (Mixed)
    {
      std::uninitialized_default_construct_n(P.data(), 2 * Size);
    }
  }

  /// z = M^-1 R by the cycle (double precision only).
  void ApplyCycle(Real* z) const
  {
    if constexpr (Mixed)
    {
      throw std::logic_error("SquaredSolver: a V-cycle in single precision");
    }
    else
    {
      Cycle(R.data(), z, W);
    }
  }

  /// Jacobi: 1 / (D_i + i a K_ii) on the free rows, 0 on the others.
  Complex InverseAt(std::int64_t i) const
  {
    const double d = System.Shift[i], k = A * System.Diagonal[i], scale = IsFree(i) ? 1.0 / (d * d + k * k) : 0.0;
    return { d * scale, -k * scale };
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
    ReclaimP();
    std::vector<double> sums;
    if (Cycle)
    {
      ApplyCycle(P.data());
      sums = RhoAndNorms(P.data());
    }
    else
    {
      sums = Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
        for (std::int64_t i = s; i < e; ++i)
        {
          for (int c = 0; c < NC; ++c)
          {
            const double r = R[i * W + c];
            const Complex z = Times(InverseAt(i), r);
            P[i * W + c] = static_cast<Real>(z.real());
            P[i * W + NC + c] = static_cast<Real>(z.imag());
            acc[2 * c] += r * z.real(); // rho = r^T z, unconjugated
            acc[2 * c + 1] += r * z.imag();
            acc[2 * NC + c] += r * r;
          }
        }
      }));
    }
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
    ApplyGraphStiffness(N, System.Offsets, System.Neighbors, System.Weights, System.Diagonal, P.data(), KP.data(), W,
      Threads);
    const std::vector<double> pq = Total(ParallelSum(N, 2 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      double local[2 * NC] = {};
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = IsFree(i);
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          const Complex p(P[re], P[im]);
          const Complex q = f ? static_cast<double>(System.Shift[i]) * p + Complex(-A * KP[im], A * KP[re]) : Complex(0.0);
          KP[re] = static_cast<Real>(q.real());
          KP[im] = static_cast<Real>(q.imag());
          const Complex product = Times(p, q);
          local[2 * c] += f ? product.real() : 0.0;
          local[2 * c + 1] += f ? product.imag() : 0.0;
        }
      }
      for (int k = 0; k < 2 * NC; ++k)
      {
        acc[k] += local[k];
      }
    }));
    for (int c = 0; c < NC; ++c)
    {
      const Complex d(pq[2 * c], pq[2 * c + 1]);
      alpha[c] = std::abs(d) > 0.0 ? Rho[c] / d : Complex(0.0);
    }
  }

  /// Dx += Re(alpha P) on the free rows, R -= alpha Q, the new rho (with
  /// Z = M^-1 R) and beta; true when every column's complex residual
  /// reached `target` of its start.
  bool Advance(const Complex* alpha, Complex* beta, double target)
  {
    Real* dx = System.Dx.data();
    const bool jacobi = !Cycle;
    std::vector<double> sums = Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      double local[3 * NC] = {}; // (not through acc: its stores would not leave the loop)
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = IsFree(i);
        const Complex inverse = InverseAt(i);
        for (int c = 0; c < NC; ++c)
        {
          const std::int64_t re = i * W + c, im = re + NC;
          dx[i * NC + c] += static_cast<Real>(f ? alpha[c].real() * P[re] - alpha[c].imag() * P[im] : 0.0);
          const Complex r = Complex(R[re], R[im]) - Times(alpha[c], Complex(KP[re], KP[im]));
          R[re] = static_cast<Real>(r.real());
          R[im] = static_cast<Real>(r.imag());
          const Complex rz = jacobi ? Times(r, Times(inverse, r)) : Complex(0.0);
          local[2 * c] += f ? rz.real() : 0.0;
          local[2 * c + 1] += f ? rz.imag() : 0.0;
          local[2 * NC + c] += f ? std::norm(r) : 0.0;
        }
      }
      for (int k = 0; k < 3 * NC; ++k)
      {
        acc[k] += local[k];
      }
    }));
    ++Result.Iterations;
    if (Cycle)
    {
      ApplyCycle(Z.data());
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
          const Complex z = Cycle ? Complex(Z[re], Z[im]) : Times(InverseAt(i), Complex(R[re], R[im]));
          const Complex p = z + Times(beta[c], Complex(P[re], P[im]));
          P[re] = static_cast<Real>(p.real());
          P[im] = static_cast<Real>(p.imag());
        }
      }
    });
  }

  /// With a preconditioner: the sums r^T z (unconjugated; real and
  /// imaginary part per column) over the free rows, then ||r||^2 per column.
  std::vector<double> RhoAndNorms(const Real* z) const
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
  const ShiftedLaplacianProblem& Pb;
  SquaredSystem<Real> System;
  const double* B;
  double* X; ///< the caller's x
  const std::int64_t N;
  const int Threads;
  const double T, A;
  const std::size_t Size;
  UninitializedVector<Real> R, P, KP, Z; // Z = M^-1 R with a preconditioner
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
  return WithCount<4>(pb.Columns, [&](auto k) {
    constexpr int nc = decltype(k)::value;
    if (cycle || pb.Split || pb.Tolerance < MixedPrecisionTolerance || pb.Rows < pb.MixedPrecisionRows ||
      !FitsSinglePrecision(pb, b))
    {
      return SquaredSolver<nc, double>(pb, b, x, cycle).Run();
    }
    double initial[nc];
    ConjugateGradientResult mixed;
    {
      SquaredSolver<nc, float> solver(pb, b, x, cycle);
      mixed = solver.Run();
      std::copy_n(solver.InitialNorms(), nc, initial);
    } // (its buffers freed)
    if (mixed.Converged || mixed.Iterations >= pb.MaximumIterations)
    {
      return mixed;
    }
    // Single precision made no more progress (an operator whose real part
    // the corrections' round-off hides): on in double precision from there.
    ShiftedLaplacianProblem rest = pb;
    rest.Guess = nullptr;
    rest.MaximumIterations -= mixed.Iterations;
    ConjugateGradientResult r = SquaredSolver<nc, double>(rest, b, x, cycle).Run(initial);
    r.Iterations += mixed.Iterations;
    return r;
  });
}

} // namespace beltrami
