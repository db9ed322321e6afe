// Reconstruction of ALGORITHM.md §9 (the tone map of §0 is core/tone_map.h).
//  - The bilateral filterbank of eq. 18: per pixel a spatial falloff alpha chosen from its
//    bias by the thresholds Phi, a range term on tone-mapped RGB, averaging on linear values;
//    then a second pass with alpha_3 everywhere to soften seams between scales.
#pragma once

#include "core/image.h"
#include "core/tone_map.h"

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

struct FilterConfig {
  int radius = 4;                                        // r: (2r+1)^2 window
  std::vector<float> alphas{0.1f, 1.f, 3.f, 5.f, 10.f};  // alpha_1 (widest) .. alpha_5
  std::vector<float> phi{0.3f, 0.45f, 0.7f, 0.85f};      // bias thresholds, ascending
  float sigmaC = 0.3f;                                   // range falloff on tone-mapped RGB
  bool secondPass = true;
  int secondPassAlpha = 2;  // index of alpha_3
};

// Index into alphas for a bias: the number of thresholds <= bias (a value exactly on a
// threshold goes to the narrower filter). NaN bias -> the narrowest filter.
int alphaIndexForBias(float bias, std::span<const float> phi);

// One pass of eq. 18 with falloff alphaOf[p] at pixel p (window clipped at the borders and
// renormalised; range term from T of `image` itself).
// `cancel`, when given and set, stops it between rows (the result is then incomplete).
Image bilateralPass(const Image& image, std::span<const float> alphaOf, const ToneMap& tone,
                    int radius, float sigmaC, const std::atomic<bool>* cancel = nullptr);

struct Reconstruction {
  Image firstPass;
  Image output;                     // second pass, or the first pass when it is disabled
  std::vector<uint8_t> alphaIndex;  // per pixel, into FilterConfig::alphas
};
// Throws std::invalid_argument when bias.size() differs from the pixel count, or the
// configuration is inconsistent (phi.size() != alphas.size() - 1, radius < 0, ...).
Reconstruction reconstruct(const Image& estimate, std::span<const float> bias, const ToneMap& tone,
                           const FilterConfig& config, const std::atomic<bool>* cancel = nullptr);

}  // namespace penumbra
