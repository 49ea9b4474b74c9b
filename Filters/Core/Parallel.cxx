#include "Parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include <unistd.h>

namespace beltrami
{

namespace
{

/// Threads kept between parallel loops: starting threads costs ~50 us per
/// loop here, and a flow or a solver runs thousands of short loops.  One loop
/// at a time uses the pool; a loop started meanwhile (another thread of the
/// application, or a loop inside a loop) starts its own threads as before.
class WorkerPool
{
public:
  static WorkerPool& Instance()
  {
    static WorkerPool pool;
    return pool;
  }

  /// Runs job on `helpers` pool threads and on the caller; false (nothing
  /// run) when the pool is in use or belongs to the parent of a fork.
  bool Run(int helpers, const std::function<void()>& job)
  {
    if (getpid() != Owner)
    {
      return false;
    }
    std::unique_lock<std::mutex> busy(Busy, std::try_to_lock);
    if (!busy.owns_lock())
    {
      return false;
    }
    {
      std::lock_guard<std::mutex> lock(Mutex);
      while (static_cast<int>(Threads.size()) < helpers)
      {
        const int index = static_cast<int>(Threads.size());
        Threads.emplace_back([this, index]() { Loop(index); });
      }
      Job = &job;
      Wanted = helpers;
      Pending = helpers;
      ++Generation;
    }
    Wake.notify_all();
    job();
    std::unique_lock<std::mutex> lock(Mutex);
    Done.wait(lock, [this]() { return Pending == 0; });
    Job = nullptr;
    return true;
  }

  ~WorkerPool()
  {
    {
      std::lock_guard<std::mutex> lock(Mutex);
      Stop = true;
    }
    Wake.notify_all();
    for (auto& t : Threads)
    {
      if (getpid() == Owner && t.joinable())
      {
        t.join();
      }
      else if (t.joinable())
      {
        t.detach();
      }
    }
  }

private:
  WorkerPool() = default;

  void Loop(int index)
  {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(Mutex);
    for (;;)
    {
      Wake.wait(lock, [&]() { return Stop || (Generation != seen && index < Wanted); });
      if (Stop)
      {
        return;
      }
      seen = Generation;
      const std::function<void()>* job = Job;
      lock.unlock();
      (*job)(); // never throws: the loops catch and pass exceptions on
      lock.lock();
      if (--Pending == 0)
      {
        Done.notify_all();
      }
    }
  }

