#include "Solvers/GraphSolvers.h"

#include "Solvers/Partition.h"
#include "Solvers/SparseGraph.h"
#include "Support/LargeBuffer.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace beltrami
{

namespace
{

/// The renumbered single-precision copy of D + t K, for W values per row (the
/// column count; 5 to 7 columns are padded to 8); fixed rows have no
/// off-diagonal entries, a unit diagonal and stay zero.
struct SinglePrecisionSystem
{
  std::int64_t Rows = 0;
  LargeVector<std::int64_t> Offsets;
  LargeVector<Index> Neighbors;
  LargeVector<float> Weights, Diagonal, InverseDiagonal;
  LargeVector<std::uint8_t> Free;
};

/// The locality order of pb's rows: pb.Order, or computed into `computed`.
const Index* OrderOf(const ShiftedLaplacianProblem& pb, std::vector<Index>& computed)
{
  if (pb.Order)
  {
    return pb.Order;
  }
  computed = LocalityOrder(pb.Rows, pb.Offsets, pb.Neighbors);
  return computed.data();
}

/// pb's graph renumbered by `order` (row i is the caller's row order[i]):
/// offsets, neighbours and each entry's value(k) (k: the caller's entry);
/// rows with keep(v) false get no entries.  Returns the new position of
/// each of the caller's rows.
template <typename T, typename Keep, typename ValueOf>
std::vector<Index> RenumberEntries(const ShiftedLaplacianProblem& pb, const Index* order, Keep&& keep,
  ValueOf&& value, LargeVector<std::int64_t>& offsets, LargeVector<Index>& neighbors, LargeVector<T>& values)
{
  const std::int64_t n = pb.Rows;
  std::vector<Index> position(static_cast<std::size_t>(n));
  offsets.resize(static_cast<std::size_t>(n) + 1);
  offsets[0] = 0;
  for (std::int64_t i = 0; i < n; ++i)
  {
    const Index v = order[i];
    position[v] = static_cast<Index>(i);
    offsets[i + 1] = offsets[i] + (keep(v) ? pb.Offsets[v + 1] - pb.Offsets[v] : 0);
  }
  neighbors.resize(static_cast<std::size_t>(offsets[n]));
  values.resize(static_cast<std::size_t>(offsets[n]));
  ParallelForStatic(n, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t i = s; i < e; ++i)
    {
      const Index v = order[i];
      for (std::int64_t k = pb.Offsets[v], o = offsets[i]; keep(v) && k < pb.Offsets[v + 1]; ++k, ++o)
      {
        neighbors[o] = position[pb.Neighbors[k]];
        values[o] = value(k);
      }
    }
  });
  return position;
}

