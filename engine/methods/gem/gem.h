// GEM, "Adaptive sampling and reconstruction using greedy error minimization" (Rousselle,
// Knaus, Zwicker 2011), as ALGORITHM.md §10.4 reads it from the authors' code, on the
// shared allocation framework (allocation.h): per-pixel mean and variance, a filterbank of
// isotropic Gaussians, a greedy per-pixel scale choice that stops where the estimated
// squared bias outgrows the variance removed, and an MSE estimate that both ranks pixels
// for sampling and, through the chosen scale's Gaussian, places their new samples (which
// may land in neighbouring pixels). The output is each pixel's estimate at its scale in a
// final 8-scale pass. A box pixel filter replaces the original's Gaussian pixel filter.
#pragma once

#include "core/image.h"
#include "methods/allocation.h"

#include <memory>
#include <span>
#include <vector>

namespace penumbra {

struct GemConfig : AllocationConfig {
  float gamma = 0.2f;  // confidence of the bias test; c_gamma = -ln(1 - (1.9 gamma)^(1/sqrt2))
};

// The parameters of GemConfig, for the command line, the panel, the stats and compare.
const ParamTable<GemConfig>& gemParams();
// The method\'s descriptor (methods/method.h).
const MethodDescriptor& gemMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeGemMethod(const PreparedScene& prepared,
                                                 const RunShape& shape, const GemConfig& config);

namespace gem {

// Filter widths (pixels) of the sampling rounds {1, 2, 4, 8} and of the final pass
// 2^-1/2 (sqrt 2)^s = {0.71, ..., 8}. Scale index 0 is the unfiltered pixel; index s >= 1
// is the s-th width.
const std::vector<float>& samplingScales();
const std::vector<float>& finalScales();
double cGamma(double gamma);

// Normalised Gaussian filtering of `channels` interleaved planes, clipped at the borders
// and renormalised (separable). squared: sum w^2 x / (sum w)^2, the variance of a
// filtered mean. The kernel is cut at 3 sigma.
void gaussianFilter(std::span<const float> src, std::span<float> dst, int width, int height,
                    int channels, float sigma, bool squared);

struct PixelStatistics {
  int width = 0, height = 0;
  std::vector<vec3> mean;      // linear RGB
  std::vector<vec3> variance;  // of the mean: s^2 / n, 0 when n <= 1
  std::vector<float> count;    // samples
};
struct ScaleSelection {
  std::vector<uint8_t> scale;  // 0 = unfiltered, s = sigmas[s - 1]
  std::vector<float> mse;      // v_0 + sum (loss - gain) up to the chosen scale (RGB mean)
  std::vector<float> count;    // effective count at the chosen scale
  std::vector<vec3> estimate;  // the pixel's value at the chosen scale
};
// The greedy choice over `sigmas` (increasing). finalPass: an invalid transition counts
// only where its smoothed map agrees (min of the two); otherwise the smoothed map alone.
ScaleSelection selectScales(const PixelStatistics& stats, std::span<const float> sigmas,
                            double gamma, bool finalPass);
// E_p = mse / (1e-3 + mean RGB of estimate^2) x spp / (spp + n_sel): the relative MSE
// times the expected gain of another `spp` samples.
float pixelError(const ScaleSelection& s, size_t pixel, int spp);

}  // namespace gem

}  // namespace penumbra
