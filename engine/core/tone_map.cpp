// The tone map of ALGORITHM.md §0.
#include "core/tone_map.h"

#include <algorithm>
#include <cmath>

namespace penumbra {
namespace {

// The Reinhard key's offset keeps log finite on black pixels [A9].
constexpr double kLogOffset = 1e-4;
constexpr double kMiddleGrey = 0.18;
// Tone-mapped values at 1 would invert to infinity.
constexpr float kMaxMapped = 1.0f - 1e-6f;

float mapChannel(float linear, float key) {
  const float x = key * std::max(linear, 0.0f);
  // x / (1 + x) is inf / inf for an infinite (or overflowed) input; its limit is 1.
  return std::isinf(x) ? 1.0f : x / (1.0f + x);
}

}  // namespace

vec3 ToneMap::apply(vec3 linear) const {
  return {mapChannel(linear.x, key), mapChannel(linear.y, key), mapChannel(linear.z, key)};
}

vec3 ToneMap::invert(vec3 mapped) const {
  vec3 out;
  for (int k = 0; k < 3; ++k) {
    const float t = std::clamp(mapped[k], 0.0f, kMaxMapped);
    out[k] = t / (key * (1.0f - t));
  }
  return out;
}

float ToneMap::value(vec3 linear) const { return luminance(apply(linear)); }

ToneMap toneMapFor(const Image& image) {
  double logSum = 0.0;
  size_t used = 0;
  for (const vec3& c : image.pixels) {
    if (!isFinite(c)) continue;
    const float y = luminance(c);
    if (!std::isfinite(y)) continue;  // finite channels can still overflow the weighted sum
    // Negative luminance (negative channels) is treated as black, as apply() clamps it.
    logSum += std::log(kLogOffset + std::max(0.0, double(y)));
    ++used;
  }
  ToneMap tone;
  if (used > 0) tone.key = float(kMiddleGrey / std::exp(logSum / double(used)));
  return tone;
}

}  // namespace penumbra