/// The correction: A dx = r (r in the renumbered order, W per row; inactive
/// columns are left at 0) until the residual of every active column is below
/// target[c].  Returns the iterations.
template <int W>
int SolveCorrection(const SinglePrecisionSystem& A, LargeVector<float>& r, LargeVector<float>& dx,
  const double* target, bool* active, int maxIterations, int threads)
{
  const std::int64_t n = A.Rows;
  const std::size_t size = static_cast<std::size_t>(n) * W;
  LargeVector<float> p(size), q(size);
  dx.assign(size, 0.0f);
  std::vector<double> s = ParallelSum(n, 2 * W, threads, [&](std::int64_t b, std::int64_t e, double* acc) {
    for (std::int64_t i = b; i < e; ++i)
    {
      const float id = A.InverseDiagonal[i];
      for (int c = 0; c < W; ++c)
      {
        r[i * W + c] = active[c] ? r[i * W + c] : 0.0f;
        const float z = id * r[i * W + c];
        p[i * W + c] = z;
        acc[c] += static_cast<double>(r[i * W + c]) * z;
        acc[W + c] += static_cast<double>(r[i * W + c]) * r[i * W + c];
      }
    }
  });
  double rz[W];
  for (int c = 0; c < W; ++c)
  {
    rz[c] = s[c];
    active[c] = active[c] && std::sqrt(s[W + c]) > target[c] && rz[c] > 0.0;
  }
  int it = 0;
  while (std::any_of(active, active + W, [](bool a) { return a; }) && it < maxIterations)
  {
    ++it;
    // q = A p and p.q in one pass.
    const std::vector<double> pq = ParallelSum(n, W, threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      double sum[W] = {};
      for (std::int64_t i = b; i < e; ++i)
      {
        float y[W];
        const float d = A.Diagonal[i];
        for (int c = 0; c < W; ++c)
        {
          y[c] = d * p[i * W + c];
        }
        for (std::int64_t k = A.Offsets[i]; k < A.Offsets[i + 1]; ++k)
        {
          const float w = A.Weights[k];
          const float* pj = p.data() + static_cast<std::int64_t>(A.Neighbors[k]) * W;
          for (int c = 0; c < W; ++c)
          {
            y[c] -= w * pj[c];
          }
        }
        for (int c = 0; c < W; ++c)
        {
          q[i * W + c] = y[c];
          sum[c] += static_cast<double>(p[i * W + c]) * y[c];
        }
      }
      std::copy(sum, sum + W, acc);
    });
    float alpha[W];
    for (int c = 0; c < W; ++c)
    {
      alpha[c] = active[c] && pq[c] > 0.0 ? static_cast<float>(rz[c] / pq[c]) : 0.0f;
    }
    const std::vector<double> sums = ParallelSum(n, 2 * W, threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      double sum[2 * W] = {};
      for (std::int64_t i = b; i < e; ++i)
      {
        const float id = A.InverseDiagonal[i];
        for (int c = 0; c < W; ++c)
        {
          const float rc = r[i * W + c] - alpha[c] * q[i * W + c];
          r[i * W + c] = rc;
          sum[c] += static_cast<double>(rc) * (id * rc);
          sum[W + c] += static_cast<double>(rc) * rc;
        }
      }
      std::copy(sum, sum + 2 * W, acc);
    });
    float beta[W];
    for (int c = 0; c < W; ++c)
    {
      beta[c] = active[c] && rz[c] > 0.0 ? static_cast<float>(sums[c] / rz[c]) : 0.0f;
      if (active[c])
      {
        rz[c] = sums[c];
        active[c] = std::sqrt(sums[W + c]) > target[c] && rz[c] > 0.0;
      }
    }
    float keep[W];
    for (int c = 0; c < W; ++c)
    {
      keep[c] = active[c] ? 1.0f : 0.0f;
    }
    // x += alpha p (the old p), then the new direction.
    ParallelForStatic(n, threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        const float id = A.InverseDiagonal[i];
        for (int c = 0; c < W; ++c)
        {
          dx[i * W + c] += alpha[c] * p[i * W + c];
          p[i * W + c] = keep[c] * (id * r[i * W + c] + beta[c] * p[i * W + c]);
        }
      }
    });
  }
  return it;
}

