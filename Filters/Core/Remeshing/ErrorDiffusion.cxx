#include "Remeshing/ErrorDiffusion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace beltrami
{

namespace
{

/// The diffusion weights (forward, down-behind, down) of Ostromoukhov's
/// paper at its key levels (grey levels 0-127 of 255; the upper half mirrors
/// the lower), unnormalised as published.
struct KeyLevel
{
  int Level;
  double Forward, DownBehind, Down;
};
constexpr std::array<KeyLevel, 18> KeyLevels = { { { 0, 13, 0, 5 }, { 1, 1300249, 0, 499250 },
  { 2, 213113, 287, 99357 }, { 3, 351854, 0, 199965 }, { 4, 801100, 0, 490999 },
  { 10, 704075, 297466, 303694 }, { 22, 46613, 31917, 21469 }, { 32, 47482, 30617, 21900 },
  { 44, 43024, 42131, 14826 }, { 64, 36411, 43219, 20369 }, { 72, 38477, 53843, 7678 },
  { 77, 40503, 51547, 7948 }, { 85, 35865, 34108, 30026 }, { 95, 34117, 36899, 28983 },
  { 102, 35464, 35049, 29485 }, { 107, 16477, 18810, 14712 }, { 112, 33360, 37954, 28685 },
  { 127, 35269, 36066, 28664 } } };

struct Weights
{
  float Forward, DownBehind, Down; ///< summing to 1
};

/// The normalised weights of the 256 grey levels (linear between the key
/// levels, as in the paper).
const std::array<Weights, 256>& WeightTable()
{
  static const std::array<Weights, 256> table = [] {
    std::array<Weights, 256> t{};
    for (int level = 0; level < 256; ++level)
    {
      const int l = std::min(level, 255 - level);
      std::size_t k = 0;
      while (k + 2 < KeyLevels.size() && KeyLevels[k + 1].Level <= l)
      {
        ++k;
      }
      const KeyLevel& a = KeyLevels[k];
      const KeyLevel& b = KeyLevels[k + 1];
      const double s = std::clamp(static_cast<double>(l - a.Level) / (b.Level - a.Level), 0.0, 1.0);
      const double f = a.Forward / (a.Forward + a.DownBehind + a.Down) * (1 - s) +
        b.Forward / (b.Forward + b.DownBehind + b.Down) * s;
      const double db = a.DownBehind / (a.Forward + a.DownBehind + a.Down) * (1 - s) +
        b.DownBehind / (b.Forward + b.DownBehind + b.Down) * s;
      t[level] = { static_cast<float>(f), static_cast<float>(db), static_cast<float>(1.0 - f - db) };
    }
    return t;
  }();
  return table;
}

/// A pixel's expected samples: its density times `scale`, in [0, 1] (NaN,
/// infinite and negative values: 0, as Halftone counts them).
inline double Level(double density, double scale)
{
  const double scaled = scale * density;
  return std::isfinite(scaled) && scaled > 0.0 ? std::min(scaled, 1.0) : 0.0;
}

/// Adds (change > 0) or removes (change < 0) |change| samples among the
/// free pixels of positive density, spread over the image in proportion to
/// the density (a 1D error diffusion over the candidates in scan order):
/// first where no two samples end up side by side (added: pixels with no
/// sample beside them; removed: samples with one beside them), then anywhere.
void AdjustCount(const double* density, double scale, int width, int height, const std::uint8_t* roles,
  std::int64_t change, std::vector<std::uint8_t>& samples)
{
  const bool add = change > 0;
  const std::uint8_t from = add ? 0 : 1;
  const std::size_t pixels = samples.size();
  const auto crowded = [&](std::size_t p) {
    const int x = static_cast<int>(p % width), y = static_cast<int>(p / width);
    return (x > 0 && samples[p - 1]) || (x + 1 < width && samples[p + 1]) || (y > 0 && samples[p - width]) ||
      (y + 1 < height && samples[p + width]);
  };
  const auto candidate = [&](std::size_t p, int round) {
    const bool free = !roles || static_cast<PixelRole>(roles[p]) == PixelRole::Free;
    return free && Level(density[p], scale) > 0.0 && samples[p] == from && (round == 2 || crowded(p) != add);
  };
  // Expected share of a candidate: added samples go where the density is
  // (over the free pixels left there), removed ones evenly over the samples.
  const auto weight = [&](std::size_t p) {
    const double d = Level(density[p], scale);
    return add ? d / std::max(1e-9, 1.0 - d) : 1.0;
  };
  std::int64_t left = std::abs(change);
  for (int round = 0; round < 3 && left > 0; ++round)
  {
    double total = 0.0;
    for (std::size_t p = 0; p < pixels; ++p)
    {
      total += candidate(p, round) ? weight(p) : 0.0;
    }
    // Round 0: the share of `left` the eligible pixels can take in
    // proportion; round 1: all of the rest among them; round 2: anywhere.
    double carried = 0.0;
    const double factor = total > 0.0 ? static_cast<double>(left) / total : 0.0;
    for (std::size_t p = 0; p < pixels && left > 0; ++p)
    {
      if (candidate(p, round))
      {
        carried += round == 2 ? 1.0 : std::min(1.0, factor * weight(p));
        if (carried >= 0.5)
        {
          samples[p] = 1 - from;
          carried -= 1.0;
          --left;
        }
      }
    }
  }
}

/// Moves every sample that has another beside it (left, right, above,
/// below) to the nearest free pixel of positive density within two pixels
/// where it has none: the count and the local density stay, the rare
/// clusters that error diffusion leaves along sides and at simple levels go.
void SeparateNeighbours(
  const double* density, int width, int height, const std::uint8_t* roles, std::vector<std::uint8_t>& samples)
{
  const auto at = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < width && y < height && samples[static_cast<std::size_t>(y) * width + x];
  };
  const auto crowded = [&](int x, int y) { return at(x - 1, y) || at(x + 1, y) || at(x, y - 1) || at(x, y + 1); };
  for (int y = 0; y < height; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      if (!samples[p] || !crowded(x, y))
      {
        continue;
      }
      samples[p] = 0;
      int best = -1, bestDistance = 9;
      for (int dy = -2; dy <= 2; ++dy)
      {
        for (int dx = -2; dx <= 2; ++dx)
        {
          const int qx = x + dx, qy = y + dy, distance = dx * dx + dy * dy;
          const std::size_t q = static_cast<std::size_t>(qy) * width + qx;
          if (distance < bestDistance && qx >= 0 && qy >= 0 && qx < width && qy < height && !samples[q] &&
            Level(density[q], 1.0) > 0.0 && (!roles || static_cast<PixelRole>(roles[q]) == PixelRole::Free) && !crowded(qx, qy))
          {
            best = static_cast<int>(q);
            bestDistance = distance;
          }
        }
      }
      samples[best >= 0 ? static_cast<std::size_t>(best) : p] = 1;
    }
  }
}

} // namespace

