// Beltrami core, internal to the graph solvers: the renumbering of a
// system's rows that the order-1 (GraphSolvers.cxx) and order-2
// (SquaredSolver.cxx) Jacobi solvers share, and the order-2 solver's entry.
#pragma once

#include "Solvers/GraphSolvers.h"
#include "Solvers/SparseGraph.h"
#include "Support/LargeBuffer.h"
#include "Support/Parallel.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace beltrami
{
namespace detail
{

/// The locality order of pb's rows: pb.Order, or computed into `computed`.
inline const Index* OrderOf(const ShiftedLaplacianProblem& pb, std::vector<Index>& computed)
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
/// each of the caller's rows.  (Containers of the LargeVector kind; those of
/// UninitializedAllocator are first touched by the threads that fill them.)
template <typename Offsets, typename Neighbors, typename Values, typename Keep, typename ValueOf>
std::vector<Index> RenumberEntries(const ShiftedLaplacianProblem& pb, const Index* order, Keep&& keep,
  ValueOf&& value, Offsets& offsets, Neighbors& neighbors, Values& values)
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

/// z = M r, M ~ (D + i sqrt(t) K)^-1 symmetric (M^T = M, unconjugated), for
/// complex vectors stored as `columns` real values per row: the real parts
/// of a row's values, then their imaginary parts (a V-cycle).
using ComplexCycle = std::function<void(const double* r, double* z, int columns)>;

/// SolveSquaredLaplacian by COCG on D + i sqrt(t) K (checked problem, at
/// least one row or a split), preconditioned by Jacobi, or by `cycle` where
/// given; the cycle gets the rows in pb's Order (which must then be given).
ConjugateGradientResult SolveSquaredComplex(
  const ShiftedLaplacianProblem& pb, const double* b, double* x, const ComplexCycle& cycle = {});

} // namespace detail
} // namespace beltrami
