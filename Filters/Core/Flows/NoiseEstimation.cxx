#include "Flows/NoiseEstimation.h"

#include "Support/Parallel.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace beltrami
{

namespace
{

/// At most about this many samples are used, all components together (rows,
/// planes or vertices taken at a regular stride beyond): medians of the kept
/// halves of 2^18 samples have a relative standard error of about
/// 1.17 / sqrt(2^17) = 0.3%, far below the estimator's bias on real data,
/// and an image of a megapixel in colour spent 45 ms (half its flow's
/// set-up) selecting from all.
constexpr std::int64_t SampleBudget = std::int64_t(1) << 18;

/// The stride that keeps `count` samples of `components` each within the
/// budget.
std::int64_t StrideFor(double count, int components)
{
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(count * components / SampleBudget)));
}

/// Responses and gradients of the samples of one component.
struct Samples
{
  std::vector<double> Response; ///< |high-pass response| / its noise gain
  std::vector<double> Gradient; ///< any measure that grows with the gradient
};

/// The samples of `rows` sampled rows of `width` each, in parallel and in
/// the order of a serial loop: sample(row, x, response, gradient).
template <typename Sample>
void SampleRows(std::int64_t rows, std::int64_t width, int numThreads, Samples& s, Sample&& sample)
{
  s.Response.resize(static_cast<std::size_t>(rows * width));
  s.Gradient.resize(s.Response.size());
  ParallelFor(rows, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      for (std::int64_t x = 0; x < width; ++x)
      {
        sample(r, x, s.Response[r * width + x], s.Gradient[r * width + x]);
      }
    }
  }, {}, 0, 1);
}

/// The k-th smallest of `values` (0-based; of all processes' with `split`).
double NthSmallest(std::vector<double>& values, std::int64_t k, const Partition* split)
{
  if (split)
  {
    return split->NthSmallest(values, k);
  }
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

/// The median response over the half of the samples with the smallest
/// gradient, as a standard deviation (0 without samples).  split: the
/// samples of all processes together (collective).
double RobustDeviation(Samples& s, const Partition* split)
{
  const auto total = [&](std::size_t count) {
    return static_cast<std::int64_t>(split ? split->Sum(static_cast<double>(count)) : count);
  };
  const std::int64_t count = total(s.Response.size());
  if (count == 0)
  {
    return 0.0;
  }
  std::vector<double> sorted = s.Gradient;
  const double limit = NthSmallest(sorted, count / 2, split);
  std::vector<double> kept;
  kept.reserve(s.Response.size() / 2 + 1);
  for (std::size_t k = 0; k < s.Response.size(); ++k)
  {
    if (s.Gradient[k] <= limit) // ties: all of them
    {
      kept.push_back(s.Response[k]);
    }
  }
  return NthSmallest(kept, total(kept.size()) / 2, split) / 0.6744897501960817;
}

/// The mean over the components of one component's estimate.
template <typename Component>
double MeanOverComponents(int components, Component&& component, const Partition* split = nullptr)
{
  double sum = 0.0;
  for (int c = 0; c < components; ++c)
  {
    Samples s;
    component(c, s);
    sum += RobustDeviation(s, split);
  }
  return sum / components;
}

} // namespace