template <int W>
ConjugateGradientResult SolveShifted(const ShiftedLaplacianProblem& pb, const double* b, double* x)
{
  const std::int64_t n = pb.Rows;
  const int nc = pb.Columns;
  const int threads = pb.NumberOfThreads;
  std::vector<Index> computed;
  const Index* order = OrderOf(pb, computed);
  const auto diagonalOf = [&](std::int64_t i) {
    return (pb.Shift ? pb.Shift[i] : 0.0) + pb.Factor * pb.Diagonal[i];
  };
  const auto isFree = [&](std::int64_t i) {
    const double d = diagonalOf(i);
    return (!pb.Fixed || !pb.Fixed[i]) && d > 0.0 && std::isfinite(d);
  };

  // The renumbered single-precision system.
  SinglePrecisionSystem A;
  A.Rows = n;
  const std::vector<Index> position = RenumberEntries(pb, order, isFree,
    [&](std::int64_t k) { return static_cast<float>(pb.Factor * pb.Weights[k]); }, A.Offsets, A.Neighbors, A.Weights);
  A.Diagonal.resize(n);
  A.InverseDiagonal.resize(n);
  A.Free.resize(n);
  ParallelForStatic(n, threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t i = s; i < e; ++i)
    {
      const Index v = order[i];
      const bool free = isFree(v);
      A.Free[i] = free;
      const double d = free ? diagonalOf(v) : 1.0;
      A.Diagonal[i] = static_cast<float>(d);
      A.InverseDiagonal[i] = static_cast<float>(1.0 / d);
    }
  });

  // r = b - A x, in double (rows in the caller's order: sequential reads),
  // stored renumbered in single precision, and its norms.
  LargeVector<float> r(static_cast<std::size_t>(n) * W), dx;
  const auto residual = [&]() {
    return ParallelSum(n, nc, threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t v = s; v < e; ++v)
      {
        const std::int64_t i = position[v];
        if (!A.Free[i])
        {
          continue; // r stays 0
        }
        const double d = diagonalOf(v);
        double y[W] = {};
        for (int c = 0; c < nc; ++c)
        {
          y[c] = d * x[v * nc + c];
        }
        for (std::int64_t k = pb.Offsets[v]; k < pb.Offsets[v + 1]; ++k)
        {
          const double w = pb.Factor * pb.Weights[k];
          const double* xj = x + static_cast<std::int64_t>(pb.Neighbors[k]) * nc;
          for (int c = 0; c < nc; ++c)
          {
            y[c] -= w * xj[c];
          }
        }
        for (int c = 0; c < nc; ++c)
        {
          const double rc = b[v * nc + c] - y[c];
          r[i * W + c] = static_cast<float>(rc);
          acc[c] += rc * rc;
        }
      }
    });
  };

  ConjugateGradientResult result;
  std::vector<double> norms = residual(), initial(nc), threshold(W, 0.0);
  for (int c = 0; c < nc; ++c)
  {
    initial[c] = std::sqrt(norms[c]);
    threshold[c] = std::max(pb.Tolerance * initial[c], ResidualRoundOff * pb.Scale[c]);
  }
  for (int round = 0;; ++round)
  {
    bool active[W] = {};
    result.RelativeResidual = 0.0;
    bool any = false;
    for (int c = 0; c < nc; ++c)
    {
      const double norm = std::sqrt(norms[c]);
      if (initial[c] > 0.0)
      {
        result.RelativeResidual = std::max(result.RelativeResidual, norm / initial[c]);
      }
      active[c] = norm > threshold[c];
      any = any || active[c];
    }
    // A round reduces the residual by up to 1e-5 (what single precision
    // resolves); at most 8 rounds, fewer when the iterations are spent.
    if (!any || round == 8 || result.Iterations >= pb.MaximumIterations)
    {
      result.Converged = !any;
      return result;
    }
    // Aim a little below the threshold (float round-off separates the
    // recursive residual from the true one, and another round costs more),
    // but ask one round for no more than single precision can resolve.
    double target[W] = {};
    for (int c = 0; c < nc; ++c)
    {
      target[c] = std::max(0.7 * threshold[c], 1e-5 * std::sqrt(norms[c]));
    }
    result.Iterations +=
      SolveCorrection<W>(A, r, dx, target, active, pb.MaximumIterations - result.Iterations, threads);
    ParallelForStatic(n, threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        if (A.Free[i])
        {
          const std::int64_t v = order[i];
          for (int c = 0; c < nc; ++c)
          {
            x[v * nc + c] += dx[i * W + c];
          }
        }
      }
    });
    norms = residual();
  }
}

} // namespace

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
    Order = OrderOf(pb, Computed);
    RenumberEntries(pb, Order, [](Index) { return true; }, [&](std::int64_t k) { return pb.Weights[k]; }, Offsets,
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

  SquaredSolver(const ShiftedLaplacianProblem& pb, const double* b, double* x)
    : System(pb, b, x)
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
    const std::vector<double> sums = Total(ParallelSum(N, 3 * NC, Threads, [&](std::int64_t s, std::int64_t e, double* acc) {
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
          const Complex rz = Times(r, Times(Inverse[i], r));
          acc[2 * c] += f ? rz.real() : 0.0;
          acc[2 * c + 1] += f ? rz.imag() : 0.0;
          acc[2 * NC + c] += f ? std::norm(r) : 0.0;
        }
      }
    }));
    ++Result.Iterations;
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
          const Complex p = Times(Inverse[i], Complex(R[re], R[im])) + Times(beta[c], Complex(P[re], P[im]));
          P[re] = p.real();
          P[im] = p.imag();
        }
      }
    });
  }

  SquaredSystem System;
  const ShiftedLaplacianProblem& Pb;
  const double* B;
  double* X;
  double* Xout;
  const std::int64_t N;
  const int Threads;
  const double T, A;
  const std::size_t Size;
  LargeVector<double> R, P, KP;
  LargeVector<Complex> Inverse;
  ConjugateGradientResult Result;
  std::vector<double> Norms;
  double Initial[NC] = {}, Threshold[NC] = {}, StartNorm[NC] = {};
  Complex Rho[NC];
  bool Stalled = false;
};

