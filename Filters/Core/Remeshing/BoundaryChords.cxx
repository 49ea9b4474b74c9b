#include "Remeshing/BoundaryChords.h"

#include "Remeshing/Remesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

namespace beltrami
{

namespace
{

using PlanePoint = std::array<double, 2>;

/// The parameter positions of a path's vertices in one chart (empty where
/// a vertex is not in it).
std::vector<PlanePoint> PathInChart(const SamplePath& path, const AtlasChart& chart)
{
  std::vector<PlanePoint> uv(path.Vertices.size());
  for (std::size_t i = 0; i < path.Vertices.size(); ++i)
  {
    const auto at = std::lower_bound(chart.Vertices.begin(), chart.Vertices.end(), path.Vertices[i]);
    if (at == chart.Vertices.end() || *at != path.Vertices[i])
    {
      return {};
    }
    const std::size_t local = static_cast<std::size_t>(at - chart.Vertices.begin());
    uv[i] = { chart.UV[2 * local], chart.UV[2 * local + 1] };
  }
  return uv;
}

/// The path's point at arc length `arc` in the chart (vertex positions uv).
PlanePoint AtArc(const SamplePath& path, const std::vector<PlanePoint>& uv, double arc)
{
  const auto [k, t] = EdgeAtArc(path.Arc, arc);
  return { (1.0 - t) * uv[k][0] + t * uv[k + 1][0], (1.0 - t) * uv[k][1] + t * uv[k + 1][1] };
}

double Orient(const PlanePoint& a, const PlanePoint& b, const PlanePoint& c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Proper crossing of segments ab and cd (not at a shared end).
bool Cross(const PlanePoint& a, const PlanePoint& b, const PlanePoint& c, const PlanePoint& d)
{
  const double o1 = Orient(a, b, c), o2 = Orient(a, b, d), o3 = Orient(c, d, a), o4 = Orient(c, d, b);
  return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

/// A chord of a chart: path p's samples j, j + 1, and its ends' sample ids.
struct Chord
{
  int Path;
  std::size_t Number;
  PlanePoint A, B;
  Index SampleA, SampleB;
};

/// Whether q lies inside the polygon `ring` (even-odd rule).
bool Inside(const std::vector<PlanePoint>& ring, const PlanePoint& q)
{
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
  {
    const PlanePoint& a = ring[i];
    const PlanePoint& b = ring[j];
    if ((a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
    {
      inside = !inside;
    }
  }
  return inside;
}

/// The chords whose lune (the chord and the stretch of its path between
/// its samples) holds another of the chords' ends: the chord passes on the
/// far side of that sample, and the chart's polygon of chords would turn
/// inside out there (a seam that bends round a thin chart's corners).
void ChordsAroundSamples(const SurfaceSamples& out, const std::vector<std::vector<PlanePoint>>& uvOfPath,
  const std::vector<Chord>& chords, std::set<std::pair<int, std::size_t>>& separate)
{
  std::vector<std::pair<PlanePoint, Index>> ends; // by x
  for (const Chord& c : chords)
  {
    ends.push_back({ c.A, c.SampleA });
    ends.push_back({ c.B, c.SampleB });
  }
  std::sort(ends.begin(), ends.end());
  std::vector<PlanePoint> lune;
  for (const Chord& c : chords)
  {
    const SamplePath& path = out.Paths[c.Path];
    const std::vector<PlanePoint>& uv = uvOfPath[c.Path];
    lune.assign(1, c.A);
    for (std::size_t i = 0; i < path.Vertices.size(); ++i)
    {
      if (path.Arc[i] > path.SampleArc[c.Number] && path.Arc[i] < path.SampleArc[c.Number + 1])
      {
        lune.push_back(uv[i]);
      }
    }
    lune.push_back(c.B);
    if (lune.size() < 3)
    {
      continue;
    }
    PlanePoint low = lune[0], high = lune[0];
    for (const PlanePoint& q : lune)
    {
      low = { std::min(low[0], q[0]), std::min(low[1], q[1]) };
      high = { std::max(high[0], q[0]), std::max(high[1], q[1]) };
    }
    for (auto e = std::lower_bound(ends.begin(), ends.end(), std::make_pair(low, Index(-1)));
         e != ends.end() && e->first[0] <= high[0]; ++e)
    {
      if (e->second != c.SampleA && e->second != c.SampleB && e->first[1] >= low[1] && e->first[1] <= high[1] &&
        Inside(lune, e->first))
      {
        separate.insert({ c.Path, c.Number });
        break;
      }
    }
  }
}

/// The chords of a chart's boundary paths (`paths`, their ids) to separate
/// (as (path, chord index) pairs): those that cross another chord, and
/// those whose lune holds another chord's end (ChordsAroundSamples).
std::set<std::pair<int, std::size_t>> CrossingChords(const AtlasChart& chart, const std::vector<int>& paths,
  const SurfaceSamples& out, std::vector<std::vector<PlanePoint>>& uvOfPath)
{
  std::vector<Chord> chords;
  for (const int p : paths)
  {
    const SamplePath& path = out.Paths[p];
    uvOfPath[p] = PathInChart(path, chart);
    if (uvOfPath[p].size() < 2)
    {
      continue;
    }
    for (std::size_t j = 0; j + 1 < path.Samples.size(); ++j)
    {
      chords.push_back({ static_cast<int>(p), j, AtArc(path, uvOfPath[p], path.SampleArc[j]),
        AtArc(path, uvOfPath[p], path.SampleArc[j + 1]), path.Samples[j], path.Samples[j + 1] });
    }
  }
  std::sort(chords.begin(), chords.end(),
    [](const Chord& x, const Chord& y) { return std::min(x.A[0], x.B[0]) < std::min(y.A[0], y.B[0]); });
  std::set<std::pair<int, std::size_t>> crossing;
  for (std::size_t i = 0; i < chords.size(); ++i)
  {
    const Chord& x = chords[i];
    const double right = std::max(x.A[0], x.B[0]);
    for (std::size_t k = i + 1; k < chords.size() && std::min(chords[k].A[0], chords[k].B[0]) <= right; ++k)
    {
      const Chord& y = chords[k];
      const bool shareEnd = x.SampleA == y.SampleA || x.SampleA == y.SampleB || x.SampleB == y.SampleA ||
        x.SampleB == y.SampleB;
      if (!shareEnd && Cross(x.A, x.B, y.A, y.B))
      {
        crossing.insert({ x.Path, x.Number });
        crossing.insert({ y.Path, y.Number });
      }
    }
  }
  ChordsAroundSamples(out, uvOfPath, chords, crossing);
  return crossing;
}

/// The path vertex strictly between chord j's samples farthest from the
/// chord in the chart (-1: none).
std::ptrdiff_t FarthestVertex(const SamplePath& path, const std::vector<PlanePoint>& uv, std::size_t j)
{
  const PlanePoint a = AtArc(path, uv, path.SampleArc[j]), b = AtArc(path, uv, path.SampleArc[j + 1]);
  std::ptrdiff_t best = -1;
  double farthest = -1.0;
  for (std::size_t i = 0; i < path.Vertices.size(); ++i)
  {
    if (path.Arc[i] > path.SampleArc[j] && path.Arc[i] < path.SampleArc[j + 1])
    {
      const double d = std::abs(Orient(a, b, uv[i]));
      if (d > farthest)
      {
        farthest = d;
        best = static_cast<std::ptrdiff_t>(i);
      }
    }
  }
  return best;
}

} // namespace

std::int64_t SeparateCrossingChords(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  SurfaceSamples& out, bool keepCount)
{
  std::int64_t added = 0;
  std::vector<std::vector<int>> pathsOfChart(atlas.Charts.size()); // (a scan's many rims: not every path per chart)
  for (int p = 0; p < static_cast<int>(out.Paths.size()); ++p)
  {
    for (const int c : out.Paths[p].Charts)
    {
      if (c >= 0 && (pathsOfChart[c].empty() || pathsOfChart[c].back() != p))
      {
        pathsOfChart[c].push_back(p);
      }
    }
  }
  std::vector<std::vector<std::size_t>> interior(keepCount ? atlas.Charts.size() : 0); // per chart
  for (std::size_t s = 0; keepCount && s < out.Kind.size(); ++s)
  {
    if (out.Kind[s] == SampleKind::Interior && out.Chart[s] >= 0)
    {
      interior[out.Chart[s]].push_back(s);
    }
  }
  for (int round = 0; round < 16; ++round)
  {
    // (path, vertex) to sample, from every chart's crossings
    std::set<std::pair<int, std::size_t>> wanted;
    std::vector<std::vector<PlanePoint>> uvOfPath(out.Paths.size());
    for (int c = 0; c < static_cast<int>(atlas.Charts.size()); ++c)
    {
      for (const auto& [p, j] : CrossingChords(atlas.Charts[c], pathsOfChart[c], out, uvOfPath))
      {
        const std::ptrdiff_t i = FarthestVertex(out.Paths[p], uvOfPath[p], j);
        if (i >= 0)
        {
          wanted.insert({ p, static_cast<std::size_t>(i) });
        }
      }
    }
    const std::int64_t before = added;
    for (const auto& [p, i] : wanted)
    {
      SamplePath& path = out.Paths[p];
      const double arc = path.Arc[i];
      double w[3];
      const Index triangle = LocateOnPath(topology, path, arc, w);
      // (keepCount: the nearest interior sample of the path's charts takes the place)
      std::vector<std::size_t> candidates;
      for (const int c : path.Charts)
      {
        if (keepCount && c >= 0)
        {
          candidates.insert(candidates.end(), interior[c].begin(), interior[c].end());
        }
      }
      const std::size_t reused = NearestInterior(candidates, Point(points, path.Vertices[i]), out);
      if (keepCount && reused == out.Kind.size())
      {
        continue; // (no interior sample beside it to take the place of)
      }
      const std::size_t at =
        static_cast<std::size_t>(std::upper_bound(path.SampleArc.begin(), path.SampleArc.end(), arc) -
          path.SampleArc.begin());
      path.Samples.insert(path.Samples.begin() + static_cast<std::ptrdiff_t>(at),
        static_cast<Index>(keepCount ? reused : out.Kind.size()));
      path.SampleArc.insert(path.SampleArc.begin() + static_cast<std::ptrdiff_t>(at), arc);
      if (keepCount)
      {
        MoveSample(reused, SurfacePoint(topology, points, triangle, w), triangle, w, SampleKind::Boundary, out);
        out.Chart[reused] = -1;
      }
      else
      {
        AddSample(topology, points, triangle, w, SampleKind::Boundary, -1, out);
      }
      ++added;
    }
    if (added == before)
    {
      break;
    }
  }
  return added;
}

} // namespace beltrami
