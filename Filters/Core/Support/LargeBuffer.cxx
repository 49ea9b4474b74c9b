#include "Support/LargeBuffer.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace beltrami
{

namespace
{

constexpr std::size_t HugePage = LargeBufferAllocator<char>::HugePage;

std::size_t DefaultCacheLimit()
{
  if (const char* env = std::getenv("BELTRAMI_LARGE_BUFFER_CACHE_MB"))
  {
    return static_cast<std::size_t>(std::max(0L, std::strtol(env, nullptr, 10))) << 20;
  }
  std::size_t limit = std::size_t(1) << 30;
#if defined(__linux__)
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  if (pages > 0 && pageSize > 0)
  {
    limit = std::min(limit, static_cast<std::size_t>(pages) * static_cast<std::size_t>(pageSize) / 16);
  }
#endif
  return limit;
}

struct BlockCache
{
  std::mutex Mutex;
  std::unordered_map<void*, std::size_t> Sizes; // every block handed out or cached
  std::vector<std::pair<void*, std::size_t>> Free; // cached, oldest first
  std::size_t FreeBytes = 0;
  std::size_t Limit = DefaultCacheLimit();
};

BlockCache& Cache()
{
  // Never destroyed: VTK arrays holding blocks may be freed during exit.
  static BlockCache* cache = new BlockCache;
  return *cache;
}

} // namespace

void* AllocateLargeBlock(std::size_t bytes)
{
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + HugePage - 1) / HugePage * HugePage;
  BlockCache& cache = Cache();
  std::vector<void*> release;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    for (auto it = cache.Free.rbegin(); it != cache.Free.rend(); ++it)
    {
      if (it->second == rounded)
      {
        void* block = it->first;
        cache.FreeBytes -= rounded;
        cache.Free.erase(std::next(it).base());
        return block;
      }
    }
    // No block of its size: the smallest of those up to twice its size, so
    // that the temporaries of one pass reuse the memory the pass before
    // faulted in (the line drawing's first run faulted in 90 MB less).
    auto best = cache.Free.end();
    for (auto it = cache.Free.begin(); it != cache.Free.end(); ++it)
    {
      if (it->second > rounded && it->second <= 2 * rounded && (best == cache.Free.end() || it->second < best->second))
      {
        best = it;
      }
    }
    if (best != cache.Free.end())
    {
      void* block = best->first;
      cache.FreeBytes -= best->second;
      cache.Free.erase(best);
      return block;
    }
    // A miss: cached blocks (oldest first) make room for the new one.
    std::size_t freed = 0, evict = 0;
    for (; evict < cache.Free.size() && freed < rounded; ++evict)
    {
      freed += cache.Free[evict].second;
      cache.Sizes.erase(cache.Free[evict].first);
      release.push_back(cache.Free[evict].first);
    }
    cache.FreeBytes -= freed;
    cache.Free.erase(cache.Free.begin(), cache.Free.begin() + evict);
  }
  for (void* b : release)
  {
    std::free(b);
  }
  void* block = std::aligned_alloc(HugePage, rounded);
  if (!block)
  {
    throw std::bad_alloc();
  }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  madvise(block, rounded, MADV_HUGEPAGE); // a hint: failure changes nothing
#endif
  std::lock_guard<std::mutex> lock(cache.Mutex);
  cache.Sizes[block] = rounded;
  return block;
}

void ReleaseLargeBlockCache()
{
  BlockCache& cache = Cache();
  std::vector<std::pair<void*, std::size_t>> release;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    release.swap(cache.Free);
    for (const auto& block : release)
    {
      cache.Sizes.erase(block.first);
    }
    cache.FreeBytes = 0;
  }
  for (const auto& block : release)
  {
    std::free(block.first);
  }
}

std::size_t LargeBlockSize(const void* block)
{
  BlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  const auto known = cache.Sizes.find(const_cast<void*>(block));
  return known == cache.Sizes.end() ? 0 : known->second;
}

void FreeLargeBlock(void* block)
{
  if (!block)
  {
    return;
  }
  BlockCache& cache = Cache();
  std::vector<void*> release;
  {
    std::lock_guard<std::mutex> lock(cache.Mutex);
    const auto known = cache.Sizes.find(block);
    if (known == cache.Sizes.end())
    {
      release.push_back(block); // not ours (SuiteSparse's hooks pass small malloc blocks here)
    }
    else if (known->second > cache.Limit)
    {
      cache.Sizes.erase(known);
      release.push_back(block);
    }
    else
    {
      cache.Free.emplace_back(block, known->second);
      cache.FreeBytes += known->second;
      std::size_t evict = 0;
      while (cache.FreeBytes > cache.Limit)
      {
        cache.FreeBytes -= cache.Free[evict].second;
        cache.Sizes.erase(cache.Free[evict].first);
        release.push_back(cache.Free[evict].first);
        ++evict;
      }
      cache.Free.erase(cache.Free.begin(), cache.Free.begin() + evict);
    }
  }
  for (void* b : release)
  {
    std::free(b);
  }
}

} // namespace beltrami
