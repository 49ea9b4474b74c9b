#include "SparseFactorization.h"

#include "LargeBuffer.h"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

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
  Eigen::CholmodSupernodalLLT<Matrix> Cholesky;
  mutable Eigen::UmfPackLU<Matrix> LU;

  Internals()
  {
    cholmod_common& common = Cholesky.cholmod();
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;
    LU.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_AMD;
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

bool SparseFactorization::Compute(const Matrix& a, bool symmetric)
{
  SerialOpenMPRegions serial;
  Internals& in = *Internal;
  in.Symmetric = symmetric;
  if (symmetric)
  {
    in.Cholesky.compute(a);
    if (in.Cholesky.info() == Eigen::Success)
    {
      return true;
    }
    in.Symmetric = false; // not positive definite after all: LU
  }
  in.LU.compute(a);
  return in.LU.info() == Eigen::Success;
}

Eigen::MatrixXd SparseFactorization::Solve(const Eigen::MatrixXd& b) const
{
  SerialOpenMPRegions serial;
  return Internal->Symmetric ? Eigen::MatrixXd(Internal->Cholesky.solve(b))
                             : Eigen::MatrixXd(Internal->LU.solve(b));
}

} // namespace beltrami
