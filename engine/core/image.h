// Images: a plain RGB float buffer (linear radiance) plus the small helpers every
// part of the engine shares (luminance, sRGB transfer, tone mapping for display).
#pragma once

#include "core/large_pages.h"

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

using glm::vec3;

// Row-major, top row first, linear RGB. The pixels of a large image are huge pages
// (core/large_pages.h): every round and picture makes images afresh, and on 4 KiB pages a
// 1280x720 image costs 2,700 page faults each time.
struct Image {
  int width = 0;
  int height = 0;
  LargeVector<vec3> pixels;

  Image() = default;
  Image(int w, int h, vec3 fill = vec3(0.0f)) : width(w), height(h), pixels(size_t(w) * h, fill) {}
  vec3& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const vec3& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
  bool empty() const { return pixels.empty(); }
};

// True when every channel is a finite number (no NaN, no infinity).
inline bool isFinite(vec3 c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

// Rec. 709 luminance of linear RGB.
inline float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

float linearToSrgb(float v);
float srgbToLinear(float v);

// srgbToLinear(i / 255) for every 8-bit code i (filled before main).
extern const std::array<float, 256> kSrgb8ToLinear;
// The linear value of an 8-bit sRGB code, through kSrgb8ToLinear.
inline float srgb8ToLinear(uint8_t v) { return kSrgb8ToLinear[v]; }
// The 8-bit sRGB code nearest a linear value (clamped to [0, 1]).
uint8_t linearToSrgb8(float v);

// Display transform used for PNG output: exposure (stops), clamp, sRGB encode, 8 bits.
std::vector<uint8_t> toSrgb8(const Image& image, float exposureStops = 0.0f);

}  // namespace penumbra