namespace
{

/// The samples of a piece of a split grid (GridPiece): the samples it owns
/// inside the whole grid (a margin of 1), on the rows (y, z) the whole grid
/// samples at `stride` (its interior rows numbered y fastest), in any order
/// (the estimate takes order statistics); sample(x, y, z, response,
/// gradient) at local coordinates.
template <typename Sample>
void SamplePiece(const GridPiece& piece, std::int64_t w, std::int64_t h, std::int64_t d, std::int64_t stride,
  Samples& s, Sample&& sample)
{
  const std::int64_t* whole = piece.Whole;
  const std::int64_t* origin = piece.Origin;
  const bool volume = whole[2] > 1;
  const auto inside = [&](std::int64_t local, int a) {
    const std::int64_t g = local + origin[a];
    return g >= 1 && g <= whole[a] - 2;
  };
  for (std::int64_t z = 0; z < d; ++z)
  {
    for (std::int64_t y = 0; y < h; ++y)
    {
      const std::int64_t row = (y + origin[1] - 1) + (volume ? (z + origin[2] - 1) * (whole[1] - 2) : 0);
      if (!inside(y, 1) || (volume && !inside(z, 2)) || row % stride != 0)
      {
        continue;
      }
      for (std::int64_t x = 0; x < w; ++x)
      {
        if (inside(x, 0) && piece.Split->IsOwned(static_cast<Index>((z * h + y) * w + x)))
        {
          double response = 0.0, gradient = 0.0;
          sample(x, y, z, response, gradient);
          s.Response.push_back(response);
          s.Gradient.push_back(gradient);
        }
      }
    }
  }
}

} // namespace

double EstimateImageNoise(
  const PixelGrid& grid, int components, const double* values, int numThreads, const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process joins, an empty piece too)
  const std::int64_t W = split ? piece->Whole[0] : grid.Width, H = split ? piece->Whole[1] : grid.Height;
  if (W < 3 || H < 3 || components < 1 || (!values && !split))
  {
    return 0.0;
  }
  const Index w = grid.Width, h = grid.Height;
  const std::int64_t stride = StrideFor(static_cast<double>(W - 2) * (H - 2), components); // rows
  return MeanOverComponents(components, [&](int comp, Samples& s) {
    const auto at = [&](Index x, Index y) {
      return values[(static_cast<std::size_t>(y) * w + x) * components + comp];
    };
    const auto sample = [&](Index x, Index y, double& response, double& gradient) {
      const double a = at(x - 1, y - 1), b = at(x, y - 1), c = at(x + 1, y - 1);
      const double d = at(x - 1, y), e = at(x, y), f = at(x + 1, y);
      const double g = at(x - 1, y + 1), i = at(x, y + 1), j = at(x + 1, y + 1);
      response = std::abs(a - 2 * b + c - 2 * d + 4 * e - 2 * f + g - 2 * i + j) / 6.0;
      const double gx = (c + 2 * f + j) - (a + 2 * d + g), gy = (g + 2 * i + j) - (a + 2 * b + c);
      gradient = gx * gx + gy * gy;
    };
    if (split)
    {
      SamplePiece(*piece, w, h, 1, stride, s,
        [&](std::int64_t x, std::int64_t y, std::int64_t, double& response, double& gradient) {
          sample(static_cast<Index>(x), static_cast<Index>(y), response, gradient);
        });
      return;
    }
    SampleRows((h - 2 + stride - 1) / stride, w - 2, numThreads, s,
      [&](std::int64_t row, std::int64_t column, double& response, double& gradient) {
        sample(static_cast<Index>(1 + column), static_cast<Index>(1 + row * stride), response, gradient);
      });
  }, split ? piece->Split : nullptr);
}

