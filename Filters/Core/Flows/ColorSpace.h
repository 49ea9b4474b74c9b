// Beltrami core: colour spaces for the colour flows of section 3.8.4.
//
// The thesis smooths colour images in CIE L*u*v*, which is nearly
// perceptually uniform, so that the edge indicator sees the edges a viewer
// sees.  RGB is taken as sRGB (IEC 61966-2-1, D65 white) with components in
// [0, 1] (values outside are clipped); L*u*v* is returned divided by 100, so
// that both spaces have comparable ranges (L* in [0, 1]) and one contrast
// scale suits either.
#pragma once

#include "Support/Parallel.h"

namespace beltrami
{

/// In place: `count` colours, the first three of every `stride` values.
void RGBToLuv(double* colors, std::int64_t count, int stride, int numThreads = 0);
/// The inverse of RGBToLuv (results clipped to [0, 1]).
void LuvToRGB(double* colors, std::int64_t count, int stride, int numThreads = 0);

} // namespace beltrami