/// The rows the multigrid solves leave alone: fixed, or (as SolveShifted)
/// without a positive finite diagonal D_ii + t K_ii (and, for the squared
/// systems, a positive D_ii).
std::vector<std::uint8_t> HeldRows(const ShiftedLaplacianProblem& pb, bool squared)
{
  std::vector<std::uint8_t> held(static_cast<std::size_t>(pb.Rows));
  for (Index i = 0; i < pb.Rows; ++i)
  {
    const double d = (pb.Shift ? pb.Shift[i] : 0.0) + pb.Factor * pb.Diagonal[i];
    held[i] = (pb.Fixed && pb.Fixed[i]) || !(d > 0.0) || !std::isfinite(d) || (squared && !(pb.Shift[i] > 0.0));
  }
  if (pb.Split)
  {
    pb.Split->UpdateGhosts(held); // a ghost's diagonal is not all here
  }
  return held;
}

/// The CG of the multigrid paths: same contract and stopping rule as the
/// graph solvers, the rows in `held` kept.
ConjugateGradientProblem MultigridProblem(const ShiftedLaplacianProblem& pb, const std::vector<std::uint8_t>& held)
{
  ConjugateGradientProblem cg;
  cg.Rows = pb.Rows;
  cg.Columns = pb.Columns;
  cg.Fixed = held.data();
  cg.Scale = pb.Scale;
  cg.Tolerance = pb.Tolerance;
  cg.MaximumIterations = pb.MaximumIterations;
  cg.NumberOfThreads = pb.NumberOfThreads;
  cg.Split = pb.Split;
  return cg;
}

/// y = D x + t K x over all rows.
void ShiftedProduct(const ShiftedLaplacianProblem& pb, double t, const double* x, double* y)
{
  const int nc = pb.Columns;
  ApplyGraphStiffness(pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, x, y, nc, pb.NumberOfThreads);
  ParallelFor(pb.Rows, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t k = s * nc; k < e * nc; ++k)
    {
      y[k] = (pb.Shift ? pb.Shift[k / nc] : 0.0) * x[k] + t * y[k];
    }
  });
}

ConjugateGradientResult SolveShiftedMultigrid(const ShiftedLaplacianProblem& pb, const double* b, double* x)
{
  const std::vector<std::uint8_t> held = HeldRows(pb, false);
  const AlgebraicMultigrid amg(
    pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, pb.Shift, pb.Factor, held.data(), pb.Split);
  ConjugateGradientProblem cg = MultigridProblem(pb, held);
  cg.Apply = [&](const double* in, double* out) { ShiftedProduct(pb, pb.Factor, in, out); };
  cg.Preconditioner = [&](const double* r, double* z) { amg.Apply(r, z, pb.Columns); };
  return SolveConjugateGradient(cg, b, x);
}

