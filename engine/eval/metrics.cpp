// Error metrics between a render and its reference, and false-colour display of the error.
#include "eval/metrics.h"

#include "core/tone_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

// Keeps the relative error finite where the reference is black, while barely affecting it
// where the reference is bright.
constexpr double kRelEpsilon = 1e-2;

void requireSameSize(const Image& test, const Image& reference) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("image sizes differ: " + std::to_string(test.width) + "x" +
                                std::to_string(test.height) + " vs reference " +
                                std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
}

double relativeSquaredError(vec3 test, vec3 reference) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = double(test[k]) - reference[k];
    sum += d * d / (double(reference[k]) * reference[k] + kRelEpsilon);
  }
  return sum / 3.0;
}

}  // namespace

ImageMetrics compareImages(const Image& test, const Image& reference) {
  requireSameSize(test, reference);
  // Both images through the reference's tone map, so the key is the same for every test.
  const ToneMap tone = toneMapFor(reference);
  double squared = 0.0, relative = 0.0, clampedSquared = 0.0, maxAbs = 0.0, toneSquared = 0.0;
  size_t finitePixels = 0, nonFinite = 0;
  for (size_t i = 0; i < test.pixels.size(); ++i) {
    const vec3 x = test.pixels[i], ref = reference.pixels[i];
    if (!isFinite(x) || !isFinite(ref)) {
      ++nonFinite;
      continue;
    }
    ++finitePixels;
    relative += relativeSquaredError(x, ref);
    const vec3 dt = tone.apply(x) - tone.apply(ref);
    toneSquared += double(dt.x) * dt.x + double(dt.y) * dt.y + double(dt.z) * dt.z;
    for (int k = 0; k < 3; ++k) {
      const double d = double(x[k]) - ref[k];
      squared += d * d;
      maxAbs = std::max(maxAbs, std::abs(d));
      const double dc = std::clamp(double(x[k]), 0.0, 1.0) - std::clamp(double(ref[k]), 0.0, 1.0);
      clampedSquared += dc * dc;
    }
  }

  ImageMetrics m;
  m.nonFinite = nonFinite;
  if (finitePixels == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    m.mse = m.relMse = m.toneMappedMse = m.psnr = m.maxAbsError = nan;
    return m;
  }
  const double n = double(finitePixels);
  m.mse = squared / (3.0 * n);
  m.relMse = relative / n;  // relativeSquaredError already averages the channels
  m.toneMappedMse = toneSquared / (3.0 * n);
  m.maxAbsError = maxAbs;
  const double clampedMse = clampedSquared / (3.0 * n);
  m.psnr = clampedMse > 0.0 ? 10.0 * std::log10(1.0 / clampedMse)
                            : std::numeric_limits<double>::infinity();
  return m;
}

Image errorImage(const Image& test, const Image& reference, double& maxValue) {
  requireSameSize(test, reference);
  Image out(test.width, test.height);
  maxValue = 0.0;
  for (size_t i = 0; i < test.pixels.size(); ++i) {
    const vec3 x = test.pixels[i], ref = reference.pixels[i];
    if (!isFinite(x) || !isFinite(ref)) {
      out.pixels[i] = vec3(std::numeric_limits<float>::quiet_NaN());
      continue;
    }
    const double e = relativeSquaredError(x, ref);
    out.pixels[i] = vec3(float(e));
    // Compare the stored float so that maxValue maps exactly to the top of the colour map.
    if (std::isfinite(float(e))) maxValue = std::max(maxValue, double(float(e)));
  }
  return out;
}

vec3 colormapViridis(float t) {
  // Nine evenly spaced stops of matplotlib's viridis (public domain), sRGB 0..255;
  // interpolating linearly between them stays within a few levels of the full map.
  static constexpr std::array<std::array<float, 3>, 9> kStops = {{
      {68, 1, 84},
      {71, 45, 123},
      {59, 82, 139},
      {44, 114, 142},
      {33, 145, 140},
      {40, 174, 128},
      {94, 201, 98},
      {173, 220, 48},
      {253, 231, 37},
  }};
  if (!(t > 0.0f)) t = 0.0f;  // also maps NaN to the bottom of the range
  t = std::min(t, 1.0f);
  const float position = t * float(kStops.size() - 1);
  const size_t lower = std::min(size_t(position), kStops.size() - 2);
  const float f = position - float(lower);
  vec3 c;
  for (int k = 0; k < 3; ++k)
    c[k] = ((1.0f - f) * kStops[lower][k] + f * kStops[lower + 1][k]) / 255.0f;
  return c;
}

Image falseColor(const Image& scalar, float maxValue) {
  Image out(scalar.width, scalar.height);
  const vec3 magenta(1.0f, 0.0f, 1.0f);
  for (size_t i = 0; i < scalar.pixels.size(); ++i) {
    const float v = scalar.pixels[i].x;
    if (!std::isfinite(v)) {
      out.pixels[i] = magenta;
      continue;
    }
    // With maxValue 0 (identical images) everything sits at the bottom of the map.
    const float t = maxValue > 0.0f ? v / maxValue : 0.0f;
    const vec3 srgb = colormapViridis(t);
    out.pixels[i] = vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
  }
  return out;
}

Convergence convergenceOf(const Image& mean, const Image& varianceOfMean) {
  if (mean.width != varianceOfMean.width || mean.height != varianceOfMean.height)
    throw std::invalid_argument("convergenceOf: the variance image's size differs");
  Convergence c;
  size_t counted = 0;
  for (size_t p = 0; p < mean.pixels.size(); ++p) {
    const vec3 v = varianceOfMean.pixels[p];
    const double y = luminance(mean.pixels[p]), var = luminance(v);
    if (!std::isfinite(var) || !std::isfinite(y)) continue;
    c.meanRelativeError += std::sqrt(std::max(0.0, var)) / (std::abs(y) + 1e-2);
    c.residualMse += (double(v.x) + v.y + v.z) / 3.0;
    ++counted;
  }
  if (counted) {
    c.meanRelativeError /= double(counted);
    c.residualMse /= double(counted);
  }
  return c;
}

}  // namespace penumbra
