// Tests for engine/metrics: metrics on tiny images worked out by hand, size checks, handling
// of NaN/inf pixels, the error image, and the colour map's monotone lightness.
#include "eval/metrics.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

using test::kInf;
using test::kNaN;

Image imageOf(std::initializer_list<vec3> pixels) {
  Image image(int(pixels.size()), 1);
  std::copy(pixels.begin(), pixels.end(), image.pixels.begin());
  return image;
}

// Values chosen exactly representable in binary so the hand computation is exact:
//   pixel 0: test 0.25 grey, reference black     -> each channel d = 0.25, d^2 = 0.0625
//   pixel 1: test (1,1,0.5), reference white     -> d = (0, 0, -0.5), d^2 = (0, 0, 0.25)
//   MSE     = (3 * 0.0625 + 0.25) / 6 = 0.4375 / 6                 = 0.0729166666...
//   relMSE  = (3 * 0.0625 / 0.01 + 0.25 / 1.01) / 6
//           = (18.75 + 0.2475247525) / 6                           = 3.1662541254...
//   PSNR    = 10 log10(1 / 0.0729166666) = 10 log10(13.714285714)  = 11.3717319303 dB
//   max abs = 0.5
TEST(Metrics, HandComputedTinyImage) {
  const Image test = imageOf({vec3(0.25f), vec3(1.0f, 1.0f, 0.5f)});
  const Image reference = imageOf({vec3(0.0f), vec3(1.0f)});
  const ImageMetrics m = compareImages(test, reference);
  EXPECT_NEAR(m.mse, 0.0729166666666667, 1e-12);
  EXPECT_NEAR(m.relMse, 3.1662541254125413, 1e-12);
  EXPECT_NEAR(m.psnr, 11.371731930253116, 1e-9);
  EXPECT_DOUBLE_EQ(m.maxAbsError, 0.5);
  EXPECT_EQ(m.nonFinite, 0u);
}

// PSNR clamps both images to [0,1]: 2 vs 1 and -1 vs 0 look identical on a display, so
// PSNR is infinite, while MSE sees the unclamped differences: (1 + 1) * 3 / 6 = 1.
TEST(Metrics, PsnrUsesClampedValues) {
  const Image test = imageOf({vec3(2.0f), vec3(-1.0f)});
  const Image reference = imageOf({vec3(1.0f), vec3(0.0f)});
  const ImageMetrics m = compareImages(test, reference);
  EXPECT_DOUBLE_EQ(m.mse, 1.0);
  EXPECT_TRUE(std::isinf(m.psnr) && m.psnr > 0);
  EXPECT_DOUBLE_EQ(m.maxAbsError, 1.0);
}

// Clamping still counts differences inside [0,1]: test 1.5 vs 0.5 -> clamped 1 vs 0.5, d = 0.5,
// clamped MSE = 0.25, PSNR = 10 log10(4) = 6.0206 dB; unclamped MSE = 1.
TEST(Metrics, PsnrOfPartlyClampedDifference) {
  const ImageMetrics m = compareImages(imageOf({vec3(1.5f)}), imageOf({vec3(0.5f)}));
  EXPECT_DOUBLE_EQ(m.mse, 1.0);
  EXPECT_NEAR(m.psnr, 10.0 * std::log10(4.0), 1e-12);
}

TEST(Metrics, IdenticalImages) {
  const Image a = imageOf({vec3(0.1f, 5.0f, -2.0f), vec3(0.0f)});
  const ImageMetrics m = compareImages(a, a);
  EXPECT_EQ(m.mse, 0.0);
  EXPECT_EQ(m.relMse, 0.0);
  EXPECT_EQ(m.maxAbsError, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr));
}

TEST(Metrics, SizeMismatchThrowsNamingBothSizes) {
  const Image a(3, 2), b(2, 3);
  try {
    compareImages(a, b);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("3x2"), std::string::npos) << message;
    EXPECT_NE(message.find("2x3"), std::string::npos) << message;
  }
  double maxValue = 0.0;
  EXPECT_THROW(errorImage(a, b, maxValue), std::invalid_argument);
}

// Pixels 1 (NaN in test) and 2 (inf in reference) are skipped; the rest is pixel 0 and 3:
//   d = (-0.5, 0, 0) and (0, 0, 0)  ->  MSE = 0.25 / 6 = 0.041666..., max abs = 0.5
//   relMSE = (0.25 / (1 + 0.01)) / 6 = 0.0412541254...
//   all values lie in [0,1], so PSNR = 10 log10(6 / 0.25) = 10 log10(24) = 13.802 dB
TEST(Metrics, NonFinitePixelsAreCountedAndSkipped) {
  const Image test = imageOf({vec3(0.5f, 1.0f, 1.0f), vec3(kNaN, 0, 0), vec3(1.0f), vec3(0.5f)});
  const Image reference = imageOf({vec3(1.0f), vec3(1.0f), vec3(1.0f, kInf, 1.0f), vec3(0.5f)});
  const ImageMetrics m = compareImages(test, reference);
  EXPECT_EQ(m.nonFinite, 2u);
  EXPECT_NEAR(m.mse, 0.25 / 6.0, 1e-12);
  EXPECT_NEAR(m.relMse, 0.25 / 1.01 / 6.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.maxAbsError, 0.5);
  EXPECT_NEAR(m.psnr, 10.0 * std::log10(24.0), 1e-9);
}

