#include "Drawing/LineChaining.h"

#include "Drawing/FaceZeroSets.h"
#include "Solvers/Partition.h"

#include <algorithm>
#include <cstring>
#include <limits>
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

namespace
{

/// What a curvature line must reach to be kept: its length, and its
/// largest point strength (the hysteresis' full threshold; -inf: any).
struct LineFilter
{
  double MinimumLength = 0.0;
  double MinimumPeak = -std::numeric_limits<double>::infinity();
};

/// Turns the segments of `type` into polylines with their points'
/// positions, normals and strengths; polylines that do not pass `filter`
/// are left out.
void AddLines(const ViewSegments& segments, LineType type, LineSet& lines, const LineFilter& filter = {})
{
  const std::vector<double>& ends = segments.Ends[static_cast<int>(type)];
  const std::vector<Index>& faces = segments.Faces[static_cast<int>(type)];
  const auto faceOf = [&](const ChainPoint& cp) { return faces.empty() ? Index(-1) : faces[cp.Segment]; };
  for (const SegmentChain& chain : ChainSegments(segments.Keys[static_cast<int>(type)]))
  {
    const std::size_t firstValue = lines.PointStrength.size();
    const Index first = static_cast<Index>(lines.Points.size() / 3);
    double sum = 0.0, length = 0.0, peak = -std::numeric_limits<double>::infinity();
    for (const ChainPoint& cp : chain.Points)
    {
      const double* end = ends.data() + ViewSegments::ValuesPerEnd * (2 * static_cast<std::int64_t>(cp.Segment) + cp.End);
      const Vec3 p(end[0], end[1], end[2]);
      const double value = end[6];
      if (lines.PointStrength.size() > firstValue)
      {
        length += (p - Point(lines.Points.data(), static_cast<Index>(lines.PointStrength.size() - 1))).norm();
        lines.EdgeFace.back() = faceOf(cp); // (the piece from the previous point: this segment's)
      }
      lines.EdgeFace.push_back(-1);
      lines.Points.insert(lines.Points.end(), end, end + 3);
      lines.Normals.insert(lines.Normals.end(), end + 3, end + 6);
      lines.FieldPoints.insert(lines.FieldPoints.end(), end + 7, end + 10);
      lines.PointStrength.push_back(value);
      lines.Connectivity.push_back(static_cast<Index>(lines.PointStrength.size() - 1));
      sum += value;
      peak = std::max(peak, value);
    }
    if (chain.Closed && lines.PointStrength.size() > firstValue)
    {
      length += (Point(lines.Points.data(), first) -
        Point(lines.Points.data(), static_cast<Index>(lines.PointStrength.size() - 1))).norm();
    }
    if (length < filter.MinimumLength || !(peak >= filter.MinimumPeak))
    {
      // Too short or too weak: its points go again (they were appended above).
      lines.Points.resize(3 * firstValue);
      lines.Normals.resize(3 * firstValue);
      lines.FieldPoints.resize(3 * firstValue);
      lines.PointStrength.resize(firstValue);
      lines.Connectivity.resize(static_cast<std::size_t>(lines.Offsets.back()));
      lines.EdgeFace.resize(lines.Connectivity.size());
      continue;
    }
    if (chain.Closed)
    {
      lines.EdgeFace.back() = faces.empty() ? Index(-1) : faces[chain.ClosingSegment]; // (the closing piece)
      lines.Connectivity.push_back(first);
      lines.EdgeFace.push_back(-1);
    }
    lines.Offsets.push_back(static_cast<Index>(lines.Connectivity.size()));
    lines.Type.push_back(static_cast<std::uint8_t>(type));
    lines.Closed.push_back(chain.Closed);
    lines.Strength.push_back(sum / chain.Points.size());
  }
}

} // namespace

ViewSegments GatherViewSegments(const ViewSegments& mine, const LineDrawingGeometry& geo)
{
  // Per process and line type: the count, the keys (their bits), the ends,
  // the corners of the faces (global rows: exact in doubles).
  constexpr int perSegment = 2 * ViewSegments::ValuesPerEnd;
  std::vector<double> packed;
  for (int type = 0; type < NumberOfLineTypes; ++type)
  {
    packed.push_back(static_cast<double>(mine.Keys[type].size() / 2));
    for (const std::int64_t key : mine.Keys[type])
    {
      double bits;
      std::memcpy(&bits, &key, sizeof bits);
      packed.push_back(bits);
    }
    packed.insert(packed.end(), mine.Ends[type].begin(), mine.Ends[type].end());
    for (const Index f : mine.Faces[type])
    {
      for (int c = 0; c < 3; ++c)
      {
        packed.push_back(static_cast<double>(geo.KeyId(geo.Triangles[3 * static_cast<std::int64_t>(f) + c])));
      }
    }
  }
  const std::vector<double> all = geo.Split->GatherOnFirst(packed); // (the others return no lines)
  ViewSegments segments;
  for (std::size_t at = 0; at < all.size();)
  {
    for (int type = 0; type < NumberOfLineTypes; ++type)
    {
      const std::size_t count = static_cast<std::size_t>(all[at++]);
      for (std::size_t k = 0; k < 2 * count; ++k)
      {
        std::int64_t key;
        std::memcpy(&key, &all[at++], sizeof key);
        segments.Keys[type].push_back(key);
      }
      segments.Ends[type].insert(segments.Ends[type].end(), all.begin() + at, all.begin() + at + perSegment * count);
      at += perSegment * count;
      for (std::size_t k = 0; k < count; ++k)
      {
        segments.Faces[type].push_back(static_cast<Index>(segments.FaceCorners.size() / 3));
        for (int c = 0; c < 3; ++c)
        {
          segments.FaceCorners.push_back(static_cast<std::int64_t>(all[at++]));
        }
      }
    }
  }
  return segments;
}

LineSet ChainViewSegments(const ViewSegments& segments, const LineDrawingOptions& options, double size)
{
  // The curvature lines: long enough, and past the full threshold somewhere
  // where they were traced below it.
  const double hysteresis = HysteresisFactor(options);
  const auto curvatureLines = [&](double threshold) {
    LineFilter filter;
    filter.MinimumLength = options.MinimumLength * size;
    if (hysteresis < 1.0)
    {
      filter.MinimumPeak = threshold;
    }
    return filter;
  };
  LineSet lines;
  lines.FaceCorners = segments.FaceCorners;
  LineFilter contours; // (contours: no threshold, the length alone)
  contours.MinimumLength = options.MinimumLength * size;
  AddLines(segments, LineType::Contour, lines, contours);
  AddLines(segments, LineType::SuggestiveContour, lines, curvatureLines(options.SuggestiveThreshold));
  AddLines(segments, LineType::SuggestiveHighlight, lines, curvatureLines(options.SuggestiveThreshold));
  AddLines(segments, LineType::Ridge, lines, curvatureLines(options.RidgeThreshold));
  AddLines(segments, LineType::Valley, lines, curvatureLines(options.RidgeThreshold));
  AddLines(segments, LineType::Boundary, lines);
  AddLines(segments, LineType::Crease, lines);
  AddLines(segments, LineType::ApparentRidge, lines, curvatureLines(options.ApparentRidgeThreshold));
  return lines;
}

} // namespace beltrami
