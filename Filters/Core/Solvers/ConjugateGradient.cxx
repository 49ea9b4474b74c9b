#include "Solvers/ConjugateGradient.h"

#include "Solvers/Partition.h"
#include "Support/LargeBuffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace beltrami
{

namespace
{
/// The solver for NC columns (a compile-time count: the per-row loops unroll
/// and vectorize).
template <int NC>
ConjugateGradientResult Solve(const ConjugateGradientProblem& pb, const double* b, double* x)
{
  constexpr int nc = NC;
  const std::int64_t n = pb.Rows;
  const std::size_t size = static_cast<std::size_t>(n) * nc;
  const int threads = pb.NumberOfThreads;
  const Partition* split = pb.Split;
  const auto isFree = [&](std::int64_t i) {
    return (!pb.Fixed || !pb.Fixed[i]) && (!split || split->IsOwned(static_cast<Index>(i)));
  };
  // Over the processes (a distributed solve): sums, and the ghost rows of
  // an operand or of the result.
  const auto total = [&](std::vector<double> sums) {
    if (split)
    {
      split->Sum(sums.data(), static_cast<int>(sums.size()));
    }
    for (std::size_t first = 0; pb.CoupledColumns && first < sums.size(); first += nc)
    {
      // Each group of nc (r.z, r.r or p.q per column): their sum in every column.
      double all = 0.0;
      for (int c = 0; c < nc; ++c)
      {
        all += sums[first + c];
      }
      std::fill(sums.begin() + first, sums.begin() + first + nc, all);
    }
    return sums;
  };
  const auto refresh = [&](double* v) {
    if (split)
    {
      split->UpdateGhosts(v, nc);
    }
  };
  const auto invDiag = [&](std::int64_t i) {
    const double d = pb.Diagonal ? pb.Diagonal[i] : 1.0;
    return d > 0.0 ? 1.0 / d : 1.0;
  };

  LargeVector<double> r(size), z(size), p(size), q(size);
  // z = M^-1 r (0 on the fixed rows) and per column r.z, then r.r; the
  // Jacobi preconditioner in the same pass as the sums.
  const auto precondition = [&]() {
    if (pb.Preconditioner)
    {
      pb.Preconditioner(r.data(), z.data());
    }
    return total(ParallelSum(n, 2 * nc, threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        const bool f = isFree(i);
        const double id = invDiag(i);
        for (int c = 0; c < nc; ++c)
        {
          const std::int64_t k = i * nc + c;
          z[k] = !f ? 0.0 : pb.Preconditioner ? z[k] : id * r[k];
          acc[c] += r[k] * z[k];
          acc[nc + c] += r[k] * r[k];
        }
      }
    }));
  };
  // r = b - A x (fixed rows: 0), p = z
  refresh(x);
  pb.Apply(x, q.data());
  ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t k = s * nc; k < e * nc; ++k)
    {
      r[k] = isFree(k / nc) ? b[k] - q[k] : 0.0;
    }
  });
  std::vector<double> rz = precondition();
  std::copy(z.begin(), z.end(), p.begin());

  ConjugateGradientResult result;
  std::vector<double> rzOld(rz.begin(), rz.begin() + nc);
  bool active[NC];
  std::vector<double> initial(nc), threshold(nc);
  for (int c = 0; c < nc; ++c)
  {
    initial[c] = std::sqrt(std::max(0.0, rz[nc + c]));
    threshold[c] = std::max(pb.Tolerance * initial[c], ResidualRoundOff * pb.Scale[c]);
  }
  const auto converged = [&](const std::vector<double>& sums) {
    bool all = true;
    result.RelativeResidual = 0.0;
    for (int c = 0; c < nc; ++c)
    {
      const double norm = std::sqrt(std::max(0.0, sums[nc + c]));
      if (initial[c] > 0.0)
      {
        result.RelativeResidual = std::max(result.RelativeResidual, norm / initial[c]);
      }
      active[c] = norm > threshold[c] && rzOld[c] > 0.0;
      all = all && !active[c];
    }
    return all;
  };
  if (converged(rz))
  {
    result.Converged = true;
    return result;
  }
  // Fixed rows of x must not leak into A p: p is zero there by construction.
  for (int it = 1; it <= pb.MaximumIterations; ++it)
  {
    refresh(p.data());
    pb.Apply(p.data(), q.data());
    const std::vector<double> pq = total(ParallelSum(n, nc, threads, [&](std::int64_t s, std::int64_t e, double* acc) {
      for (std::int64_t i = s; i < e; ++i)
      {
        if (isFree(i))
        {
          for (int c = 0; c < nc; ++c)
          {
            acc[c] += p[i * nc + c] * q[i * nc + c];
          }
        }
      }
    }));
    double alpha[8];
    for (int c = 0; c < nc; ++c)
    {
      alpha[c] = active[c] && pq[c] > 0.0 ? rzOld[c] / pq[c] : 0.0;
    }
    ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < nc && isFree(i); ++c)
        {
          const std::int64_t k = i * nc + c;
          x[k] += alpha[c] * p[k];
          r[k] -= alpha[c] * q[k];
        }
      }
    });
    const std::vector<double> sums = precondition();
    result.Iterations = it;
    double beta[8];
    for (int c = 0; c < nc; ++c)
    {
      beta[c] = active[c] && rzOld[c] > 0.0 ? sums[c] / rzOld[c] : 0.0;
      if (active[c])
      {
        rzOld[c] = sums[c];
      }
    }
    if (converged(sums))
    {
      result.Converged = true;
      refresh(x);
      return result;
    }
    ParallelFor(n, threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < nc; ++c)
        {
          const std::int64_t k = i * nc + c;
          p[k] = active[c] ? z[k] + beta[c] * p[k] : 0.0;
        }
      }
    });
  }
  refresh(x);
  return result;
}

} // namespace

ConjugateGradientResult SolveConjugateGradient(
  const ConjugateGradientProblem& pb, const double* b, double* x)
{
  const int nc = pb.Columns;
  if (nc < 1 || nc > 8 || static_cast<int>(pb.Scale.size()) != nc || !pb.Apply ||
    !(pb.Diagonal || pb.Preconditioner || pb.Rows == 0))
  {
    throw std::invalid_argument("SolveConjugateGradient: inconsistent problem");
  }
  return WithCount<8>(nc, [&](auto k) { return Solve<decltype(k)::value>(pb, b, x); });
}

} // namespace beltrami
