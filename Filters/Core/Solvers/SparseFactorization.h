// Beltrami core: sparse direct factorizations.
//
// With an elimination order from the caller (the parameterization's nested
// dissection): our SupernodalLU, its Cholesky form for symmetric positive
// definite systems and its LU for the others; it runs independent subtrees
// on separate threads, faster than CHOLMOD and UMFPACK on the
// parameterization's systems (the guide's benchmarks page has the
// timings).  SuiteSparse otherwise, and
// when SupernodalLU fails: CHOLMOD's supernodal Cholesky, UMFPACK's LU (any
// pivot; also when the Cholesky finds the matrix not positive definite).
// SuiteSparse is set up for this project's machines:
// - ordering: the caller's (a nested dissection of the mesh) or AMD.
//   CHOLMOD's default tries METIS after AMD when the fill is high; on the
//   parameterization systems (10^5 vertices) METIS saves flops but costs more
//   time than it saves (at 179k vertices the ordering took about five times
//   longer).
// - memory: SuiteSparse's allocations of 1 MiB and more go through
//   LargeBuffer (2 MiB pages, cached): the factor of a 179k-vertex system is
//   ~100 MB, and faulting it in 4 KiB pages cost as much as computing it.
// - supernodes: relaxed amalgamation coarser than CHOLMOD's default (fewer,
//   larger supernodes: per-supernode overhead dominated the flops).
// - dense algebra: BLAS/LAPACK (dsyrk, dpotrf, dpotrs) for the coupled
//   block of twin pairs (below).
// - threads: CHOLMOD opens OpenMP regions of 4 threads (a compile-time
//   constant) around every large supernode; on 2 cores the wake-ups cost
//   more than they gain, so the calling thread runs them serially (OpenMP's
//   max-active-levels, a per-thread setting, restored afterwards). The
//   dense kernels keep the BLAS library's own threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace beltrami
{

class SparseFactorization
{
public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  /// A compressed-column matrix in the caller's arrays (e.g. LargeVectors).
  using MatrixView = Eigen::Map<const Matrix>;

  SparseFactorization();
  ~SparseFactorization();
  SparseFactorization(const SparseFactorization&) = delete;
  SparseFactorization& operator=(const SparseFactorization&) = delete;

  /// Factorizes `a` (square, compressed, sorted row indices per column),
  /// which must stay alive and unchanged while the factorization is used
  /// (the LU refers to it).  With `symmetric`, a Cholesky factorization of
  /// the lower triangle is tried first (falling back to LU when `a` is not
  /// positive definite).  Returns false when `a` is singular, numerically too
  /// (the pivots' ratio estimate below `leastPivotRatio`: rounding level),
  /// or memory ran out.
  ///
  /// `order`, if not empty, is the elimination order (order[k] = the unknown
  /// eliminated k-th, e.g. NestedDissectionOrder's) of the Cholesky or the
  /// LU (SupernodalLU, or UMFPACK's symmetric pivoting strategy); AMD's
  /// otherwise.  `numThreads` (0: DefaultThreadCount()) is SupernodalLU's.
  ///
  /// `twinPairs`: the unknowns come in pairs (2k, 2k+1) and A = I_2 (x) L
  /// except for entries between the pairs' even and odd unknowns on a few
  /// pairs (the natural conformal map: u and v share the cotangent matrix
  /// and are coupled on the boundary only).  Then only L is factorized, with
  /// the coupled pairs last, and the coupled unknowns are solved from the
  /// dense system of its trailing block (when the coupled pairs are at most
  /// about 4 sqrt(pairs), as on a disk's boundary; other matrices take the
  /// general path).
  bool Compute(const MatrixView& a, bool symmetric, const std::vector<int>& order = {}, bool twinPairs = false,
    int numThreads = 0, double leastPivotRatio = 1e-13);
  /// The same for a matrix in Eigen's own storage.
  bool Compute(const Matrix& a, bool symmetric, const std::vector<int>& order = {}, bool twinPairs = false,
    int numThreads = 0, double leastPivotRatio = 1e-13);
  /// With the twin-pair path of Compute: the number of coupled pairs; -1
  /// when Compute took another path.
  int CoupledPairs() const;
  /// Solves A X = B for every column of B.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b) const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace beltrami
