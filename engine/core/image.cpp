#include "core/image.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

float linearToSrgb(float v) {
  if (!(v > 0.0f)) return 0.0f;
  if (v >= 1.0f) return 1.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// Filled while statics are initialised: no static initialiser decodes an image.
const std::array<float, 256> kSrgb8ToLinear = [] {
  std::array<float, 256> table{};
  for (int i = 0; i < 256; ++i) table[size_t(i)] = srgbToLinear(float(i) / 255.0f);
  return table;
}();

uint8_t linearToSrgb8(float v) { return uint8_t(std::lround(255.0f * linearToSrgb(v))); }

std::vector<uint8_t> toSrgb8(const Image& image, float exposureStops) {
  const float scale = std::exp2(exposureStops);
  std::vector<uint8_t> out(image.pixels.size() * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const vec3 c = image.pixels[i] * scale;
    for (int k = 0; k < 3; ++k) out[3 * i + k] = linearToSrgb8(c[k]);
  }
  return out;
}

}  // namespace penumbra
