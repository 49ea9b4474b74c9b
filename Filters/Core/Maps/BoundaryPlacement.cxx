#include "Maps/BoundaryPlacement.h"

#include <array>
#include <cmath>

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

void PlaceBoundaryLoop(const std::vector<Index>& loop, const double* points,
  ParameterizationBoundary shape, BoundarySpacing spacing, double* uv)
{
  const std::size_t n = loop.size();
  std::vector<double> t(n + 1, 0.0); // normalised parameter along the loop
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
  // Square: the corners are the vertices nearest to the quarters of the
  // length (distinct, in order); each side is spaced like the loop.
  std::array<std::size_t, 5> corner{};
  corner[0] = 0;
  corner[4] = n;
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
  static const double cornerUV[5][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 }, { 0, 0 } };
  for (int side = 0; side < 4; ++side)
  {
    const double t0 = t[corner[side]], t1 = t[corner[side + 1]];
    for (std::size_t k = corner[side]; k < corner[side + 1]; ++k)
    {
      const double s = t1 > t0 ? (t[k] - t0) / (t1 - t0) : 0.0;
      uv[2 * loop[k]] = (1 - s) * cornerUV[side][0] + s * cornerUV[side + 1][0];
      uv[2 * loop[k] + 1] = (1 - s) * cornerUV[side][1] + s * cornerUV[side + 1][1];
    }
  }
}

} // namespace beltrami
