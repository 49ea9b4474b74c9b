#include "Drawing/LineChaining.h"

#include <algorithm>
#include <utility>

namespace beltrami
{

namespace
{

/// partner[2 s + e]: the end (2 s' + e') that end e of segment s joins, or -1.
std::vector<std::int64_t> JoinEnds(const std::vector<LineSegment>& segments)
{
  std::vector<std::pair<std::int64_t, std::int64_t>> ends; // (key, end id)
  ends.reserve(2 * segments.size());
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    for (int e = 0; e < 2; ++e)
    {
      if (segments[s].End[e].Key >= 0)
      {
        ends.emplace_back(segments[s].End[e].Key, static_cast<std::int64_t>(2 * s + e));
      }
    }
  }
  std::sort(ends.begin(), ends.end());
  std::vector<std::int64_t> partner(2 * segments.size(), -1);
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

std::vector<SegmentChain> ChainSegments(const std::vector<LineSegment>& segments)
{
  const std::vector<std::int64_t> partner = JoinEnds(segments);
  std::vector<std::uint8_t> used(segments.size(), 0);
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
        break;
      }
      chain.Points.push_back({ s, exit });
      s = static_cast<Index>(next / 2);
      start = static_cast<int>(next % 2); // the same point as the previous exit
    }
    chains.push_back(std::move(chain));
  };
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    for (int e = 0; e < 2 && !used[s]; ++e)
    {
      if (partner[2 * s + e] < 0)
      {
        walk(static_cast<Index>(s), e);
      }
    }
  }
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    if (!used[s])
    {
      walk(static_cast<Index>(s), 0);
    }
  }
  return chains;
}

} // namespace beltrami
