// Image comparison: error metrics against a reference render, a per-pixel error image, and
// the perceptual colour map used to display such scalar images.
#pragma once

#include "core/image.h"

#include <cstddef>

namespace penumbra {

struct ImageMetrics {
  double mse = 0.0;            // mean over pixels and RGB channels of (x - ref)^2, linear values
  double relMse = 0.0;         // mean of (x - ref)^2 / (ref^2 + 1e-2), same averaging
  double toneMappedMse = 0.0;  // MSE of T(x) - T(ref), T the Reinhard map keyed on ref (§0)
  double psnr = 0.0;         // dB, 10 log10(1 / MSE) on both images clamped to [0,1]; +inf if equal
  double maxAbsError = 0.0;  // largest |x - ref| over all channels
  size_t nonFinite = 0;      // pixels skipped because a channel of either image is NaN or inf
};

// Compares `test` against `reference`. Pixels with a non-finite channel in either image are
// counted in nonFinite and left out of every average; if no pixel is left, all metrics are NaN.
// Throws std::invalid_argument (naming both sizes) when the sizes differ.
ImageMetrics compareImages(const Image& test, const Image& reference);

// Per-pixel relative squared error, mean over channels of (x - ref)^2 / (ref^2 + 1e-2), stored
// in all three channels (NaN where a channel of either image is non-finite). maxValue receives
// the largest finite value (0 if there is none). Throws std::invalid_argument on a size mismatch.
Image errorImage(const Image& test, const Image& reference, double& maxValue);

// How converged a render is, from its per-pixel variance of the mean: residualMse is the
// mean over pixels and channels of that variance (the MSE an exact method would still show
// against it), meanRelativeError the mean of sqrt(Var[Y]) / (|Y| + 0.01) over pixels, Y the
// luminance. Non-finite pixels are skipped. Throws std::invalid_argument on a size mismatch.
struct Convergence {
  double residualMse = 0, meanRelativeError = 0;
};
Convergence convergenceOf(const Image& mean, const Image& varianceOfMean);

// Viridis-like colour map: t in [0,1] (clamped) to an sRGB-encoded colour, dark purple to
// yellow with monotonically increasing lightness, readable in greyscale and by colour-blind users.
vec3 colormapViridis(float t);

// Maps scalar.x from [0, maxValue] through colormapViridis to linear RGB (so writeImage's sRGB
// encoding reproduces the map's colours). Non-finite values become magenta so they stand out.
Image falseColor(const Image& scalar, float maxValue);

}  // namespace penumbra
