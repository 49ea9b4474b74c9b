// Halftoning with an exact sample count (thesis section 4.3.2).
#include "Remeshing/ErrorDiffusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

using namespace beltrami;

namespace
{

std::vector<double> Image(int n, const std::function<double(double, double)>& f)
{
  std::vector<double> image(static_cast<std::size_t>(n) * n);
  for (int y = 0; y < n; ++y)
  {
    for (int x = 0; x < n; ++x)
    {
      image[static_cast<std::size_t>(y) * n + x] = f((x + 0.5) / n, (y + 0.5) / n);
    }
  }
  return image;
}

std::int64_t Count(const std::vector<std::uint8_t>& samples)
{
  std::int64_t c = 0;
  for (std::uint8_t s : samples)
  {
    c += s;
  }
  return c;
}

/// A curvature-like map: two sharp ridges over a flat floor.
double Ridges(double x, double y)
{
  return 0.05 + std::exp(-std::pow((x - 0.3) / 0.03, 2)) + 0.5 * std::exp(-std::pow((x + y - 1.2) / 0.05, 2));
}

} // namespace

TEST(ErrorDiffusion, ExactCountOnConstantRampAndCurvatureMaps)
{
  const int n = 256;
  const std::vector<std::pair<const char*, std::function<double(double, double)>>> maps = {
    { "constant", [](double, double) { return 1.0; } }, { "ramp", [](double x, double) { return x; } },
    { "ridges", Ridges } };
  for (const auto& [name, f] : maps)
  {
    const std::vector<double> density = Image(n, f);
    for (std::int64_t count : { 1, 100, 1000, 6000, 20000, 40000 })
    {
      const HalftoneResult r = Halftone(density.data(), n, n, count);
      ASSERT_EQ(r.Error, "") << name;
      EXPECT_EQ(r.Count, count) << name;
      EXPECT_EQ(Count(r.Samples), count) << name << " " << count;
      // The scale finds the count to 1%, the adjustment the rest.
      EXPECT_LE(r.Adjusted, std::max<std::int64_t>(1, count / 100)) << name << " " << count;
      if (count == 6000)
      {
        std::printf("%-8s %5lld samples: %d passes, %lld adjusted\n", name, static_cast<long long>(count), r.Passes,
          static_cast<long long>(r.Adjusted));
      }
    }
  }
}

TEST(ErrorDiffusion, BlueNoiseNoTwoSamplesAdjacentOnAConstantMap)
{
  const int n = 256;
  for (double level : { 0.25, 0.2, 0.1, 0.02 })
  {
    const std::vector<double> density = Image(n, [level](double, double) { return level; });
    const HalftoneResult r = Halftone(density.data(), n, n, std::llround(level * n * n));
    ASSERT_EQ(r.Error, "");
    int adjacent = 0;
    for (int y = 0; y < n; ++y)
    {
      for (int x = 0; x < n; ++x)
      {
        const std::size_t p = static_cast<std::size_t>(y) * n + x;
        adjacent += r.Samples[p] && x + 1 < n && r.Samples[p + 1];
        adjacent += r.Samples[p] && y + 1 < n && r.Samples[p + n];
      }
    }
    EXPECT_EQ(adjacent, 0) << "density " << level;
  }
}