ConjugateGradientResult SolveSquaredMultigrid(const ShiftedLaplacianProblem& pb, const double* b, double* x)
{
  const std::vector<std::uint8_t> held = HeldRows(pb, true);
  const double a = std::sqrt(pb.Factor);
  const AlgebraicMultigrid amg(
    pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, pb.Shift, a, held.data(), pb.Split);
  const int nc = pb.Columns;
  const std::int64_t size = static_cast<std::int64_t>(pb.Rows) * nc;
  LargeVector<double> kx(size), tmp(size);
  ConjugateGradientProblem cg = MultigridProblem(pb, held);
  // Two orders of magnitude below the asked reduction, as the complex solver
  // asks of its own residual: at the bare tolerance the residual bound held
  // but points of tiny area (small D, so small residuals) stayed off by as
  // much as the noise (1e-2 of the diagonal on the noisy 1.2M-triangle
  // bunny, where the complex solver's are 8e-6 off).
  cg.Tolerance = 0.01 * pb.Tolerance;
  // y = D x + t K N K x, N = D^-1 on the free rows and 0 on the others.
  cg.Apply = [&](const double* in, double* out) {
    ApplyGraphStiffness(pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, in, kx.data(), nc, pb.NumberOfThreads);
    ParallelFor(size, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = s; k < e; ++k)
      {
        kx[k] = held[k / nc] ? 0.0 : kx[k] / pb.Shift[k / nc];
      }
    });
    if (pb.Split)
    {
      pb.Split->UpdateGhosts(kx.data(), nc); // the ghosts' rows of K x are not all here
    }
    ApplyGraphStiffness(pb.Rows, pb.Offsets, pb.Neighbors, pb.Weights, pb.Diagonal, kx.data(), out, nc, pb.NumberOfThreads);
    ParallelFor(size, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = s; k < e; ++k)
      {
        out[k] = pb.Shift[k / nc] * in[k] + pb.Factor * out[k];
      }
    });
  };
  // z = B D B r.
  cg.Preconditioner = [&](const double* r, double* z) {
    amg.Apply(r, tmp.data(), nc);
    ParallelFor(size, pb.NumberOfThreads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t k = s; k < e; ++k)
      {
        tmp[k] *= held[k / nc] ? 0.0 : pb.Shift[k / nc];
      }
    });
    amg.Apply(tmp.data(), z, nc);
  };
  return SolveConjugateGradient(cg, b, x);
}

} // namespace

bool UsesMultigrid(const ShiftedLaplacianProblem& pb)
{
  return pb.Preconditioner == Preconditioning::Multigrid;
}

ConjugateGradientResult SolveSquaredLaplacian(const ShiftedLaplacianProblem& pb, const double* b, double* x)
{
  const int nc = pb.Columns;
  if (nc < 1 || nc > 4 || static_cast<int>(pb.Scale.size()) != nc || !(pb.Factor >= 0.0) ||
    (pb.Rows > 0 && (!pb.Offsets || !pb.Neighbors || !pb.Weights || !pb.Diagonal || !pb.Shift)))
  {
    throw std::invalid_argument("SolveSquaredLaplacian: inconsistent problem");
  }
  if (pb.Rows <= 0 && !pb.Split)
  {
    ConjugateGradientResult none;
    none.Converged = true;
    return none;
  }
  if (UsesMultigrid(pb))
  {
    return SolveSquaredMultigrid(pb, b, x);
  }
  return WithCount<4>(nc, [&](auto k) { return SquaredSolver<decltype(k)::value>(pb, b, x).Run(); });
}

ConjugateGradientResult SolveShiftedLaplacian(
  const ShiftedLaplacianProblem& pb, const double* b, double* x)
{
  const int nc = pb.Columns;
  if (nc < 1 || nc > 8 || static_cast<int>(pb.Scale.size()) != nc ||
    (pb.Rows > 0 && (!pb.Offsets || !pb.Neighbors || !pb.Weights || !pb.Diagonal)))
  {
    throw std::invalid_argument("SolveShiftedLaplacian: inconsistent problem");
  }
  if (pb.Split && !UsesMultigrid(pb))
  {
    throw std::invalid_argument("SolveShiftedLaplacian: a distributed solve needs the multigrid preconditioner");
  }
  if (pb.Rows <= 0 && !pb.Split)
  {
    ConjugateGradientResult none;
    none.Converged = true;
    return none;
  }
  if (UsesMultigrid(pb))
  {
    return SolveShiftedMultigrid(pb, b, x);
  }
  if (nc > 4)
  {
    return SolveShifted<8>(pb, b, x); // 5 to 7 columns padded to 8
  }
  return WithCount<4>(nc, [&](auto k) { return SolveShifted<decltype(k)::value>(pb, b, x); });
}

} // namespace beltrami
