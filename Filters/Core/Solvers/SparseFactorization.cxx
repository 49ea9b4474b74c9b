#include "Solvers/SparseFactorization.h"

#include "Support/LargeBuffer.h"
#include "Solvers/SupernodalLU.h"

#include <cholmod.h>
#include <umfpack.h>
#include <SuiteSparse_config.h>
#include <malloc.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <numeric>
#include <optional>
#include <vector>

// BLAS and LAPACK (OpenBLAS's where installed), Fortran calling
// convention with the hidden lengths of the character arguments.
extern "C"
{
  void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uploLength);
  void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
    const int* lda, const double* beta, double* c, const int* ldc, std::size_t uploLength, std::size_t transLength);
  void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda, double* b,
    const int* ldb, int* info, std::size_t uploLength);
}

namespace beltrami
{

namespace
{

// SuiteSparse's allocation hooks: blocks of 1 MiB and more from LargeBuffer.
constexpr std::size_t LargeAllocation = std::size_t(1) << 20;

void* Allocate(std::size_t bytes)
{
  if (bytes < LargeAllocation)
  {
    return std::malloc(bytes);
  }
  try
  {
    return AllocateLargeBlock(bytes);
  }
  catch (const std::bad_alloc&)
  {
    return nullptr; // SuiteSparse reports out of memory
  }
}

void* AllocateZeroed(std::size_t count, std::size_t size)
{
  if (size != 0 && count > SIZE_MAX / size)
  {
    return nullptr;
  }
  if (count * size < LargeAllocation)
  {
    return std::calloc(count, size);
  }
  void* block = Allocate(count * size);
  if (block)
  {
    std::memset(block, 0, count * size); // a cached block is not zero
  }
  return block;
}

void* Reallocate(void* block, std::size_t bytes)
{
  if (!block)
  {
    return Allocate(bytes);
  }
  const std::size_t large = LargeBlockSize(block);
  if (large == 0 && bytes < LargeAllocation)
  {
    return std::realloc(block, bytes);
  }
  if (large >= bytes)
  {
    return block; // already big enough
  }
  void* moved = Allocate(bytes);
  if (moved)
  {
    std::memcpy(moved, block, std::min(bytes, large ? large : malloc_usable_size(block)));
    FreeLargeBlock(block); // std::free for a block of malloc
  }
  return moved; // on failure the old block stays valid, as with realloc
}

void InstallAllocator()
{
  static std::once_flag once;
  std::call_once(once, [] {
    // Only over the library's defaults (a host that set its own keeps them).
    if (SuiteSparse_config.malloc_func == &std::malloc && SuiteSparse_config.free_func == &std::free)
    {
      SuiteSparse_config.malloc_func = &Allocate;
      SuiteSparse_config.calloc_func = &AllocateZeroed;
      SuiteSparse_config.realloc_func = &Reallocate;
      SuiteSparse_config.free_func = &FreeLargeBlock;
    }
  });
}

/// Runs the OpenMP regions opened by this thread serially while it lives.
class SerialOpenMPRegions
{
public:
  SerialOpenMPRegions()
    : Saved(omp_get_max_active_levels())
  {
    omp_set_max_active_levels(0);
  }
  ~SerialOpenMPRegions() { omp_set_max_active_levels(Saved); }

private:
  int Saved;
};

/// A dense matrix as a CHOLMOD view (no copy).
cholmod_dense DenseView(const Eigen::MatrixXd& m)
{
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(m.rows());
  view.ncol = static_cast<std::size_t>(m.cols());
  view.d = view.nrow;
  view.nzmax = view.nrow * view.ncol;
  view.x = const_cast<double*>(m.data());
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  return view;
}

/// cholmod_solve(system, factor, b) as an Eigen matrix.
Eigen::MatrixXd CholmodSolve(int system, cholmod_factor* factor, const Eigen::MatrixXd& b, cholmod_common& common)
{
  cholmod_dense view = DenseView(b);
  cholmod_dense* x = cholmod_solve(system, factor, &view, &common);
  if (!x)
  {
    throw std::bad_alloc(); // CHOLMOD's only failure here: out of memory
  }
  Eigen::MatrixXd result = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), b.rows(), b.cols());
  cholmod_free_dense(&x, &common);
  return result;
}

} // namespace

