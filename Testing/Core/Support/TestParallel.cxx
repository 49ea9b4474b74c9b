// The parallel loops of the core (Filters/Core/Support/Parallel): every
// index once, sums independent of the thread count, cancellation, the
// compile-time count dispatch, the default thread count.
#include "Support/Parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

using namespace beltrami;

TEST(Parallel, StaticLoopsAndPartialsCoverEveryIndexOnce)
{
  for (std::int64_t n : { 0, 1, 4095, 4096, 4097, 50000 })
  {
    for (int threads : { 1, 2, 3 })
    {
      std::vector<std::atomic<int>> seen(static_cast<std::size_t>(n));
      ParallelForStatic(n, threads, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i)
        {
          seen[i]++;
        }
      });
      for (std::int64_t i = 0; i < n; ++i)
      {
        ASSERT_EQ(seen[i].load(), 1) << "n " << n << " threads " << threads << " index " << i;
      }
      // A maximum from the per-chunk partials (a sum of chunk maxima was the
      // bug of the surface flows' stable step).
      const std::vector<double> partials = ParallelPartials(n, 1, threads, [&](std::int64_t b, std::int64_t e, double* m) {
        for (std::int64_t i = b; i < e; ++i)
        {
          m[0] = std::max(m[0], static_cast<double>((i * 7919) % 1000));
        }
      });
      ASSERT_EQ(static_cast<std::int64_t>(partials.size()), (n + ParallelChunkSize - 1) / ParallelChunkSize);
      const double expected = n > 1000 ? 999.0 : 0.0;
      if (n > 1000)
      {
        EXPECT_EQ(*std::max_element(partials.begin(), partials.end()), expected);
      }
    }
  }
}

TEST(Parallel, SumsAreBitIdenticalForAnyThreadCount)
{
  const std::int64_t n = 100003;
  const auto body = [](std::int64_t b, std::int64_t e, double* acc) {
    for (std::int64_t i = b; i < e; ++i)
    {
      acc[0] += 1.0 / (1.0 + static_cast<double>(i)); // sums that depend on the order of additions
      acc[1] += std::sin(static_cast<double>(i));
    }
  };
  const std::vector<double> one = ParallelSum(n, 2, 1, body);
  for (int threads : { 2, 3, 8 })
  {
    EXPECT_EQ(ParallelSum(n, 2, threads, body), one) << threads;
  }
  EXPECT_NEAR(one[0], std::log(static_cast<double>(n)) + 0.5772156649, 1e-4);
}

TEST(Parallel, ProgressCanCancelBetweenBatches)
{
  const std::int64_t n = 1 << 20;
  std::atomic<std::int64_t> done{ 0 };
  int calls = 0;
  const bool completed = ParallelFor(n, 2,
    [&](std::int64_t b, std::int64_t e) { done += e - b; },
    [&](double fraction) {
      ++calls;
      EXPECT_GE(fraction, 0.0);
      EXPECT_LE(fraction, 1.0);
      return fraction < 0.25; // cancel once a quarter is done
    },
    16);
  EXPECT_FALSE(completed);
  EXPECT_GT(calls, 1);
  EXPECT_GT(done.load(), 0);
  EXPECT_LT(done.load(), n); // the remaining batches were not processed
  std::atomic<std::int64_t> all{ 0 };
  EXPECT_TRUE(ParallelFor(n, 2, [&](std::int64_t b, std::int64_t e) { all += e - b; }));
  EXPECT_EQ(all.load(), n);
}

TEST(Parallel, WithCountDispatchesToTheClampedCount)
{
  for (int count : { -3, 0, 1, 2, 3, 4, 9 })
  {
    const int chosen = WithCount<4>(count, [](auto k) { return decltype(k)::value; });
    EXPECT_EQ(chosen, std::clamp(count, 1, 4)) << count;
  }
  EXPECT_EQ(ResolveThreadCount(3), 3);
  EXPECT_EQ(ResolveThreadCount(0), DefaultThreadCount());
  EXPECT_GE(DefaultThreadCount(), 1);
}

// "All cores" in an MPI job: the node's cores shared among the job's
// processes there, as the launcher tells them; BELTRAMI_NUM_THREADS wins.
TEST(Parallel, DefaultThreadsAreSharedAmongAnMpiJobsProcesses)
{
  const char* names[] = { "BELTRAMI_NUM_THREADS", "OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS" };
  std::string saved[3];
  bool had[3];
  for (int k = 0; k < 3; ++k)
  {
    const char* value = std::getenv(names[k]);
    had[k] = value != nullptr;
    saved[k] = value ? value : "";
    unsetenv(names[k]);
  }
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  EXPECT_EQ(DefaultThreadCount(), cores);
  setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "2", 1);
  EXPECT_EQ(DefaultThreadCount(), std::max(1, cores / 2));
  setenv("OMPI_COMM_WORLD_LOCAL_SIZE", "100000", 1); // more processes than cores: one thread each
  EXPECT_EQ(DefaultThreadCount(), 1);
  unsetenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  setenv("MPI_LOCALNRANKS", "100000", 1);
  EXPECT_EQ(DefaultThreadCount(), 1);
  setenv("BELTRAMI_NUM_THREADS", "3", 1);
  EXPECT_EQ(DefaultThreadCount(), 3);
  EXPECT_EQ(ResolveThreadCount(0), 3);
  for (int k = 0; k < 3; ++k)
  {
    if (had[k])
    {
      setenv(names[k], saved[k].c_str(), 1);
    }
    else
    {
      unsetenv(names[k]);
    }
  }
}