TEST(ErrorDiffusion, LocalDensityFollowsTheMapFromTheFirstRow)
{
  // A ramp across and a low constant density: the samples of every band of
  // columns and of the first rows (where a plain scan leaves a "dead zone")
  // follow the map.
  const int n = 256;
  const std::vector<double> ramp = Image(n, [](double x, double) { return 0.02 + 0.3 * x; });
  double total = 0.0;
  for (double d : ramp)
  {
    total += d;
  }
  const std::int64_t count = std::llround(total);
  const HalftoneResult r = Halftone(ramp.data(), n, n, count);
  ASSERT_EQ(r.Error, "");
  const int bands = 8, width = n / bands;
  double worst = 0.0;
  for (int b = 0; b < bands; ++b)
  {
    double expected = 0.0, got = 0.0;
    for (int y = 0; y < n; ++y)
    {
      for (int x = b * width; x < (b + 1) * width; ++x)
      {
        expected += ramp[static_cast<std::size_t>(y) * n + x];
        got += r.Samples[static_cast<std::size_t>(y) * n + x];
      }
    }
    worst = std::max(worst, std::abs(got - expected) / expected);
  }
  EXPECT_LT(worst, 0.02);
  const std::vector<double> sparse = Image(n, [](double, double) { return 0.01; });
  const HalftoneResult s = Halftone(sparse.data(), n, n, std::llround(0.01 * n * n));
  std::int64_t top = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(n) * n / 16; ++p)
  {
    top += s.Samples[p];
  }
  const double expectedTop = 0.01 * n * n / 16;
  std::printf("ramp bands within %.2f%%; first 16 rows at density 0.01: %lld samples (expected %.0f)\n",
    100 * worst, static_cast<long long>(top), expectedTop);
  EXPECT_NEAR(static_cast<double>(top), expectedTop, 0.2 * expectedTop);
}

TEST(ErrorDiffusion, ForcedExcludedAndOutsidePixels)
{
  const int n = 128;
  const std::vector<double> density = Image(n, [](double, double) { return 0.2; });
  std::vector<std::uint8_t> roles(density.size(), static_cast<std::uint8_t>(PixelRole::Free));
  for (int x = 0; x < n; ++x)
  {
    roles[64 * n + x] = static_cast<std::uint8_t>(PixelRole::Excluded); // a feature line
    roles[static_cast<std::size_t>(x) * n] = static_cast<std::uint8_t>(PixelRole::Outside); // left column
  }
  for (int k = 0; k < 10; ++k)
  {
    roles[static_cast<std::size_t>(10 + 10 * k) * n + 30] = static_cast<std::uint8_t>(PixelRole::Sample);
  }
  const HalftoneResult r = Halftone(density.data(), n, n, 3000, roles.data());
  ASSERT_EQ(r.Error, "");
  EXPECT_EQ(Count(r.Samples), 3000);
  for (std::size_t p = 0; p < roles.size(); ++p)
  {
    const PixelRole role = static_cast<PixelRole>(roles[p]);
    if (role == PixelRole::Sample)
    {
      EXPECT_EQ(r.Samples[p], 1);
    }
    if (role == PixelRole::Excluded || role == PixelRole::Outside)
    {
      EXPECT_EQ(r.Samples[p], 0);
    }
  }
  // Impossible requests are errors, not wrong counts.
  EXPECT_NE(Halftone(density.data(), n, n, n * n, roles.data()).Error, "");
  EXPECT_NE(Halftone(density.data(), n, n, 5, roles.data()).Error, "");
  const std::vector<double> empty(density.size(), 0.0);
  EXPECT_NE(Halftone(empty.data(), n, n, 1).Error, "");
  EXPECT_EQ(Count(Halftone(empty.data(), n, n, 0).Samples), 0);
}

TEST(ErrorDiffusion, AlongAPathTheRoundedTotalAtEvenSpacing)
{
  std::vector<double> uniform(11);
  for (int k = 0; k <= 10; ++k)
  {
    uniform[k] = 0.4 * k; // 0.4 samples per segment: 4 samples in all
  }
  const std::vector<double> at = DiffuseAlongPath(uniform);
  ASSERT_EQ(at.size(), 4u);
  for (std::size_t k = 0; k < at.size(); ++k)
  {
    EXPECT_NEAR(at[k], (k + 0.5) / 0.4, 1e-12);
  }
  // Denser where the density is: nodes 0-5 carry 9 of 10 samples.
  std::vector<double> skewed = { 0, 1.8, 3.6, 5.4, 7.2, 9.0, 9.2, 9.4, 9.6, 9.8, 10.0 };
  const std::vector<double> s = DiffuseAlongPath(skewed);
  ASSERT_EQ(s.size(), 10u);
  EXPECT_LT(s[8], 5.0);
  EXPECT_GT(s[9], 5.0);
  EXPECT_TRUE(DiffuseAlongPath({ 0.0 }).empty());
}