struct SparseFactorization::Internals
{
  bool Symmetric = true;
  int Size = 0;
  std::optional<MatrixView> A; // the factorized matrix (the caller keeps it)
  // CHOLMOD (supernodal Cholesky).
  mutable cholmod_common Common;
  cholmod_factor* Cholesky = nullptr;
  // UMFPACK (LU).
  double Control[UMFPACK_CONTROL];
  mutable double Info[UMFPACK_INFO];
  void* LU = nullptr;
  // SupernodalLU (when the caller gives an order): the Cholesky factor in
  // place of CHOLMOD's, or the LU in place of UMFPACK's (which stay the
  // fallbacks).
  std::unique_ptr<SupernodalLU> Supernodal;
  int Threads = 0;
  // Twin pairs (see Compute): A = I_2 (x) L + a coupling of the last m
  // pairs in Cholesky's order. Cholesky then factors L only.
  std::vector<int> Order; // the caller's elimination order (for the LU)
  bool Twin = false;
  int Coupled = 0;         // m
  // The trailing m x m block of L's factor (lower), and the Cholesky factor
  // (lower) of the 2m x 2m coupled system; on LargeBuffer's pages (53 MB
  // for m = 1150).
  LargeVector<double> CornerData, ReducedData;
  Eigen::Map<Eigen::MatrixXd> Corner{ nullptr, 0, 0 };
  Eigen::Map<Eigen::MatrixXd> Reduced{ nullptr, 0, 0 };

  Internals()
  {
    cholmod_start(&Common);
    Common.print = 0; // failures are reported by Compute's result
    Common.supernodal = CHOLMOD_SUPERNODAL;
    Common.final_asis = 1;
    Common.nmethods = 1;
    // Coarser supernodes than CHOLMOD's defaults (4/16/48 columns, 0.8/0.1/
    // 0.05 zeros): every supernode costs a few OpenMP regions and BLAS calls
    // whatever its size, which dominated the flops on these systems.  179k
    // vertices, nested dissection, factorization in a fresh / warm process:
    // defaults 0.82 / 0.50 s (12M entries); 8/32/64 columns 0.36-0.59 /
    // 0.34 s (16M); 16/64/128 with 0.3/0.1 zeros 0.73-0.77 / 0.33 s (23M:
    // the fresh pages cost more than the fewer supernodes save).
    Common.nrelax[0] = 8;
    Common.nrelax[1] = 32;
    Common.nrelax[2] = 64;
    Common.zrelax[0] = 0.8;
    Common.zrelax[1] = 0.2;
    Common.zrelax[2] = 0.05;
    umfpack_di_defaults(Control);
    Control[UMFPACK_ORDERING] = UMFPACK_ORDERING_AMD;
    // UMFPACK's iterative refinement (2 steps by default, i.e. three solves
    // per column) aims at a componentwise backward error of machine epsilon
    // and barely moved the residual here (179k-vertex DAP: 1.6e-11 -> 1.2e-11
    // relative, 0.04 -> 0.13 s per column); Solve refines only when the
    // residual is actually large.
    Control[UMFPACK_IRSTEP] = 0;
  }
  ~Internals()
  {
    Clear();
    cholmod_finish(&Common);
  }
  void Clear()
  {
    if (Cholesky)
    {
      cholmod_free_factor(&Cholesky, &Common);
    }
    if (LU)
    {
      umfpack_di_free_numeric(&LU);
    }
    Supernodal.reset();
    Twin = false;
    Coupled = 0;
    Matrices(0);
  }
  void Matrices(int m)
  {
    CornerData.assign(static_cast<std::size_t>(m) * m, 0.0);
    ReducedData.assign(4 * static_cast<std::size_t>(m) * m, 0.0);
    new (&Corner) Eigen::Map<Eigen::MatrixXd>(CornerData.data(), m, m);
    new (&Reduced) Eigen::Map<Eigen::MatrixXd>(ReducedData.data(), 2 * m, 2 * m);
  }

