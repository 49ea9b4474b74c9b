#include "Drawing/LineChaining.h"

#include <algorithm>
#include <utility>

namespace beltrami
{

namespace
{

/// (key, id) pairs with keys >= 0 and ids ascending sorted by key, ties in
/// id order (what std::sort gives them): a least-significant-digit radix
/// sort, 11 bits a pass, as many passes as the largest key needs (the keys
/// are vertex and edge numbers: two or three passes; with std::sort the
/// per-view pass of the 1.2M-triangle bunny took about 8% longer).
void SortByKey(std::vector<std::pair<std::int64_t, std::int64_t>>& items)
{
  constexpr int bits = 11, buckets = 1 << bits;
  std::int64_t largest = 0;
  for (const auto& item : items)
  {
    largest = std::max(largest, item.first);
  }
  std::vector<std::pair<std::int64_t, std::int64_t>> other(items.size());
  for (int shift = 0; shift < 63 && (largest >> shift) > 0; shift += bits)
  {
    std::vector<std::size_t> start(buckets + 1, 0);
    for (const auto& item : items)
    {
      ++start[((item.first >> shift) & (buckets - 1)) + 1];
    }
    for (int b = 0; b < buckets; ++b)
    {
      start[b + 1] += start[b];
    }
    for (const auto& item : items)
    {
      other[start[(item.first >> shift) & (buckets - 1)]++] = item;
    }
    items.swap(other);
  }
}

/// partner[2 s + e]: the end (2 s' + e') that end e of segment s joins, or -1.
std::vector<std::int64_t> JoinEnds(const std::vector<std::int64_t>& keys)
{
  std::vector<std::pair<std::int64_t, std::int64_t>> ends; // (key, end id)
  ends.reserve(keys.size());
  for (std::size_t e = 0; e < keys.size(); ++e)
  {
    if (keys[e] >= 0)
    {
      ends.emplace_back(keys[e], static_cast<std::int64_t>(e));
    }
  }
  SortByKey(ends);
  std::vector<std::int64_t> partner(keys.size(), -1);
  for (std::size_t k = 0; k < ends.size();)
  {
    std::size_t next = k;
    while (next < ends.size() && ends[next].first == ends[k].first)
    {
      ++next;
    }
    const std::int64_t a = ends[k].second, b = ends[k + 1 < next ? k + 1 : k].second;
    if (next - k == 2 && a / 2 != b / 2)
    {
      partner[a] = b;
      partner[b] = a;
    }
    k = next;
  }
  return partner;
}

} // namespace

std::vector<SegmentChain> ChainSegments(const std::vector<std::int64_t>& keys)
{
  const std::vector<std::int64_t> partner = JoinEnds(keys);
  const std::size_t numSegments = keys.size() / 2;
  std::vector<std::uint8_t> used(numSegments, 0);
  std::vector<SegmentChain> chains;
  // Walks from end `start` of segment s along the joined ends.
  const auto walk = [&](Index s, int start) {
    SegmentChain chain;
    chain.Points.push_back({ s, start });
    for (;;)
    {
      used[s] = 1;
      const int exit = 1 - start;
      const std::int64_t next = partner[2 * static_cast<std::int64_t>(s) + exit];
      if (next < 0 || used[next / 2])
      {
        chain.Closed = next >= 0 && next / 2 == chain.Points.front().Segment && next % 2 == chain.Points.front().End;
        if (!chain.Closed)
        {
          chain.Points.push_back({ s, exit });
        }
        else
        {
          chain.ClosingSegment = s;
        }
        break;
      }
      chain.Points.push_back({ s, exit });
      s = static_cast<Index>(next / 2);
      start = static_cast<int>(next % 2); // the same point as the previous exit
    }
    chains.push_back(std::move(chain));
  };
  for (std::size_t s = 0; s < numSegments; ++s)
  {
    for (int e = 0; e < 2 && !used[s]; ++e)
    {
      if (partner[2 * s + e] < 0)
      {
        walk(static_cast<Index>(s), e);
      }
    }
  }
  for (std::size_t s = 0; s < numSegments; ++s)
  {
    if (!used[s])
    {
      walk(static_cast<Index>(s), 0);
    }
  }
  return chains;
}

} // namespace beltrami
