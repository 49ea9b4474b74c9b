// Large-array allocation: 2 MiB alignment and the cache of freed blocks.
#include "Support/LargeBuffer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

using namespace beltrami;

TEST(LargeBuffer, BlocksAreAlignedAndReused)
{
  constexpr std::size_t MiB = std::size_t(1) << 20;
  ReleaseLargeBlockCache(); // (the blocks earlier tests left)
  void* a = AllocateLargeBlock(5 * MiB);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a) % (2 * MiB), 0u);
  static_cast<char*>(a)[5 * MiB - 1] = 1; // the whole rounded block is usable
  FreeLargeBlock(a);
  // The same rounded size (6 MiB) comes back from the cache; another does not.
  void* b = AllocateLargeBlock(5 * MiB + 1);
  EXPECT_EQ(b, a);
  void* c = AllocateLargeBlock(9 * MiB);
  EXPECT_NE(c, a);
  FreeLargeBlock(b);
  FreeLargeBlock(c);
  FreeLargeBlock(nullptr); // allowed, like free(nullptr)
}

/// Whether every byte of [block + from, block + to) is `value`.
bool Holds(void* block, std::size_t from, std::size_t to, char value)
{
  const char* bytes = static_cast<const char*>(block);
  return std::all_of(bytes + from, bytes + to, [value](char b) { return b == value; });
}

TEST(LargeBuffer, ARequestOfANewSizeTakesTheCachedPagesWithTheirContents)
{
#if !defined(__linux__)
  GTEST_SKIP() << "pages are moved between blocks on Linux only";
#endif
  // A block of a size the cache does not hold is made of cached blocks'
  // pages (oldest first), moved with what they hold (so not faulted in and
  // zeroed again); only what the cache cannot cover is fresh (zero).
  constexpr std::size_t MiB = std::size_t(1) << 20;
  ReleaseLargeBlockCache(); // (the blocks earlier tests left)
  void* four = AllocateLargeBlock(4 * MiB);
  void* six = AllocateLargeBlock(6 * MiB);
  std::memset(four, 1, 4 * MiB);
  std::memset(six, 2, 6 * MiB);
  FreeLargeBlock(four);
  FreeLargeBlock(six);
  void* eight = AllocateLargeBlock(8 * MiB); // all of 4, then 4 of the 6
  ASSERT_EQ(LargeBlockSize(eight), 8 * MiB);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(eight) % (2 * MiB), 0u);
  EXPECT_TRUE(Holds(eight, 0, 4 * MiB, 1));
  EXPECT_TRUE(Holds(eight, 4 * MiB, 8 * MiB, 2));
  void* rest = AllocateLargeBlock(2 * MiB); // what is left of the 6: its size exactly
  EXPECT_EQ(rest, static_cast<char*>(six) + 4 * MiB);
  EXPECT_TRUE(Holds(rest, 0, 2 * MiB, 2));
  // A block made of pieces is moved piece by piece; beyond the cache, fresh pages.
  std::memset(eight, 3, 8 * MiB);
  FreeLargeBlock(eight);
  void* twelve = AllocateLargeBlock(12 * MiB);
  EXPECT_TRUE(Holds(twelve, 0, 8 * MiB, 3));
  EXPECT_TRUE(Holds(twelve, 8 * MiB, 12 * MiB, 0));
  static_cast<char*>(twelve)[12 * MiB - 1] = 1; // the whole block is usable
  for (void* block : { rest, twelve })
  {
    FreeLargeBlock(block);
  }
}

TEST(LargeBuffer, VectorsFromManyThreads)
{
  // LargeVector through the allocator, small (ordinary allocator) and large
  // (cached blocks), allocated and freed concurrently.
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
  {
    threads.emplace_back([t]() {
      for (int r = 0; r < 50; ++r)
      {
        LargeVector<double> small(100, t), large((std::size_t(1) << 18) * (1 + r % 3), t);
        ASSERT_EQ(small[99], t);
        ASSERT_EQ(large.back(), t);
      }
    });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
}

TEST(LargeBuffer, UninitializedVectorsSkipTheZeroFillOnly)
{
  // A large UninitializedVector gets a cached block as it was left (no
  // zero fill); values given explicitly are still written.
  constexpr std::size_t n = std::size_t(3) << 18; // 6 MiB of doubles
  const double* block = nullptr;
  {
    LargeVector<double> filled(n, 7.0);
    block = filled.data();
  }
  UninitializedVector<double> reused(n);
  ASSERT_EQ(reused.data(), block); // (the cache's block)
  EXPECT_EQ(reused[0], 7.0);
  EXPECT_EQ(reused[n - 1], 7.0);
  UninitializedVector<double> given(n, 2.5);
  EXPECT_EQ(given[n / 2], 2.5);
  given.resize(n + 10, -1.0);
  EXPECT_EQ(given[n + 9], -1.0);
  EXPECT_EQ(given[n - 1], 2.5);
}
