// Large-array allocation: 2 MiB alignment and the cache of freed blocks.
#include "Support/LargeBuffer.h"

#include <gtest/gtest.h>

#include <cstdint>
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

TEST(LargeBuffer, ASmallerRequestTakesTheSmallestBlockUpToTwiceItsSize)
{
  constexpr std::size_t MiB = std::size_t(1) << 20;
  ReleaseLargeBlockCache(); // (the blocks earlier tests left)
  void* six = AllocateLargeBlock(6 * MiB);
  void* ten = AllocateLargeBlock(10 * MiB);
  void* twenty = AllocateLargeBlock(20 * MiB);
  FreeLargeBlock(twenty);
  FreeLargeBlock(ten);
  FreeLargeBlock(six);
  void* five = AllocateLargeBlock(5 * MiB); // rounded to 6: the same size first
  EXPECT_EQ(five, six);
  void* four = AllocateLargeBlock(4 * MiB + 1); // 6 MiB: none left; 10 and 20 MiB: the smaller
  EXPECT_EQ(four, ten);
  EXPECT_EQ(LargeBlockSize(four), 10 * MiB);
  static_cast<char*>(four)[10 * MiB - 1] = 1;
  void* two = AllocateLargeBlock(2 * MiB); // 20 MiB is more than twice: a block of 2 MiB
  EXPECT_EQ(LargeBlockSize(two), 2 * MiB);
  for (void* block : { five, four, two })
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
