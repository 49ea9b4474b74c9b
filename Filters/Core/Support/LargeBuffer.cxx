#include "Support/LargeBuffer.h"

#include <algorithm>
#include <cstdint>
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

/// A block of whole huge pages.  On Linux it is made of pieces, each within
/// one kernel mapping (mremap moves pages only within one): the block's own
/// fresh mapping and the pages moved into it from cached blocks.
struct Block
{
  char* Address = nullptr;
  std::size_t Size = 0;
  std::vector<std::size_t> Pieces; ///< lengths, in address order
};

struct BlockCache
{
  std::mutex Mutex;
  std::unordered_map<void*, Block> Used; // handed out
  std::vector<Block> Free;               // cached, oldest first
  std::size_t FreeBytes = 0;
  std::size_t Limit = DefaultCacheLimit();
};

BlockCache& Cache()
{
  // Never destroyed: VTK arrays holding blocks may be freed during exit.
  static BlockCache* cache = new BlockCache;
  return *cache;
}

/// Returns a block to the system (munmap, or free without page moves).
void Unmap(const Block& block);

/// Returns the oldest cached block to the system; its size.
std::size_t DropOldest(BlockCache& cache)
{
  const std::size_t size = cache.Free.front().Size;
  cache.FreeBytes -= size;
  Unmap(cache.Free.front());
  cache.Free.erase(cache.Free.begin());
  return size;
}

#if defined(__linux__)

/// A fresh 2 MiB-aligned anonymous mapping of `bytes`, marked for huge pages.
char* MapFresh(std::size_t bytes)
{
  void* mapped = mmap(nullptr, bytes + HugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED)
  {
    throw std::bad_alloc();
  }
  char* raw = static_cast<char*>(mapped);
  char* aligned = raw + (HugePage - reinterpret_cast<std::uintptr_t>(raw) % HugePage) % HugePage;
  if (aligned > raw)
  {
    munmap(raw, aligned - raw);
  }
  munmap(aligned + bytes, raw + bytes + HugePage - aligned - bytes);
  madvise(aligned, bytes, MADV_HUGEPAGE); // a hint: failure changes nothing
  return aligned;
}

void Unmap(const Block& block)
{
  munmap(block.Address, block.Size);
}

/// Moves the first `bytes` (at most its first piece) of the cached block
/// `from` to `to`; false if the kernel refused.  The pages keep their
/// contents: nothing is faulted in or zeroed again.
bool MoveFront(Block& from, std::size_t bytes, char* to)
{
  if (mremap(from.Address, bytes, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, to) == MAP_FAILED)
  {
    return false;
  }
  from.Address += bytes;
  from.Size -= bytes;
  from.Pieces.front() -= bytes;
  if (from.Pieces.front() == 0)
  {
    from.Pieces.erase(from.Pieces.begin());
  }
  return true;
}

/// A new block of `bytes` whose pages are, as far as the cache has them,
/// pages of cached blocks (oldest first) moved into it: a request of a new
/// size reuses memory earlier passes faulted in, and the process's memory
/// grows only by what the cache cannot cover.  Called with the lock held.
Block AssembleBlock(BlockCache& cache, std::size_t bytes)
{
  Block block{ MapFresh(bytes), bytes, {} };
  std::size_t filled = 0;
  while (filled < bytes && !cache.Free.empty())
  {
    Block& source = cache.Free.front();
    const std::size_t piece = std::min(bytes - filled, source.Pieces.front());
    if (!MoveFront(source, piece, block.Address + filled))
    {
      break; // the rest is fresh memory
    }
    block.Pieces.push_back(piece);
    filled += piece;
    cache.FreeBytes -= piece;
    if (source.Size == 0)
    {
      cache.Free.erase(cache.Free.begin());
    }
  }
  if (filled < bytes)
  {
    block.Pieces.push_back(bytes - filled);
  }
  return block;
}

#else

char* MapFresh(std::size_t bytes)
{
  void* block = std::aligned_alloc(HugePage, bytes);
  if (!block)
  {
    throw std::bad_alloc();
  }
  return static_cast<char*>(block);
}

void Unmap(const Block& block)
{
  std::free(block.Address);
}

/// Without page moves: cached blocks (oldest first) make room for a new one.
Block AssembleBlock(BlockCache& cache, std::size_t bytes)
{
  std::size_t freed = 0;
  while (freed < bytes && !cache.Free.empty())
  {
    freed += DropOldest(cache);
  }
  return Block{ MapFresh(bytes), bytes, { bytes } };
}

#endif

} // namespace

void* AllocateLargeBlock(std::size_t bytes)
{
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + HugePage - 1) / HugePage * HugePage;
  BlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  Block block;
  const auto same = std::find_if(
    cache.Free.rbegin(), cache.Free.rend(), [rounded](const Block& b) { return b.Size == rounded; });
  if (same != cache.Free.rend())
  {
    block = std::move(*same);
    cache.Free.erase(std::next(same).base());
    cache.FreeBytes -= rounded;
  }
  else
  {
    block = AssembleBlock(cache, rounded);
  }
  void* address = block.Address;
  cache.Used.emplace(address, std::move(block));
  return address;
}

void ReleaseLargeBlockCache()
{
  BlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  while (!cache.Free.empty())
  {
    DropOldest(cache);
  }
}

std::size_t LargeBlockSize(const void* block)
{
  BlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  const auto known = cache.Used.find(const_cast<void*>(block));
  return known == cache.Used.end() ? 0 : known->second.Size;
}

void FreeLargeBlock(void* address)
{
  if (!address)
  {
    return;
  }
  BlockCache& cache = Cache();
  std::lock_guard<std::mutex> lock(cache.Mutex);
  const auto known = cache.Used.find(address);
  if (known == cache.Used.end())
  {
    std::free(address); // not ours (SuiteSparse's hooks pass small malloc blocks here)
    return;
  }
  Block block = std::move(known->second);
  cache.Used.erase(known);
  if (block.Size > cache.Limit)
  {
    Unmap(block);
    return;
  }
  cache.FreeBytes += block.Size;
  cache.Free.push_back(std::move(block));
  while (cache.FreeBytes > cache.Limit)
  {
    DropOldest(cache);
  }
}

} // namespace beltrami
