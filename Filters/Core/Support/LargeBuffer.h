// Beltrami core: an allocator for large per-vertex / per-pixel arrays.
//
// Arrays of several megabytes are placed on 2 MiB-aligned memory that the
// kernel may back with transparent huge pages (Linux, madvise mode), so that
// first touching them costs one page fault per 2 MiB instead of one per
// 4 KiB.  Where page faults are slow a 4 KiB fault can cost 10 us: a 512 x 512
// image flow spent more time faulting in its buffers than computing.
// Small arrays and other systems use the ordinary allocator.
//
// Freed large blocks are kept in a bounded process-wide cache (default: the
// smaller of 1 GiB and 1/16 of the physical memory; environment variable
// BELTRAMI_LARGE_BUFFER_CACHE_MB, 0 disables it) and handed out again for an
// allocation of the same rounded size: a filter that runs again (a changed
// parameter in ParaView, the next time step, the next solver call) finds
// its buffers already faulted in.  On machines where page faults are slow first
// touching fresh memory costs about 1-2 ms per MiB, more than computing the
// curvatures of the 1.2M-triangle benchmark mesh into it.  On Linux an
// allocation of a size the cache does not hold is made of cached blocks'
// pages (oldest first), moved into it by the kernel (mremap: page tables
// only, the pages are neither zeroed nor copied), and of fresh pages only
// for what the cache cannot cover.  So the cache gives way to new blocks
// instead of adding to them (on the 19M-triangle fairing step it had held
// up to its whole size at the peak), and passes that allocate other sizes
// in turn (the line drawing's re-runs) fault nothing in.  Elsewhere a new
// size returns cached blocks (oldest first) to the system to make room.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>


namespace beltrami
{

/// A 2 MiB-aligned block of at least `bytes` bytes (rounded up to 2 MiB),
/// marked for huge pages; from the cache when one of that size is there.
/// Throws std::bad_alloc.
void* AllocateLargeBlock(std::size_t bytes);
/// Returns a block of AllocateLargeBlock to the cache (or to the system).
/// Usable as a C free function (VTK arrays that own such a block); a block
/// that AllocateLargeBlock did not hand out is passed to std::free.
void FreeLargeBlock(void* block);
/// Returns every cached block to the system (the cache starts empty again).
void ReleaseLargeBlockCache();

/// The usable size of a block of AllocateLargeBlock, 0 for any other pointer.
std::size_t LargeBlockSize(const void* block);

template <class T>
struct LargeBufferAllocator
{
  using value_type = T;
  static constexpr std::size_t HugePage = std::size_t(2) << 20;

  LargeBufferAllocator() = default;
  template <class U>
  LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept
  {
  }

  T* allocate(std::size_t n)
  {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < HugePage)
    {
      return std::allocator<T>().allocate(n);
    }
    return static_cast<T*>(AllocateLargeBlock(bytes));
  }

  void deallocate(T* p, std::size_t n) noexcept
  {
    if (n * sizeof(T) < HugePage)
    {
      std::allocator<T>().deallocate(p, n);
    }
    else
    {
      FreeLargeBlock(p);
    }
  }

  template <class U>
  bool operator==(const LargeBufferAllocator<U>&) const noexcept
  {
    return true;
  }
  template <class U>
  bool operator!=(const LargeBufferAllocator<U>&) const noexcept
  {
    return false;
  }
};

/// A std::vector for large arrays (see above).
template <class T>
using LargeVector = std::vector<T, LargeBufferAllocator<T>>;

/// The same allocator, but resize() and the size constructor leave new
/// elements of trivial types uninitialized (default-initialized): for
/// buffers whose every element is written before it is read, so that a
/// large one is not first zeroed by one thread and then written again.
template <class T>
struct UninitializedAllocator : LargeBufferAllocator<T>
{
  template <class U>
  struct rebind
  {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept
  {
  }
  template <class U>
  void construct(U* p) noexcept
  {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A LargeVector whose new elements start uninitialized (see above).
template <class T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

} // namespace beltrami