  /// Supernodal Cholesky of the lower triangle of m, in `order` (kept as
  /// given when `exact`; CHOLMOD may otherwise postorder it) or AMD's.
  bool FactorizeCholesky(const MatrixView& m, std::vector<int> order, bool exact)
  {
    // With the caller's order: SupernodalLU's Cholesky factorization, its
    // subtrees on separate threads (179k vertices: 0.21 s where CHOLMOD's
    // analysis and factorization took 0.34 s).  CHOLMOD's when it fails.
    if (!order.empty())
    {
      Supernodal = std::make_unique<SupernodalLU>();
      if (Supernodal->Compute(m, order, Threads, true, exact))
      {
        return true;
      }
      Supernodal.reset();
    }
    cholmod_sparse view{};
    view.nrow = view.ncol = static_cast<std::size_t>(m.rows());
    view.nzmax = static_cast<std::size_t>(m.nonZeros());
    view.p = const_cast<int*>(m.outerIndexPtr());
    view.i = const_cast<int*>(m.innerIndexPtr());
    view.x = const_cast<double*>(m.valuePtr());
    view.stype = -1; // the lower triangle
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
    Common.method[0].ordering = order.empty() ? CHOLMOD_AMD : CHOLMOD_GIVEN;
    Common.postorder = !exact;
    Cholesky = cholmod_analyze_p(&view, order.empty() ? nullptr : order.data(), nullptr, 0, &Common);
    Common.postorder = 1;
    return Cholesky && cholmod_factorize(&view, Cholesky, &Common) &&
      Common.status == CHOLMOD_OK && Cholesky->minor == Cholesky->n;
  }

