#include "Support/Parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
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
  bool Run(int helpers, const std::function<void(int)>& job)
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
      Pending.store(helpers);
      Generation.fetch_add(1);
    }
    Wake.notify_all(); // no system call when every helper is still spinning
    job(0);
    if (!SpinUntil([this]() { return Pending.load() == 0; }))
    {
      std::unique_lock<std::mutex> lock(Mutex);
      Done.wait(lock, [this]() { return Pending.load() == 0; });
    }
    std::lock_guard<std::mutex> lock(Mutex);
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

  /// Spins (for up to SpinTime) until ready() holds: waking a sleeping
  /// thread costs tens of microseconds, more where page faults are slow, and a
  /// solver runs a parallel loop every few hundred microseconds.
  template <typename F>
  static bool SpinUntil(F&& ready)
  {
    constexpr auto SpinTime = std::chrono::microseconds(200);
    const auto start = std::chrono::steady_clock::now();
    for (int k = 1;; ++k)
    {
      if (ready())
      {
        return true;
      }
      if (k % 64 == 0)
      {
        if (std::chrono::steady_clock::now() - start > SpinTime)
        {
          return false;
        }
        // Gives the core away when another thread waits for it: with more
        // threads than cores (two processes at once, MPI processes on one
        // node) a spinning thread otherwise holds the core that the thread
        // it waits for needs.  Two 2-thread runs of the distributed
        // denoising test at once on 2 cores: 26 s -> 17 s, each alone as
        // before.
        std::this_thread::yield();
      }
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }

  void Loop(int index)
  {
    std::uint64_t seen = 0;
    for (;;)
    {
      const auto wanted = [&]() { return Stop.load() || (Generation.load() != seen && index < Wanted.load()); };
      if (!SpinUntil(wanted))
      {
        std::unique_lock<std::mutex> lock(Mutex);
        Wake.wait(lock, wanted);
      }
      const std::function<void(int)>* job;
      {
        std::lock_guard<std::mutex> lock(Mutex);
        if (Stop)
        {
          return;
        }
        seen = Generation.load();
        if (index >= Wanted.load())
        {
          continue;
        }
        job = Job;
      }
      (*job)(index + 1); // never throws: the loops catch and pass exceptions on
      if (Pending.fetch_sub(1) == 1)
      {
        // Under the mutex, so that a caller that has just found Pending > 0
        // is either not yet waiting (it then sees 0) or woken.
        std::lock_guard<std::mutex> lock(Mutex);
        Done.notify_all();
      }
    }
  }

  const pid_t Owner = getpid();
  std::mutex Busy;
  std::mutex Mutex;
  std::condition_variable Wake, Done;
  std::vector<std::thread> Threads;
  const std::function<void(int)>* Job = nullptr;
  std::atomic<std::uint64_t> Generation{ 0 };
  std::atomic<int> Wanted{ 0 };
  std::atomic<int> Pending{ 0 };
  std::atomic<bool> Stop{ false };
};

/// Runs loop(stop, thread) on `threads` threads numbered 0 (the caller) to
/// threads - 1; pool threads keep their number from loop to loop.  The
/// first exception thrown in any of them sets `stop`, so that the others
/// finish early, and is rethrown here once all have finished.
void RunOnThreads(int threads, const std::function<void(const std::atomic<bool>& stop, int thread)>& loop)
{
  std::atomic<bool> failed{ false };
  std::exception_ptr failure;
  const std::function<void(int)> worker = [&](int thread) {
    try
    {
      loop(failed, thread);
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
    worker(0);
  }
  else if (!WorkerPool::Instance().Run(threads - 1, worker))
  {
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (int t = 1; t < threads; ++t)
    {
      pool.emplace_back(worker, t);
    }
    worker(0);
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

namespace
{

/// The processes of this MPI job on this node, as the launcher tells them
/// (Open MPI, MPICH's Hydra); 1 outside a job.
int LocalProcesses()
{
  for (const char* name : { "OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS" })
  {
    if (const char* env = std::getenv(name))
    {
      const int n = std::atoi(env);
      if (n > 0)
      {
        return n;
      }
    }
  }
  return 1;
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
  // The cores shared among the processes of an MPI job on this node: with
  // every process on all cores, threads that wait for each other by turns
  // (the pool's spinning barriers, thousands per solve) lost their time
  // slices, and a 3-process pvbatch run on 2 cores took 44 s instead of 25.
  const unsigned hc = std::thread::hardware_concurrency();
  return std::max(1, (hc > 0 ? static_cast<int>(hc) : 1) / LocalProcesses());
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
      RunOnThreads(threads, [&](const std::atomic<bool>& stop, int) {
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

namespace
{
/// Runs body(chunk, own) for the chunks of [0, n): thread t of T takes chunks
/// [t C / T, (t + 1) C / T), `own` a zeroed buffer of `values` doubles private
/// to the thread (neighbouring chunks' results share cache lines: bodies that
/// add to them row by row made two threads slower than one).
void ForEachChunk(std::int64_t n, int values, int numThreads,
  const std::function<void(std::int64_t chunk, double* own)>& body)
{
  const std::int64_t numChunks = (std::max<std::int64_t>(n, 0) + ParallelChunkSize - 1) / ParallelChunkSize;
  const int threads = static_cast<int>(
    std::min<std::int64_t>(ResolveThreadCount(numThreads), std::max<std::int64_t>(1, numChunks / 2)));
  RunOnThreads(threads, [&](const std::atomic<bool>& stop, int thread) {
    std::vector<double> local(static_cast<std::size_t>(values) + 16);
    double* own = local.data() + 8;
    const std::int64_t first = numChunks * thread / threads, last = numChunks * (thread + 1) / threads;
    for (std::int64_t c = first; c < last && !stop.load(std::memory_order_relaxed); ++c)
    {
      std::fill(own, own + values, 0.0);
      body(c, own);
    }
  });
}
} // namespace

std::vector<double> ParallelPartials(std::int64_t n, int numberOfValues, int numThreads,
  const std::function<void(std::int64_t, std::int64_t, double*)>& body)
{
  const std::int64_t numChunks = (std::max<std::int64_t>(n, 0) + ParallelChunkSize - 1) / ParallelChunkSize;
  std::vector<double> partials(static_cast<std::size_t>(numChunks * numberOfValues), 0.0);
  ForEachChunk(n, numberOfValues, numThreads, [&](std::int64_t c, double* own) {
    body(c * ParallelChunkSize, std::min(n, (c + 1) * ParallelChunkSize), own);
    std::copy(own, own + numberOfValues, partials.data() + c * numberOfValues);
  });
  return partials;
}

std::vector<double> ParallelSum(std::int64_t n, int numberOfSums, int numThreads,
  const std::function<void(std::int64_t, std::int64_t, double*)>& body)
{
  const std::vector<double> partials = ParallelPartials(n, numberOfSums, numThreads, body);
  std::vector<double> sums(static_cast<std::size_t>(numberOfSums), 0.0);
  for (std::size_t c = 0; c < partials.size(); c += numberOfSums)
  {
    for (int k = 0; k < numberOfSums; ++k)
    {
      sums[k] += partials[c + k]; // chunk by chunk: the same sum for any thread count
    }
  }
  return sums;
}

void ParallelForStatic(std::int64_t n, int numThreads,
  const std::function<void(std::int64_t begin, std::int64_t end)>& body)
{
  ForEachChunk(n, 0, numThreads, [&](std::int64_t c, double*) {
    body(c * ParallelChunkSize, std::min(n, (c + 1) * ParallelChunkSize));
  });
}

} // namespace beltrami
