// Beltrami core: a small, VTK-free parallel loop.
//
// The work [0, n) is cut into batches; each batch is shared by the worker
// threads in blocks taken from an atomic counter.  Between batches the calling
// thread reports progress and may cancel the loop, so VTK adapters can call
// UpdateProgress()/CheckAbort() from the thread that owns the algorithm.
// Every index is processed exactly once whatever the thread count, so results
// that are written per index are bit-identical for 1 or N threads.
#pragma once

#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>
#include <vector>

namespace beltrami
{

using Index = std::int32_t;

/// Returns false to cancel the work; fraction is in [0, 1].
using ProgressCallback = std::function<bool(double fraction)>;

/// Number of threads used when a caller asks for 0 ("all"): the value of the
/// environment variable BELTRAMI_NUM_THREADS if set, else the hardware
/// concurrency divided among the processes of an MPI job on this node (as
/// Open MPI's or MPICH's launcher tells them; at least 1).
int DefaultThreadCount();

/// Resolves a requested count (<= 0 means DefaultThreadCount()).
int ResolveThreadCount(int requested);

/// Runs body(begin, end) over disjoint ranges covering [0, n).
/// Returns false when the progress callback cancelled the loop (the remaining
/// batches are then not processed).  grain: the fewest items worth a thread
/// of their own (1024 cheap items such as vertices; 1 for heavy items such as
/// image row bands).
bool ParallelFor(std::int64_t n, int numThreads,
  const std::function<void(std::int64_t begin, std::int64_t end)>& body,
  const ProgressCallback& progress = {}, int numBatches = 0, std::int64_t grain = 1024);

/// Deterministic parallel sums: [0, n) is cut into chunks of a fixed size
/// (independent of the thread count), body(begin, end, partial) adds its
/// chunk's contribution to `partial` (numberOfSums values, zeroed), and the
/// chunks are summed in order.  Results are bit-identical for any thread count.
std::vector<double> ParallelSum(std::int64_t n, int numberOfSums, int numThreads,
  const std::function<void(std::int64_t begin, std::int64_t end, double* partial)>& body);

/// The per-chunk partials of ParallelSum (numberOfValues per chunk, chunk c
/// covering [c * ParallelChunkSize, (c + 1) * ParallelChunkSize)), for other
/// reductions (a maximum: the body keeps its chunk's maximum in partial).
constexpr std::int64_t ParallelChunkSize = 4096;
std::vector<double> ParallelPartials(std::int64_t n, int numberOfValues, int numThreads,
  const std::function<void(std::int64_t begin, std::int64_t end, double* partial)>& body);

/// body(begin, end) over the chunks of ParallelSum, and on the same threads:
/// thread t always takes the t-th contiguous share of the chunks.  Loops of an
/// iterative solver that touch the same rows (its vectors) then find them in
/// the cache of the core that wrote them; with dynamic blocks two threads were
/// slower than one (the rows moved between the cores' caches on every loop).
/// For uniform work only (no load balancing).
void ParallelForStatic(std::int64_t n, int numThreads,
  const std::function<void(std::int64_t begin, std::int64_t end)>& body);

/// Calls run(std::integral_constant<int, K>()) with K = count clamped to
/// [1, Maximum]: kernels compiled per column or component count (the loops
/// over K unroll and vectorize), chosen at run time.
template <int Maximum, typename Run>
decltype(auto) WithCount(int count, Run&& run)
{
  if constexpr (Maximum > 1)
  {
    if (count < Maximum)
    {
      return WithCount<Maximum - 1>(count, std::forward<Run>(run));
    }
  }
  return run(std::integral_constant<int, Maximum>());
}

} // namespace beltrami
