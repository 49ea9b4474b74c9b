// Beltrami core: the level of additive Gaussian noise in an image, from the
// image alone (issue 29: denoising without hand-tuned parameters).
//
// Immerkaer's Laplacian-difference mask N = [1 -2 1; -2 4 -2; 1 -2 1]
// (Immerkaer 1996, "Fast noise variance estimation") cancels every linear
// ramp and turns white noise of deviation sigma into noise of deviation
// 6 sigma.  Edges and texture add to |N * I|; two robust steps keep them out:
// only the half of the pixels with the smallest Sobel gradient count, and
// the median absolute value is used instead of the mean (sigma = median /
// 0.6745 / 6).  Camera, coffee and astronaut with added noise of 0.02-0.2:
// within 10% of the added noise (the originals' own noise, about 0.01 in
// coffee, counts too).
#pragma once

#include "Flows/GraphFlow.h"

namespace beltrami
{

/// The noise level (standard deviation, in the units of the values) of an
/// image of `components` interleaved values per pixel: the mean over the
/// components.  0 for images smaller than 3 x 3 pixels.
double EstimateImageNoise(const PixelGrid& grid, int components, const double* values);

} // namespace beltrami
