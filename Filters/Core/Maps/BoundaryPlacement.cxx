#include "Maps/BoundaryPlacement.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace beltrami
{

double LoopLength(const std::vector<Index>& loop, const double* points)
{
  double length = 0.0;
  for (std::size_t k = 0; k < loop.size(); ++k)
  {
    length += (Point(points, loop[(k + 1) % loop.size()]) - Point(points, loop[k])).norm();
  }
  return length;
}

std::size_t LongestLoop(const std::vector<std::vector<Index>>& loops, const double* points)
{
  std::size_t outer = 0;
  for (std::size_t k = 1; k < loops.size(); ++k)
  {
    if (LoopLength(loops[k], points) > LoopLength(loops[outer], points))
    {
      outer = k;
    }
  }
  return outer;
}

std::vector<double> LoopParameter(const std::vector<Index>& loop, const double* points, BoundarySpacing spacing)
{
  const std::size_t n = loop.size();
  std::vector<double> t(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k)
  {
    t[k + 1] = t[k] +
      (spacing == BoundarySpacing::Uniform
          ? 1.0
          : (Point(points, loop[(k + 1) % n]) - Point(points, loop[k])).norm());
  }
  const double total = t[n];
  for (double& value : t)
  {
    value = total > 0.0 ? value / total : 0.0;
  }
  return t;
}

namespace
{

/// The first vertex and those nearest to the quarters of the length
/// (distinct, ascending; n >= 4).
std::array<std::size_t, 4> QuarterCorners(const std::vector<double>& t)
{
  const std::size_t n = t.size() - 1;
  std::array<std::size_t, 4> corner{};
  for (int q = 1; q < 4; ++q)
  {
    const std::size_t lo = corner[q - 1] + 1, hi = n - static_cast<std::size_t>(4 - q);
    std::size_t best = lo;
    for (std::size_t k = lo; k <= hi; ++k)
    {
      if (std::abs(t[k] - 0.25 * q) < std::abs(t[best] - 0.25 * q))
      {
        best = k;
      }
    }
    corner[q] = best;
  }
  return corner;
}

} // namespace

void PlaceBoundaryLoop(const std::vector<Index>& loop, const double* points,
  ParameterizationBoundary shape, BoundarySpacing spacing, double* uv, const std::array<std::size_t, 4>* corners)
{
  const std::size_t n = loop.size();
  const std::vector<double> t = LoopParameter(loop, points, spacing);
  if (shape == ParameterizationBoundary::Circle)
  {
    for (std::size_t k = 0; k < n; ++k)
    {
      const double a = 2.0 * M_PI * t[k];
      uv[2 * loop[k]] = 0.5 + 0.5 * std::cos(a);
      uv[2 * loop[k] + 1] = 0.5 + 0.5 * std::sin(a);
    }
    return;
  }
  // Square: side s runs from corner s to corner s + 1 (the last one wraps
  // around the loop's start), spaced like the loop.
  const std::array<std::size_t, 4> corner = corners ? *corners : QuarterCorners(t);
  const auto along = [&](std::size_t k) { return k >= n ? 1.0 + t[k - n] : t[k]; };
  static const double cornerUV[5][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 }, { 0, 0 } };
  for (int side = 0; side < 4; ++side)
  {
    const std::size_t k0 = corner[side], k1 = side < 3 ? corner[side + 1] : corner[0] + n;
    const double t0 = along(k0), t1 = along(k1);
    for (std::size_t k = k0; k < k1; ++k)
    {
      const double s = t1 > t0 ? (along(k) - t0) / (t1 - t0) : 0.0;
      uv[2 * loop[k % n]] = (1 - s) * cornerUV[side][0] + s * cornerUV[side + 1][0];
      uv[2 * loop[k % n] + 1] = (1 - s) * cornerUV[side][1] + s * cornerUV[side + 1][1];
    }
  }
}

namespace
{

/// What ChooseSquareCorners weighs: per loop position, the surface's angle
/// there and whether it is the tip of an ear (a single triangle); the
/// triangles with all three vertices on the loop, as loop positions.
struct LoopCorners
{
  std::vector<double> Angle;
  std::vector<std::uint8_t> Tip;
  std::vector<std::array<std::size_t, 3>> AllOnLoop;

