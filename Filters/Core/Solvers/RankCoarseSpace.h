// Beltrami core: the coarse level that joins the processes' V-cycles of a
// distributed solve on the surface's hierarchy.
//
// Distributed, each process cycles on the block of its own rows with the
// hierarchy of its own vertices (no communication in the cycle: block
// Jacobi over the processes).  Alone, that loses what couples the blocks:
// on the bunny split over 2-4 processes an order-1 step of 4000 h^2 took
// 104-138 iterations instead of the serial 13.  The coarse space here is
// the union of a coarse level of each process's hierarchy, P
// block-diagonal over the processes (each process's rows prolonged from
// its own level); its Galerkin operator P^T A P, the blocks on the diagonal
// from each process's hierarchy and those between processes from the
// couplings of the rows on their borders, is gathered on every process (a
// few thousand rows) and factorized there.  With Q = P (P^T A P)^-1 P^T the
// preconditioner is Q + (I - Q A) B_own (I - A Q) (GraphSolvers.cxx: the
// balanced two-level method, symmetric and positive definite), which took
// 31-34 iterations for that step, where the sum Q + B_own took 46-49.
// The processes join their coarsest levels for the complex systems, and
// for the real ones the finest levels that together stay within 12,000
// rows (JoiningLevel: up to half the iterations again, for a
// factorization of 0.05 s).
// Every call is collective.
#pragma once

#include "Solvers/SurfaceMultigrid.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace beltrami
{

struct ShiftedLaplacianProblem;

class RankCoarseSpace
{
public:
  /// The coarse space of pb (pb.Split given) for A = D + s K, s = `factor`,
  /// or D + i s K where `complex`; `hierarchy` and `mg` (null on a process
  /// without rows) this process's, `held` the rows the solve leaves alone
  /// (the ghosts' flags their owners').
  RankCoarseSpace(const ShiftedLaplacianProblem& pb, const SurfaceHierarchy* hierarchy,
    const SurfaceMultigrid* mg, const std::vector<std::uint8_t>& held, double factor, bool complex);
  ~RankCoarseSpace();
  RankCoarseSpace(const RankCoarseSpace&) = delete;
  RankCoarseSpace& operator=(const RankCoarseSpace&) = delete;

  /// z += P (P^T A P)^-1 P^T r, r and z in the hierarchy's order, `columns`
  /// values a row (complex: the real parts, then the imaginary ones); adds
  /// nothing where the coarse operator could not be factorized (the same on
  /// every process).
  void Add(const double* r, double* z, int columns) const;

private:
  struct State;
  std::unique_ptr<State> S;
};

} // namespace beltrami