  /// The twin-pair factorization (see Compute); false when A does not have
  /// that form (or too many coupled pairs), leaving nothing factorized.
  bool FactorizeTwin(const std::vector<int>& order)
  {
    const MatrixView& a = *A;
    if (Size < 2 || Size % 2 != 0)
    {
      return false;
    }
    const int pairs = Size / 2;
    // L from the even rows and columns, checked against the odd ones; the
    // pairs with an entry between an even and an odd unknown are coupled.
    std::vector<std::uint8_t> coupled(static_cast<std::size_t>(pairs), 0);
    std::vector<int> outer(static_cast<std::size_t>(pairs) + 1, 0);
    LargeVector<int> inner;
    LargeVector<double> values;
    inner.reserve(static_cast<std::size_t>(a.nonZeros() / 2));
    values.reserve(inner.capacity());
    const int* p = a.outerIndexPtr();
    const int* rows = a.innerIndexPtr();
    const double* x = a.valuePtr();
    for (int k = 0; k < pairs; ++k)
    {
      for (int e = p[2 * k]; e < p[2 * k + 1]; ++e)
      {
        if (rows[e] % 2 == 0)
        {
          inner.push_back(rows[e] / 2);
          values.push_back(x[e]);
        }
        else
        {
          coupled[k] = coupled[rows[e] / 2] = 1;
        }
      }
      std::size_t twin = static_cast<std::size_t>(outer[k]);
      for (int e = p[2 * k + 1]; e < p[2 * k + 2]; ++e)
      {
        if (rows[e] % 2 == 0)
        {
          coupled[k] = coupled[rows[e] / 2] = 1;
        }
        else if (twin == inner.size() || inner[twin] != rows[e] / 2 || values[twin++] != x[e])
        {
          return false;
        }
      }
      if (twin != inner.size())
      {
        return false;
      }
      outer[k + 1] = static_cast<int>(inner.size());
    }
    Coupled = static_cast<int>(std::count(coupled.begin(), coupled.end(), 1));
    // The dense part costs about (8/3) m^3 flops (S = F22 F22^T and the
    // Cholesky of the 2m system), the sparse factorization of a surface's n
    // unknowns (nested dissection) some 25 n^1.5: the twin path pays while m
    // stays below a few sqrt(n), as a disk's boundary does (179k vertices,
    // m = 1150: 1.1e10 flops like the general path, in 0.42 s instead of
    // 0.75 s); a long thin strip (m ~ n) takes the general path.  At most
    // 6000 coupled pairs (a dense matrix of 1.2 GB).
    const int maximumCoupled = std::min(6000, std::max(256, static_cast<int>(4.0 * std::sqrt(double(pairs)))));
    if (Coupled > maximumCoupled)
    {
      return false;
    }
    const MatrixView scalar(pairs, pairs, outer.back(), outer.data(), inner.data(), values.data());
    // The pairs' order (the even unknowns' in `order`), coupled pairs last.
    std::vector<int> pairOrder;
    pairOrder.reserve(static_cast<std::size_t>(pairs));
    for (int u : order)
    {
      if (u % 2 == 0)
      {
        pairOrder.push_back(u / 2);
      }
    }
    if (static_cast<int>(pairOrder.size()) != pairs)
    {
      pairOrder.resize(static_cast<std::size_t>(pairs));
      std::iota(pairOrder.begin(), pairOrder.end(), 0);
    }
    std::stable_partition(pairOrder.begin(), pairOrder.end(), [&](int k) { return !coupled[k]; });
    if (!FactorizeCholesky(scalar, pairOrder, true) ||
      !(Supernodal ? std::equal(pairOrder.begin(), pairOrder.end(), Supernodal->Order().begin())
                   : Cholesky->is_super &&
            std::equal(pairOrder.begin(), pairOrder.end(), static_cast<const int*>(Cholesky->Perm))))
    {
      return false;
    }
    // The factor's trailing block: F = [F11 0; F21 F22] with F22 F22^T the
    // Schur complement S of the uncoupled unknowns.
    const int m = Coupled, first = pairs - m;
    Matrices(m);
    if (Supernodal)
    {
      Supernodal->TrailingBlock(Corner);
    }
    else
    {
      const int* super = static_cast<const int*>(Cholesky->super);
      const int* pi = static_cast<const int*>(Cholesky->pi);
      const int* px = static_cast<const int*>(Cholesky->px);
      const int* ls = static_cast<const int*>(Cholesky->s);
      const double* lx = static_cast<const double*>(Cholesky->x);
      for (std::size_t sn = 0; sn < Cholesky->nsuper; ++sn)
      {
        const int k1 = super[sn], k2 = super[sn + 1], height = pi[sn + 1] - pi[sn];
        for (int j = std::max(k1, first); j < k2; ++j)
        {
          for (int i = j - k1; i < height; ++i) // rows from the diagonal down
          {
            Corner(ls[pi[sn] + i] - first, j - first) = lx[px[sn] + static_cast<std::int64_t>(j - k1) * height + i];
          }
        }
      }
    }
    // The coupled unknowns' system [S + C_uu, C_uv; C_vu, S + C_vv], C the
    // even-odd entries of A (its lower triangle, for LAPACK's 'L').
    std::vector<int> slot(static_cast<std::size_t>(pairs), -1);
    for (int k = first; k < pairs; ++k)
    {
      slot[pairOrder[k]] = k - first;
    }
    if (m > 0)
    {
      int n2 = 2 * m;
      const double one = 1.0, zero = 0.0;
      dsyrk_("L", "N", &m, &m, &one, Corner.data(), &m, &zero, Reduced.data(), &n2, 1, 1); // F22 F22^T
      Reduced.bottomRightCorner(m, m).triangularView<Eigen::Lower>() =
        Reduced.topLeftCorner(m, m).triangularView<Eigen::Lower>();
      for (int c = 0; c < Size; ++c)
      {
        for (int e = p[c]; e < p[c + 1]; ++e)
        {
          if (rows[e] % 2 != c % 2)
          {
            Reduced((rows[e] % 2) * m + slot[rows[e] / 2], (c % 2) * m + slot[c / 2]) = x[e];
          }
        }
      }
      int info = 0;
      dpotrf_("L", &n2, Reduced.data(), &n2, &info, 1);
      if (info != 0)
      {
        return false;
      }
    }
    Twin = true;
    return true;
  }