double EstimateVolumeNoise(
  const VoxelGrid& grid, int components, const double* values, int numThreads, const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process joins, an empty piece too)
  const std::int64_t W = split ? piece->Whole[0] : grid.Width, H = split ? piece->Whole[1] : grid.Height,
                     D = split ? piece->Whole[2] : grid.Depth;
  if (W < 3 || H < 3 || D < 3 || components < 1 || (!values && !split))
  {
    return 0.0;
  }
  const std::int64_t w = grid.Width, h = grid.Height, d = grid.Depth;
  const double gain = std::sqrt(216.0);
  const double line[3] = { 1.0, -2.0, 1.0 };
  const std::int64_t rows = (H - 2) * (D - 2);
  const std::int64_t stride = StrideFor(static_cast<double>(W - 2) * rows, components); // rows (y, z)
  return MeanOverComponents(components, [&](int comp, Samples& s) {
    const auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      return values[((z * h + y) * w + x) * components + comp];
    };
    const auto sample = [&](std::int64_t x, std::int64_t y, std::int64_t z, double& response, double& gradient) {
      double r = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        for (int j = 0; j < 3; ++j)
        {
          const double c = line[k] * line[j];
          for (int i = 0; i < 3; ++i)
          {
            r += c * line[i] * at(x + i - 1, y + j - 1, z + k - 1);
          }
        }
      }
      const double gx = at(x + 1, y, z) - at(x - 1, y, z), gy = at(x, y + 1, z) - at(x, y - 1, z),
                   gz = at(x, y, z + 1) - at(x, y, z - 1);
      response = std::abs(r) / gain;
      gradient = gx * gx + gy * gy + gz * gz;
    };
    if (split)
    {
      SamplePiece(*piece, w, h, d, stride, s, sample);
      return;
    }
    SampleRows((rows + stride - 1) / stride, w - 2, numThreads, s,
      [&](std::int64_t sampled, std::int64_t column, double& response, double& gradient) {
        const std::int64_t row = sampled * stride;
        sample(1 + column, 1 + row % (h - 2), 1 + row / (h - 2), response, gradient);
      });
  }, split ? piece->Split : nullptr);
}

double EstimateGraphNoise(Index size, const std::int64_t* offsets, const Index* neighbors, const double* points,
  int components, const double* values, const std::uint8_t* skip, const Partition* split)
{
  if (!split && (size <= 0 || !values || !offsets || !neighbors || !points))
  {
    return 0.0; // (a process of a split run joins the sums with no samples)
  }
  if (components < 1)
  {
    return 0.0;
  }
  std::int64_t counted = 0;
  // Rows at a regular stride of the (global) numbering beyond the budget.
  const std::int64_t stride = StrideFor(split ? static_cast<double>(split->TotalRows()) : size, components);
  const auto sampled = [&](Index i) {
    return split ? split->IsOwned(i) && split->GlobalRow(i) % stride == 0 : i % stride == 0;
  };
  const double estimate = MeanOverComponents(components, [&](int comp, Samples& s) {
    for (Index i = 0; i < size; i += split ? 1 : stride)
    {
      const std::int64_t b = offsets[i], e = offsets[i + 1];
      const double n = static_cast<double>(e - b);
      if (!sampled(i) || n < 3 || (skip && skip[i]))
      {
        continue;
      }
      double mean = 0.0, centre[3] = { 0.0, 0.0, 0.0 };
      for (std::int64_t k = b; k < e; ++k)
      {
        mean += values[static_cast<std::size_t>(neighbors[k]) * components + comp];
        for (int a = 0; a < 3; ++a)
        {
          centre[a] += points[3 * static_cast<std::size_t>(neighbors[k]) + a];
        }
      }
      mean /= n;
      double moment[3] = { 0.0, 0.0, 0.0 }, spread = 0.0;
      for (std::int64_t k = b; k < e; ++k)
      {
        const double df = values[static_cast<std::size_t>(neighbors[k]) * components + comp] - mean;
        for (int a = 0; a < 3; ++a)
        {
          const double dx = points[3 * static_cast<std::size_t>(neighbors[k]) + a] - centre[a] / n;
          moment[a] += dx * df;
          spread += dx * dx;
        }
      }
      const double r = values[static_cast<std::size_t>(i) * components + comp] - mean;
      s.Response.push_back(std::abs(r) / std::sqrt(1.0 + 1.0 / n));
      s.Gradient.push_back(
        spread > 0.0 ? (moment[0] * moment[0] + moment[1] * moment[1] + moment[2] * moment[2]) / (spread * spread)
                     : 0.0);
    }
    counted = static_cast<std::int64_t>(s.Response.size());
  }, split);
  return (split ? split->Sum(static_cast<double>(counted)) : counted) >= 8 ? estimate : 0.0;
}

} // namespace beltrami
