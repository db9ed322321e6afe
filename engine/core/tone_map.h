// The tone map of ALGORITHM.md §0: T(L) = kL / (1 + kL) per channel, k = 0.18 /
// exp(mean log(1e-4 + Y)) (Reinhard key from the coarse image). The BP network, the
// histograms, the filter's range term and the tone-mapped MSE all work on T(L).
#pragma once

#include "core/image.h"

namespace penumbra {

struct ToneMap {
  float key = 1.0f;                // k
  vec3 apply(vec3 linear) const;   // T(L), per channel, negative values clamped to 0
  vec3 invert(vec3 mapped) const;  // L = t / (k (1 - t)), t clamped below 1
  float value(vec3 linear) const;  // v = Y(T(L)), the scalar the slices use
};
// The key of `image` (k above); 1 for an empty image.
ToneMap toneMapFor(const Image& image);

}  // namespace penumbra