  Eigen::MatrixXd SolveTwin(const Eigen::MatrixXd& b) const
  {
    const int pairs = Size / 2, m = Coupled;
    const Eigen::Index columns = b.cols();
    Eigen::MatrixXd y(pairs, 2 * columns); // the u and v parts of each column
    for (Eigen::Index c = 0; c < columns; ++c)
    {
      for (int k = 0; k < pairs; ++k)
      {
        y(k, 2 * c) = b(2 * k, c);
        y(k, 2 * c + 1) = b(2 * k + 1, c);
      }
    }
    // Forward with F; the coupled unknowns from the reduced system; back.
    if (Supernodal)
    {
      Supernodal->SolveLower(y);
    }
    else
    {
      y = CholmodSolve(CHOLMOD_L, Cholesky, CholmodSolve(CHOLMOD_P, Cholesky, y, Common), Common);
    }
    if (m > 0)
    {
      Eigen::MatrixXd g(2 * m, columns);
      for (Eigen::Index c = 0; c < columns; ++c)
      {
        g.col(c).head(m) = Corner.triangularView<Eigen::Lower>() * y.col(2 * c).tail(m);
        g.col(c).tail(m) = Corner.triangularView<Eigen::Lower>() * y.col(2 * c + 1).tail(m);
      }
      int info = 0, n2 = 2 * m, nrhs = static_cast<int>(columns);
      dpotrs_("L", &n2, &nrhs, Reduced.data(), &n2, g.data(), &n2, &info, 1);
      for (Eigen::Index c = 0; c < columns; ++c)
      {
        y.col(2 * c).tail(m) = Corner.transpose().triangularView<Eigen::Upper>() * g.col(c).head(m);
        y.col(2 * c + 1).tail(m) = Corner.transpose().triangularView<Eigen::Upper>() * g.col(c).tail(m);
      }
    }
    if (Supernodal)
    {
      Supernodal->SolveUpper(y);
    }
    else
    {
      y = CholmodSolve(CHOLMOD_Pt, Cholesky, CholmodSolve(CHOLMOD_Lt, Cholesky, y, Common), Common);
    }
    Eigen::MatrixXd result(Size, columns);
    for (Eigen::Index c = 0; c < columns; ++c)
    {
      for (int k = 0; k < pairs; ++k)
      {
        result(2 * k, c) = y(k, 2 * c);
        result(2 * k + 1, c) = y(k, 2 * c + 1);
      }
    }
    return result;
  }

  bool FactorizeLU(int threads)
  {
    // With the caller's order: the supernodal LU (179k-vertex DAP, analysis
    // included: 0.27-0.31 s and 166 MB on 2 threads, where UMFPACK took
    // 0.65-0.82 s and 172 MB);
    // UMFPACK when it fails (a pivot it cannot find inside a supernode).
    if (!Order.empty())
    {
      Supernodal = std::make_unique<SupernodalLU>();
      if (Supernodal->Compute(*A, Order, threads))
      {
        return true;
      }
      Supernodal.reset();
    }
    void* symbolic = nullptr;
    // The caller's order when there is one: UMFPACK's LU then does half the
    // flops of AMD's order and touches less memory (179k-vertex DAP: 4.1e9
    // vs 8.2e9 flops, peak 164 vs 214 MB; first run in a process 1.0-1.4 s
    // vs 1.45-1.9 s, later runs 0.94-1.0 s vs 1.02-1.1 s; 717k: 5.3 s vs
    // 8.3-11 s), the same time at 9k and 36k.  With an order given UMFPACK
    // must be told to keep it symmetric (its automatic choice of the
    // unsymmetric strategy took 12 s at 179k).  Its memory estimate is then
    // far too high (179k: 4.3 GB for 164 MB used); the initial block (2 GB,
    // beyond LargeBuffer's cache) is only touched where it is used.
    const bool ordered = !Order.empty();
    Control[UMFPACK_STRATEGY] = ordered ? UMFPACK_STRATEGY_SYMMETRIC : UMFPACK_STRATEGY_AUTO;
    int status = umfpack_di_qsymbolic(Size, Size, A->outerIndexPtr(), A->innerIndexPtr(), A->valuePtr(),
      ordered ? Order.data() : nullptr, &symbolic, Control, Info);
    if (status == UMFPACK_OK)
    {
      status = umfpack_di_numeric(
        A->outerIndexPtr(), A->innerIndexPtr(), A->valuePtr(), symbolic, &LU, Control, Info);
    }
    umfpack_di_free_symbolic(&symbolic);
    return status == UMFPACK_OK; // UMFPACK_WARNING_singular_matrix included
  }

