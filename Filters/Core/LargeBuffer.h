// Beltrami core: an allocator for large per-vertex / per-pixel arrays.
//
// Arrays of several megabytes are placed on 2 MiB-aligned memory that the
// kernel may back with transparent huge pages (Linux, madvise mode), so that
// first touching them costs one page fault per 2 MiB instead of one per
// 4 KiB.  On virtual machines a 4 KiB fault can cost 10 us: a 512 x 512
// image flow spent more time faulting in its buffers than computing.
// Small arrays and other systems use the ordinary allocator.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace beltrami
{

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
    const std::size_t rounded = (bytes + HugePage - 1) / HugePage * HugePage;
    void* p = std::aligned_alloc(HugePage, rounded);
    if (!p)
    {
      throw std::bad_alloc();
    }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE); // a hint: failure changes nothing
#endif
    return static_cast<T*>(p);
  }

  void deallocate(T* p, std::size_t n) noexcept
  {
    if (n * sizeof(T) < HugePage)
    {
      std::allocator<T>().deallocate(p, n);
    }
    else
    {
      std::free(p);
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

} // namespace beltrami
