#include "Solvers/NestedDissection.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <numeric>

namespace beltrami
{

namespace
{

/// Subsets this small are left in their current order (their fill is small).
constexpr std::int64_t LeafSize = 16;
/// Subsets at least this large are split on a thread of their own.
constexpr std::int64_t ParallelSize = 20000;
/// Rows of more neighbours than this (and than 10 sqrt(n)) are dense.
constexpr double DenseDegree = 64.0;

struct Dissection
{
  const std::int64_t* Offsets;
  const Index* Neighbors;
  const double* Points;
  /// The side of each vertex in the split that last covered it (2 * split
  /// id + side): unique per split, so labels left by other subsets never
  /// match.
  std::vector<std::int64_t> Label;

  /// Reorders ids[begin, end) into its elimination order.
  void Order(Index* ids, std::int64_t count, std::int64_t splitId, int threads)
  {
    if (count <= LeafSize)
    {
      return;
    }
    // Longest axis of the bounding box; median split along it.
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (std::int64_t k = 0; k < count; ++k)
    {
      const double* p = Points + 3 * static_cast<std::int64_t>(ids[k]);
      for (int d = 0; d < 3; ++d)
      {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
    }
    int axis = 0;
    for (int d = 1; d < 3; ++d)
    {
      axis = hi[d] - lo[d] > hi[axis] - lo[axis] ? d : axis;
    }
    const std::int64_t half = count / 2;
    const auto key = [&](Index v) { // NaN first (a strict weak order whatever the input)
      const double x = Points[3 * static_cast<std::int64_t>(v) + axis];
      return x == x ? x : -HUGE_VAL;
    };
    std::nth_element(ids, ids + half, ids + count, [&](Index a, Index b) { return key(a) < key(b); });
    const std::int64_t labelA = 2 * splitId, labelB = labelA + 1;
    for (std::int64_t k = 0; k < count; ++k)
    {
      Label[ids[k]] = k < half ? labelA : labelB;
    }
    const auto touches = [&](Index v, std::int64_t other) {
      for (std::int64_t e = Offsets[v]; e < Offsets[v + 1]; ++e)
      {
        if (Label[Neighbors[e]] == other)
        {
          return true;
        }
      }
      return false;
    };
    std::int64_t touchA = 0, touchB = 0;
    for (std::int64_t k = 0; k < count; ++k)
    {
      (k < half ? touchA : touchB) += touches(ids[k], k < half ? labelB : labelA);
    }
    // Separator: the touching vertices of the side with fewer of them, moved
    // to the end of the range (after both halves).
    Index* a = ids;
    Index* b = ids + half;
    Index* end = ids + count;
    std::int64_t countA = half, countB = count - half;
    if (touchA <= touchB)
    {
      Index* s = std::stable_partition(a, b, [&](Index v) { return !touches(v, labelB); });
      std::rotate(s, b, end);
      countA = s - a;
      b = a + countA;
    }
    else
    {
      std::stable_partition(b, end, [&](Index v) { return !touches(v, labelA); });
      countB -= touchB;
    }
    // Children's split ids: a binary heap numbering (unique, no overflow for
    // the depths reached: about log2 of the vertex count).
    if (threads > 1 && std::min(countA, countB) >= ParallelSize)
    {
      auto left = std::async(std::launch::async, [&] { Order(a, countA, 2 * splitId, threads / 2); });
      Order(b, countB, 2 * splitId + 1, threads - threads / 2);
      left.get();
    }
    else
    {
      Order(a, countA, 2 * splitId, 1);
      Order(b, countB, 2 * splitId + 1, 1);
    }
  }
};

} // namespace

std::vector<Index> NestedDissectionOrder(Index n, const std::int64_t* offsets, const Index* neighbors,
  const double* points, int numThreads)
{
  // Dense rows (the apex of a fan of thousands of triangles: a cone, a disk
  // made of one fan, the pole of a latitude-longitude sphere) are left out
  // of the dissection and eliminated last, as minimum-degree orders do
  // (degree above 10 sqrt(n)): a split with such a vertex on one side made
  // every vertex of the other a separator vertex, and the factorization of
  // a double cone of 20,000 points a dense block of 10,000 (6 s instead of
  // 0.02).  Their labels stay -1, so touching them separates nothing.
  const double dense = std::max(DenseDegree, 10.0 * std::sqrt(static_cast<double>(n)));
  Dissection dissection{ offsets, neighbors, points, std::vector<std::int64_t>(static_cast<std::size_t>(n), -1) };
  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const auto sparse = std::stable_partition(
    order.begin(), order.end(), [&](Index v) { return static_cast<double>(offsets[v + 1] - offsets[v]) <= dense; });
  dissection.Order(order.data(), sparse - order.begin(), 1, std::max(1, numThreads));
  return order;
}

} // namespace beltrami