  Eigen::MatrixXd SolveLU(const Eigen::MatrixXd& b) const
  {
    if (Supernodal)
    {
      Eigen::MatrixXd x = b;
      Supernodal->Solve(x);
      return x;
    }
    Eigen::MatrixXd x(b.rows(), b.cols());
    for (Eigen::Index c = 0; c < b.cols(); ++c)
    {
      umfpack_di_solve(UMFPACK_A, A->outerIndexPtr(), A->innerIndexPtr(), A->valuePtr(), x.col(c).data(),
        b.col(c).data(), LU, Control, Info);
    }
    return x;
  }
};

SparseFactorization::SparseFactorization()
{
  InstallAllocator();
  Internal = std::make_unique<Internals>();
}

SparseFactorization::~SparseFactorization()
{
  SerialOpenMPRegions serial;
  Internal.reset();
}

bool SparseFactorization::Compute(
  const Matrix& a, bool symmetric, const std::vector<int>& order, bool twinPairs, int numThreads, double leastPivotRatio)
{
  return Compute(MatrixView(a.rows(), a.cols(), a.nonZeros(), a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr()),
    symmetric, order, twinPairs, numThreads, leastPivotRatio);
}

bool SparseFactorization::Compute(
  const MatrixView& a, bool symmetric, const std::vector<int>& order, bool twinPairs, int numThreads,
  double leastPivotRatio)
{
  SerialOpenMPRegions serial;
  Internals& in = *Internal;
  in.Clear();
  in.Size = static_cast<int>(a.rows());
  in.A.emplace(a);
  in.Order = order;
  in.Threads = numThreads;
  in.Symmetric = false;
  if (symmetric && twinPairs)
  {
    in.Symmetric = in.FactorizeTwin(order);
    if (!in.Symmetric)
    {
      in.Clear();
    }
  }
  if (symmetric && !in.Symmetric)
  {
    in.Symmetric = in.FactorizeCholesky(a, order, false);
  }
  if (!in.Symmetric)
  {
    in.Clear(); // not symmetric, or not positive definite after all: LU
    if (!in.FactorizeLU(numThreads))
    {
      return false;
    }
  }
  // Numerically singular (a pivot at rounding level: e.g. a part with no
  // fixed unknown) is singular: its solution would be rounding noise.  The
  // estimates are the pivots' ratio (squared for the Cholesky): about 1e-15
  // for a singular Laplacian, 1e-5 and more on the meshes of the tests.
  double rcond = in.Supernodal ? in.Supernodal->PivotRatio()
    : in.Symmetric             ? cholmod_rcond(in.Cholesky, &in.Common)
                               : in.Info[UMFPACK_RCOND];
  if (in.Twin && in.Coupled > 0)
  {
    const auto d = in.Reduced.diagonal().cwiseAbs();
    rcond = std::min(rcond, std::pow(d.minCoeff() / d.maxCoeff(), 2));
  }
  return rcond > leastPivotRatio;
}

int SparseFactorization::CoupledPairs() const
{
  return Internal->Twin ? Internal->Coupled : -1;
}

Eigen::MatrixXd SparseFactorization::Solve(const Eigen::MatrixXd& b) const
{
  SerialOpenMPRegions serial;
  const Internals& in = *Internal;
  if (in.Twin)
  {
    return in.SolveTwin(b);
  }
  if (in.Symmetric)
  {
    if (in.Supernodal)
    {
      Eigen::MatrixXd x = b;
      in.Supernodal->Solve(x);
      return x;
    }
    return CholmodSolve(CHOLMOD_A, in.Cholesky, b, in.Common);
  }
  Eigen::MatrixXd x = in.SolveLU(b);
  // Iterative refinement only where the LU left a residual above 1e-10
  // relative (threshold pivoting keeps it near 1e-11 on these systems).
  const double target = 1e-10 * b.norm();
  for (int step = 0; step < 3; ++step)
  {
    const Eigen::MatrixXd residual = b - *in.A * x;
    if (!(residual.norm() > target))
    {
      break;
    }
    x += in.SolveLU(residual);
  }
  return x;
}

} // namespace beltrami

