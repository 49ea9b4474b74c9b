#include "SparseFactorization.h"

#include "LargeBuffer.h"

#include <cholmod.h>
#include <umfpack.h>
#include <SuiteSparse_config.h>
#include <malloc.h>
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>

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

} // namespace

struct SparseFactorization::Internals
{
  bool Symmetric = true;
  int Size = 0;
  const Matrix* A = nullptr; // the factorized matrix (the caller keeps it)
  std::vector<int> Order;    // the elimination order given to Compute, if any
  // CHOLMOD (supernodal Cholesky).
  mutable cholmod_common Common;
  cholmod_factor* Cholesky = nullptr;
  // UMFPACK (LU).
  double Control[UMFPACK_CONTROL];
  mutable double Info[UMFPACK_INFO];
  void* LU = nullptr;

  Internals()
  {
    cholmod_start(&Common);
    Common.print = 0; // failures are reported by Compute's result
    Common.supernodal = CHOLMOD_SUPERNODAL;
    Common.final_asis = 1;
    Common.nmethods = 1;
    // Coarser supernodes than CHOLMOD's defaults (4/16/48 columns, 0.8/0.1/
    // 0.05 zeros): every supernode costs a few OpenMP regions and BLAS calls
    // whatever its size, which dominated the flops on these systems (179k
    // vertices: DCP 0.46 -> 0.30 s, natural 1.05 -> 0.77 s).
    Common.nrelax[0] = 16;
    Common.nrelax[1] = 64;
    Common.nrelax[2] = 128;
    Common.zrelax[0] = 0.8;
    Common.zrelax[1] = 0.3;
    Common.zrelax[2] = 0.1;
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
  }

  bool FactorizeCholesky()
  {
    cholmod_sparse view{};
    view.nrow = view.ncol = static_cast<std::size_t>(Size);
    view.nzmax = static_cast<std::size_t>(A->nonZeros());
    view.p = const_cast<int*>(A->outerIndexPtr());
    view.i = const_cast<int*>(A->innerIndexPtr());
    view.x = const_cast<double*>(A->valuePtr());
    view.stype = -1; // the lower triangle
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
    Common.method[0].ordering = Order.empty() ? CHOLMOD_AMD : CHOLMOD_GIVEN;
    Cholesky = cholmod_analyze_p(&view, Order.empty() ? nullptr : Order.data(), nullptr, 0, &Common);
    return Cholesky && cholmod_factorize(&view, Cholesky, &Common) &&
      Common.status == CHOLMOD_OK && Cholesky->minor == Cholesky->n;
  }

  bool FactorizeLU()
  {
    void* symbolic = nullptr;
    // AMD ordering whatever Order says: UMFPACK's LU took as long with a
    // nested dissection order (179k-vertex DAP: half the flops, 0.69 s vs
    // 0.62 s), and far longer when it then chose its unsymmetric strategy.
    int status = umfpack_di_symbolic(
      Size, Size, A->outerIndexPtr(), A->innerIndexPtr(), A->valuePtr(), &symbolic, Control, Info);
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

bool SparseFactorization::Compute(const Matrix& a, bool symmetric, const std::vector<int>& order)
{
  SerialOpenMPRegions serial;
  Internals& in = *Internal;
  in.Clear();
  in.Size = static_cast<int>(a.rows());
  in.A = &a;
  in.Order = order;
  in.Symmetric = symmetric && in.FactorizeCholesky();
  if (!in.Symmetric)
  {
    in.Clear(); // not symmetric, or not positive definite after all: LU
    if (!in.FactorizeLU())
    {
      return false;
    }
  }
  // Numerically singular (a pivot at rounding level: e.g. a part with no
  // fixed unknown) is singular: its solution would be rounding noise.  The
  // estimates are the pivots' ratio (squared for the Cholesky): about 1e-15
  // for a singular Laplacian, 1e-5 and more on the meshes of the tests.
  const double rcond = in.Symmetric ? cholmod_rcond(in.Cholesky, &in.Common) : in.Info[UMFPACK_RCOND];
  return rcond > 1e-13;
}

Eigen::MatrixXd SparseFactorization::Solve(const Eigen::MatrixXd& b) const
{
  SerialOpenMPRegions serial;
  const Internals& in = *Internal;
  if (in.Symmetric)
  {
    cholmod_dense view{};
    view.nrow = static_cast<std::size_t>(b.rows());
    view.ncol = static_cast<std::size_t>(b.cols());
    view.nzmax = view.d = view.nrow;
    view.nzmax *= view.ncol;
    view.x = const_cast<double*>(b.data());
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* solution = cholmod_solve(CHOLMOD_A, in.Cholesky, &view, &in.Common);
    Eigen::MatrixXd x = Eigen::Map<const Eigen::MatrixXd>(
      static_cast<const double*>(solution->x), b.rows(), b.cols());
    cholmod_free_dense(&solution, &in.Common);
    return x;
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