std::int64_t DiffuseErrors(
  const double* density, int width, int height, double scale, const std::uint8_t* roles, std::uint8_t* samples)
{
  const std::array<Weights, 256>& table = WeightTable();
  // Two rows of incoming error, one pixel of padding on each side.
  std::vector<double> current(width + 2, 0.0), next(width + 2, 0.0);
  std::int64_t count = 0;
  // Rows 0 .. height-1 scan the flipped copy (image row height-1-r), rows
  // height .. 2 height-1 the image itself; only the latter are kept.
  for (int r = 0; r < 2 * height; ++r)
  {
    const int row = r < height ? height - 1 - r : r - height;
    const bool keep = r >= height;
    const bool forward = (r % 2) == 0;
    const int step = forward ? 1 : -1;
    const bool lastRow = r + 1 == 2 * height;
    for (int k = 0; k < width; ++k)
    {
      const int x = forward ? k : width - 1 - k;
      const std::size_t p = static_cast<std::size_t>(row) * width + x;
      const PixelRole role = roles ? static_cast<PixelRole>(roles[p]) : PixelRole::Free;
      const double d = Level(density[p], scale);
      const double v = d + current[x + 1];
      current[x + 1] = 0.0;
      bool sample = false;
      double error = 0.0;
      switch (role)
      {
        case PixelRole::Free:
          sample = v >= 0.5;
          error = v - (sample ? 1.0 : 0.0);
          break;
        case PixelRole::Sample:
          sample = true;
          error = v - 1.0;
          break;
        case PixelRole::Excluded:
          error = v;
          break;
        case PixelRole::Outside:
          break;
      }
      if (keep)
      {
        samples[p] = sample ? 1 : 0;
        count += sample;
      }
      if (error == 0.0)
      {
        continue;
      }
      // The weights of the pixel's level.  At the end of a row the forward
      // share goes down, where the next row starts (dropped, it would leave
      // the sides 3-7% short of samples); the share behind the row's start
      // is dropped (sent down too, it clusters samples along the sides).
      const Weights& w = table[static_cast<int>(std::lround(255.0 * d))];
      const bool rowEnd = x + step < 0 || x + step >= width;
      if (!rowEnd)
      {
        current[x + step + 1] += w.Forward * error;
      }
      if (!lastRow)
      {
        if (x - step >= 0 && x - step < width)
        {
          next[x - step + 1] += w.DownBehind * error;
        }
        next[x + 1] += (rowEnd ? w.Down + w.Forward : w.Down) * error;
      }
    }
    std::swap(current, next);
  }
  return count;
}

