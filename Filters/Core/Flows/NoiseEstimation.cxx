#include "Flows/NoiseEstimation.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace beltrami
{

namespace
{

/// One component's estimate (values with `stride` doubles per pixel).
double ComponentNoise(const PixelGrid& grid, const double* values, int stride)
{
  const Index w = grid.Width, h = grid.Height;
  const auto at = [&](Index x, Index y) { return values[(static_cast<std::size_t>(y) * w + x) * stride]; };
  std::vector<double> response, gradient;
  response.reserve(static_cast<std::size_t>(w - 2) * (h - 2));
  gradient.reserve(response.capacity());
  for (Index y = 1; y + 1 < h; ++y)
  {
    for (Index x = 1; x + 1 < w; ++x)
    {
      const double a = at(x - 1, y - 1), b = at(x, y - 1), c = at(x + 1, y - 1);
      const double d = at(x - 1, y), e = at(x, y), f = at(x + 1, y);
      const double g = at(x - 1, y + 1), i = at(x, y + 1), j = at(x + 1, y + 1);
      response.push_back(std::abs(a - 2 * b + c - 2 * d + 4 * e - 2 * f + g - 2 * i + j));
      const double gx = (c + 2 * f + j) - (a + 2 * d + g), gy = (g + 2 * i + j) - (a + 2 * b + c);
      gradient.push_back(gx * gx + gy * gy);
    }
  }
  // The half of the pixels with the smallest gradient (ties: all of them).
  std::vector<double> sorted = gradient;
  const std::size_t half = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + half, sorted.end());
  const double limit = sorted[half];
  std::vector<double> kept;
  kept.reserve(half + 1);
  for (std::size_t k = 0; k < response.size(); ++k)
  {
    if (gradient[k] <= limit)
    {
      kept.push_back(response[k]);
    }
  }
  const std::size_t middle = kept.size() / 2;
  std::nth_element(kept.begin(), kept.begin() + middle, kept.end());
  return kept[middle] / 0.6744897501960817 / 6.0;
}

} // namespace

double EstimateImageNoise(const PixelGrid& grid, int components, const double* values)
{
  if (grid.Width < 3 || grid.Height < 3 || components < 1 || !values)
  {
    return 0.0;
  }
  double sum = 0.0;
  for (int c = 0; c < components; ++c)
  {
    sum += ComponentNoise(grid, values + c, components);
  }
  return sum / components;
}

} // namespace beltrami
