// Beltrami core: halftoning a sampling density with an exact number of
// samples (thesis section 4.3.2).  A density image (expected samples per
// pixel) becomes a binary image by Ostromoukhov's variable-coefficient error
// diffusion (SIGGRAPH 2001: serpentine scan, three neighbours whose weights
// depend on the pixel's level, interpolated between the paper's 18 key
// levels) on floating-point values, over the image below a vertically
// flipped copy of itself (no "dead zone" of missing samples where the scan
// starts), with pixels forced to be samples (constraints) or excluded
// (features and boundaries, sampled separately; their share of the density
// is diffused to the neighbours).  The exact count comes from scaling the
// density (secant steps on the scale until within 1%), then from adding or
// removing the rest spread over the image in proportion to the density,
// where no two samples end up side by side.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

/// What a pixel may hold.
enum class PixelRole : std::uint8_t
{
  Free = 0,     ///< a sample where the error diffusion puts one
  Sample = 1,   ///< always a sample (a constrained point)
  Excluded = 2, ///< never a sample; its density is diffused on (features, boundaries)
  Outside = 3   ///< not part of the domain: never a sample, its error is dropped
};

struct HalftoneResult
{
  std::string Error;                 ///< non-empty: the count cannot be met (no samples)
  std::vector<std::uint8_t> Samples; ///< per pixel: 1 where a sample is
  std::int64_t Count = 0;            ///< samples in `Samples`
  double Scale = 0.0;                ///< the factor on the density that gave the count
  int Passes = 0;                    ///< error diffusion passes (scale steps)
  std::int64_t Adjusted = 0;         ///< samples added or removed after the last pass
};

/// One error diffusion pass: `density` (width x height, row-major, expected
/// samples per pixel; times `scale`, clamped to [0, 1], NaN and infinity as 0) into
/// `samples` (1 per sample); `roles` (null: all Free) as PixelRole values.
/// Returns the sample count.
std::int64_t DiffuseErrors(
  const double* density, int width, int height, double scale, const std::uint8_t* roles, std::uint8_t* samples);

/// Exactly `count` samples distributed by `density` (its sum need not be
/// `count`: it is scaled).  An error when the count is above what the free
/// pixels of positive density can hold (one sample each, plus the forced
/// ones) or below the forced samples.
HalftoneResult Halftone(
  const double* density, int width, int height, std::int64_t count, const std::uint8_t* roles = nullptr);

/// 1D error diffusion along a path (a feature, a boundary, a seam): with
/// cumulative expected samples `cumulative` (ascending, from 0) at the path's
/// nodes, the positions (fractional node indices) of the samples, one where
/// the cumulative density crosses k + 1/2 (threshold 1/2, the error carried
/// along): round(cumulative.back()) samples.
std::vector<double> DiffuseAlongPath(const std::vector<double>& cumulative);

} // namespace beltrami