  LoopCorners(const MeshTopology& topology, const double* points, const std::vector<Index>& loop)
    : Angle(loop.size(), 0.0)
    , Tip(loop.size(), 0)
  {
    std::vector<Index> position(topology.NumberOfVertices(), -1);
    for (std::size_t k = 0; k < loop.size(); ++k)
    {
      position[loop[k]] = static_cast<Index>(k);
      Tip[k] = topology.Valence(loop[k]) == 1;
    }
    const IndexArray& tri = topology.TriangleList();
    for (Index f = 0; f < topology.NumberOfTriangles(); ++f)
    {
      const Index* v = &tri[3 * static_cast<std::size_t>(f)];
      int on = 0;
      for (int c = 0; c < 3; ++c)
      {
        const Index k = position[v[c]];
        if (k < 0)
        {
          continue;
        }
        ++on;
        const Vec3 p = Point(points, v[c]);
        const Vec3 a = Point(points, v[(c + 1) % 3]) - p, b = Point(points, v[(c + 2) % 3]) - p;
        Angle[k] += std::atan2(a.cross(b).norm(), a.dot(b));
      }
      if (on == 3)
      {
        AllOnLoop.push_back({ { static_cast<std::size_t>(position[v[0]]), static_cast<std::size_t>(position[v[1]]),
          static_cast<std::size_t>(position[v[2]]) } });
      }
    }
  }

  /// True when a triangle has its three vertices on one side.
  bool Flattens(const std::array<std::size_t, 4>& c) const
  {
    const auto onSide = [&](std::size_t p, int s) {
      return s < 3 ? (c[s] <= p && p <= c[s + 1]) : (p >= c[3] || p <= c[0]);
    };
    for (const auto& f : AllOnLoop)
    {
      for (int s = 0; s < 4; ++s)
      {
        if (onSide(f[0], s) && onSide(f[1], s) && onSide(f[2], s))
        {
          return true;
        }
      }
    }
    return false;
  }
};

} // namespace

std::array<std::size_t, 4> ChooseSquareCorners(
  const MeshTopology& topology, const double* points, const std::vector<Index>& loop)
{
  const std::size_t n = loop.size();
  const std::vector<double> t = LoopParameter(loop, points, BoundarySpacing::ArcLength);
  if (n < 4)
  {
    return { { 0, 0, 0, 0 } };
  }
  const LoopCorners loopCorners(topology, points, loop);
  // Candidates: every ear tip, the sharpest turns, and the quarters of the
  // length from the sharpest one.
  std::vector<std::size_t> byAngle(n), candidates;
  std::iota(byAngle.begin(), byAngle.end(), 0);
  const std::size_t sharp = std::min<std::size_t>(n, 16);
  std::partial_sort(byAngle.begin(), byAngle.begin() + sharp, byAngle.end(),
    [&](std::size_t a, std::size_t b) { return loopCorners.Angle[a] < loopCorners.Angle[b]; });
  candidates.assign(byAngle.begin(), byAngle.begin() + sharp);
  std::size_t tips = 0;
  for (std::size_t k = 0; k < n; ++k)
  {
    if (loopCorners.Tip[k])
    {
      candidates.push_back(k);
      ++tips;
    }
  }
  for (int q = 1; q < 4; ++q)
  {
    const double target = std::fmod(t[byAngle[0]] + 0.25 * q, 1.0);
    candidates.push_back(static_cast<std::size_t>(
      std::min_element(t.begin(), t.end() - 1,
        [&](double a, double b) { return std::abs(a - target) < std::abs(b - target); }) - t.begin()));
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  // The best set of four: the smallest sum of angles (in half turns) plus
  // the squared misfit of the sides' lengths to a quarter (x 4), with every
  // tip a corner and no triangle flat on a side.
  std::array<std::size_t, 4> best = QuarterCorners(t);
  double bestCost = HUGE_VAL;
  const std::size_t m = candidates.size();
  if (tips > 4)
  {
    return best;
  }
  std::array<std::size_t, 4> c{};
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      for (std::size_t k = j + 1; k < m; ++k)
        for (std::size_t l = k + 1; l < m; ++l)
        {
          c = { { candidates[i], candidates[j], candidates[k], candidates[l] } };
          std::size_t tipsIn = 0;
          double cost = 0.0;
          for (int s = 0; s < 4; ++s)
          {
            tipsIn += loopCorners.Tip[c[s]];
            const double side = s < 3 ? t[c[s + 1]] - t[c[s]] : 1.0 - t[c[3]] + t[c[0]];
            cost += loopCorners.Angle[c[s]] / M_PI + (4.0 * side - 1.0) * (4.0 * side - 1.0);
          }
          if (tipsIn == tips && cost < bestCost && !loopCorners.Flattens(c))
          {
            bestCost = cost;
            best = c;
          }
        }
  return best;
}

} // namespace beltrami