  const pid_t Owner = getpid();
  std::mutex Busy;
  std::mutex Mutex;
  std::condition_variable Wake, Done;
  std::vector<std::thread> Threads;
  const std::function<void()>* Job = nullptr;
  std::uint64_t Generation = 0;
  int Wanted = 0;
  int Pending = 0;
  bool Stop = false;
};

/// Runs loop(stop) on `threads` threads (the caller being one of them).  The
/// first exception thrown in any of them sets `stop`, so that the others
/// finish early, and is rethrown here once all have finished.
void RunOnThreads(int threads, const std::function<void(const std::atomic<bool>& stop)>& loop)
{
  std::atomic<bool> failed{ false };
  std::exception_ptr failure;
  const std::function<void()> worker = [&]() {
    try
    {
      loop(failed);
    }
    catch (...)
    {
      if (!failed.exchange(true))
      {
        failure = std::current_exception();
      }
    }
  };
  if (threads <= 1)
  {
    worker();
  }
  else if (!WorkerPool::Instance().Run(threads - 1, worker))
  {
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (int t = 1; t < threads; ++t)
    {
      pool.emplace_back(worker);
    }
    worker();
    for (auto& th : pool)
    {
      th.join();
    }
  }
  if (failure)
  {
    std::rethrow_exception(failure);
  }
}

} // namespace

int DefaultThreadCount()
{
  if (const char* env = std::getenv("BELTRAMI_NUM_THREADS"))
  {
    const int n = std::atoi(env);
    if (n > 0)
    {
      return n;
    }
  }
  const unsigned hc = std::thread::hardware_concurrency();
  return hc > 0 ? static_cast<int>(hc) : 1;
}

int ResolveThreadCount(int requested)
{
  return requested > 0 ? requested : DefaultThreadCount();
}

bool ParallelFor(std::int64_t n, int numThreads,
  const std::function<void(std::int64_t, std::int64_t)>& body, const ProgressCallback& progress,
  int numBatches, std::int64_t grain)
{
  if (n <= 0)
  {
    return progress ? progress(1.0) : true;
  }
  numThreads = ResolveThreadCount(numThreads);
  if (numBatches <= 0)
  {
    // Progress is reported between batches; a batch must still be large
    // enough to give every thread a few grains (20 batches of a 40k-vertex
    // mesh each ran on one thread).
    numBatches = progress
      ? static_cast<int>(std::clamp<std::int64_t>(n / (4 * std::max<std::int64_t>(grain, 1) * numThreads), 1, 20))
      : 1;
  }
  const std::int64_t batchSize = std::max<std::int64_t>(1, (n + numBatches - 1) / numBatches);

  for (std::int64_t batchBegin = 0; batchBegin < n; batchBegin += batchSize)
  {
    const std::int64_t batchEnd = std::min(n, batchBegin + batchSize);
    const std::int64_t count = batchEnd - batchBegin;
    const int threads =
      static_cast<int>(std::min<std::int64_t>(numThreads, std::max<std::int64_t>(1, count / std::max<std::int64_t>(grain, 1))));
    if (threads <= 1)
    {
      body(batchBegin, batchEnd);
    }
    else
    {
      // Blocks small enough to balance the load, large enough to amortise the atomic.
      const std::int64_t block =
        std::max<std::int64_t>(std::min<std::int64_t>(256, grain), count / (threads * 16));
      std::atomic<std::int64_t> cursor{ batchBegin };
      RunOnThreads(threads, [&](const std::atomic<bool>& stop) {
        for (;;)
        {
          const std::int64_t b = cursor.fetch_add(block);
          if (b >= batchEnd || stop.load(std::memory_order_relaxed))
          {
            break;
          }
          body(b, std::min(batchEnd, b + block));
        }
      });
    }
    if (progress && !progress(static_cast<double>(batchEnd) / static_cast<double>(n)))
    {
      return false;
    }
  }
  return true;
}

std::vector<double> ParallelSum(std::int64_t n, int numberOfSums, int numThreads,
  const std::function<void(std::int64_t, std::int64_t, double*)>& body)
{
  constexpr std::int64_t Chunk = 4096;
  const std::int64_t numChunks = (std::max<std::int64_t>(n, 0) + Chunk - 1) / Chunk;
  std::vector<double> partials(static_cast<std::size_t>(numChunks * numberOfSums), 0.0);
  // Chunks are the items of the loop: ParallelFor over rows with chunk-aligned
  // ranges would split chunks between threads.
  const int threads = static_cast<int>(
    std::min<std::int64_t>(ResolveThreadCount(numThreads), std::max<std::int64_t>(1, numChunks / 2)));
  std::atomic<std::int64_t> cursor{ 0 };
  RunOnThreads(threads, [&](const std::atomic<bool>& stop) {
    for (std::int64_t c = cursor.fetch_add(1); c < numChunks && !stop.load(std::memory_order_relaxed);
         c = cursor.fetch_add(1))
    {
      body(c * Chunk, std::min(n, (c + 1) * Chunk), partials.data() + c * numberOfSums);
    }
  });
  std::vector<double> sums(static_cast<std::size_t>(numberOfSums), 0.0);
  for (std::int64_t c = 0; c < numChunks; ++c)
  {
    for (int k = 0; k < numberOfSums; ++k)
    {
      sums[k] += partials[c * numberOfSums + k];
    }
  }
  return sums;
}

} // namespace beltrami