HalftoneResult Halftone(const double* density, int width, int height, std::int64_t count, const std::uint8_t* roles)
{
  HalftoneResult result;
  const std::size_t pixels = static_cast<std::size_t>(std::max(0, width)) * std::max(0, height);
  std::int64_t forced = 0, capacity = 0;
  double mass = 0.0;
  for (std::size_t p = 0; p < pixels; ++p)
  {
    const PixelRole role = roles ? static_cast<PixelRole>(roles[p]) : PixelRole::Free;
    const double d = Level(density[p], 1.0) > 0.0 ? density[p] : 0.0; // finite and positive
    forced += role == PixelRole::Sample;
    capacity += role == PixelRole::Sample || (role == PixelRole::Free && d > 0.0);
    mass += role == PixelRole::Free ? d : 0.0;
  }
  if (count < forced || count > capacity)
  {
    result.Error = "cannot place " + std::to_string(count) + " samples: the image holds between " +
      std::to_string(forced) + " (the forced ones) and " + std::to_string(capacity) +
      " (one per pixel of positive density)";
    return result;
  }
  result.Samples.assign(pixels, 0);
  const std::int64_t wanted = count - forced;
  double scale = mass > 0.0 ? wanted / mass : 0.0, lo = 0.0, hi = HUGE_VAL;
  // Within 1% the count is met by the adjustment below: scaling further
  // disturbs the regular patterns of simple levels (1/4, 1/2) that a few
  // added or removed samples leave intact.
  const std::int64_t tolerance = count / 100;
  std::int64_t got = 0;
  // Secant-like steps on the scale, kept inside the bracket found so far
  // (the count grows with the scale, not always strictly).
  for (result.Passes = 1;; ++result.Passes)
  {
    got = DiffuseErrors(density, width, height, scale, roles, result.Samples.data());
    if (std::abs(got - count) <= tolerance || wanted == 0 || result.Passes == 12)
    {
      break;
    }
    (got < count ? lo : hi) = scale;
    double next = scale * static_cast<double>(wanted) / std::max<std::int64_t>(1, got - forced);
    if (!(next > lo && next < hi))
    {
      next = std::isfinite(hi) ? 0.5 * (lo + hi) : 2.0 * scale;
    }
    scale = next;
  }
  result.Scale = scale;
  AdjustCount(density, scale, width, height, roles, count - got, result.Samples);
  SeparateNeighbours(density, width, height, roles, result.Samples);
  result.Adjusted = std::abs(count - got);
  result.Count = count;
  return result;
}

std::vector<double> DiffuseAlongPath(const std::vector<double>& cumulative)
{
  std::vector<double> positions;
  if (cumulative.size() < 2)
  {
    return positions;
  }
  const double total = cumulative.back();
  const std::int64_t count = std::llround(total);
  std::size_t node = 0;
  for (std::int64_t k = 0; k < count; ++k)
  {
    const double at = k + 0.5; // at most total: count <= total + 1/2
    while (node + 2 < cumulative.size() && cumulative[node + 1] < at)
    {
      ++node;
    }
    const double span = cumulative[node + 1] - cumulative[node];
    positions.push_back(node + (span > 0.0 ? std::clamp((at - cumulative[node]) / span, 0.0, 1.0) : 0.0));
  }
  return positions;
}

} // namespace beltrami