TEST(Metrics, AllPixelsNonFiniteGivesNaNNotZero) {
  const ImageMetrics m = compareImages(imageOf({vec3(kNaN)}), imageOf({vec3(1.0f)}));
  EXPECT_EQ(m.nonFinite, 1u);
  EXPECT_TRUE(std::isnan(m.mse));
  EXPECT_TRUE(std::isnan(m.relMse));
  EXPECT_TRUE(std::isnan(m.psnr));
}

// Per pixel, mean over channels of d^2 / (ref^2 + 0.01):
//   pixel 0: 3 * (0.0625 / 0.01) / 3 = 6.25
//   pixel 1: (0.25 / 1.01) / 3       = 0.0825082508...
//   pixel 2: NaN in test             -> NaN, ignored by maxValue
TEST(Metrics, ErrorImageIsPerPixelRelativeSquaredError) {
  const Image test = imageOf({vec3(0.25f), vec3(1.0f, 1.0f, 0.5f), vec3(kNaN)});
  const Image reference = imageOf({vec3(0.0f), vec3(1.0f), vec3(0.0f)});
  double maxValue = -1.0;
  const Image error = errorImage(test, reference, maxValue);
  ASSERT_EQ(error.width, 3);
  EXPECT_FLOAT_EQ(error.at(0, 0).x, 6.25f);
  EXPECT_FLOAT_EQ(error.at(1, 0).x, 0.0825082508f);
  EXPECT_EQ(error.at(1, 0).x, error.at(1, 0).z);  // scalar replicated, viewable as grey
  EXPECT_TRUE(std::isnan(error.at(2, 0).x));
  EXPECT_DOUBLE_EQ(maxValue, 6.25);
}

TEST(Metrics, ColormapEndpointsAndClamping) {
  const vec3 low = colormapViridis(0.0f), high = colormapViridis(1.0f);
  EXPECT_NEAR(low.x, 68 / 255.0f, 1e-6f);
  EXPECT_NEAR(low.z, 84 / 255.0f, 1e-6f);
  EXPECT_NEAR(high.x, 253 / 255.0f, 1e-6f);
  EXPECT_NEAR(high.y, 231 / 255.0f, 1e-6f);
  EXPECT_EQ(colormapViridis(-3.0f), low);
  EXPECT_EQ(colormapViridis(kNaN), low);
  EXPECT_EQ(colormapViridis(7.0f), high);
}

// The map must read as "brighter = larger" even in greyscale: luminance of the linear output
// rises strictly along a fine ramp.
TEST(Metrics, FalseColorIsMonotoneInLuminance) {
  const int n = 1024;
  Image ramp(n, 1);
  for (int i = 0; i < n; ++i) ramp.at(i, 0) = vec3(2.0f * float(i) / float(n - 1));
  const Image colours = falseColor(ramp, 2.0f);
  for (int i = 1; i < n; ++i)
    EXPECT_GT(luminance(colours.at(i, 0)), luminance(colours.at(i - 1, 0))) << "at " << i;
  // Output is linear: converting back to sRGB gives the colour map's own values.
  const vec3 top = colours.at(n - 1, 0);
  EXPECT_NEAR(linearToSrgb(top.y), colormapViridis(1.0f).y, 1e-5f);
}

TEST(Metrics, FalseColorFlagsNonFiniteAndClamps) {
  const Image scalar = imageOf({vec3(kNaN), vec3(kInf), vec3(10.0f), vec3(-1.0f), vec3(0.5f)});
  const Image colours = falseColor(scalar, 1.0f);
  EXPECT_EQ(colours.at(0, 0), vec3(1.0f, 0.0f, 1.0f));
  EXPECT_EQ(colours.at(1, 0), vec3(1.0f, 0.0f, 1.0f));
  EXPECT_EQ(colours.at(2, 0), falseColor(imageOf({vec3(1.0f)}), 1.0f).at(0, 0));
  EXPECT_EQ(colours.at(3, 0), falseColor(imageOf({vec3(0.0f)}), 1.0f).at(0, 0));
  // Identical images give maxValue 0: everything at the bottom of the map, no division by 0.
  const Image flat = falseColor(imageOf({vec3(0.0f)}), 0.0f);
  EXPECT_NEAR(linearToSrgb(flat.at(0, 0).x), colormapViridis(0.0f).x, 1e-5f);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(Metrics, ToneMappedMseUsesTheReferencesKey) {
  // Reference: constant 0.18 grey, so its key is k = 0.18 / (0.18 + 1e-4) and T(0.18) =
  // 0.18k / (1 + 0.18k). A test image of 0.36 gives T(0.36) = 0.36k / (1 + 0.36k).
  const Image ref(4, 2, vec3(0.18f));
  const Image test(4, 2, vec3(0.36f));
  const double k = 0.18 / (0.18 + 1e-4);
  const double d = 0.36 * k / (1 + 0.36 * k) - 0.18 * k / (1 + 0.18 * k);
  EXPECT_NEAR(compareImages(test, ref).toneMappedMse, d * d, 1e-6);
  EXPECT_EQ(compareImages(ref, ref).toneMappedMse, 0.0);
}

}  // namespace
}  // namespace penumbra
