// Tests for engine/reconstruct: the Reinhard key and tone map, the bias -> alpha mapping at the
// thresholds Phi, eq. 18 on a two-pixel image by hand, and the filterbank's behaviour on
// constant, step-edge and noisy images, its second pass, and its thread independence.
#include "methods/bp/reconstruct.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace {

using test::kInf;
using test::kNaN;

// Grey noise around `mean` with relative amplitude `amplitude`, uniform.
Image noisyImage(int width, int height, float mean, float amplitude, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Image image(width, height);
  for (vec3& c : image.pixels) c = vec3(mean * (1.0f + amplitude * unit(rng)));
  return image;
}

std::vector<float> randomBias(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> bias(count);
  for (float& b : bias) b = unit(rng);
  return bias;
}

// Variance of the green channel over the pixels at least `margin` from every border.
double interiorVariance(const Image& image, int margin) {
  double sum = 0.0, sumSq = 0.0;
  int n = 0;
  for (int y = margin; y < image.height - margin; ++y) {
    for (int x = margin; x < image.width - margin; ++x) {
      const double v = image.at(x, y).y;
      sum += v;
      sumSq += v * v;
      ++n;
    }
  }
  const double mean = sum / n;
  return sumSq / n - mean * mean;
}

void expectIdentical(const Image& a, const Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    ASSERT_EQ(a.pixels[i].x, b.pixels[i].x) << "pixel " << i;
    ASSERT_EQ(a.pixels[i].y, b.pixels[i].y) << "pixel " << i;
    ASSERT_EQ(a.pixels[i].z, b.pixels[i].z) << "pixel " << i;
  }
}

void expectConstant(const Image& image, vec3 value, float tolerance) {
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    ASSERT_NEAR(image.pixels[i].x, value.x, tolerance) << "pixel " << i;
    ASSERT_NEAR(image.pixels[i].y, value.y, tolerance) << "pixel " << i;
    ASSERT_NEAR(image.pixels[i].z, value.z, tolerance) << "pixel " << i;
  }
}

// Constant grey 0.18: every pixel has Y = 0.18 (the Rec.709 weights sum to 1), so the mean of
// log(1e-4 + Y) is log(0.1801) and k = 0.18 / 0.1801 = 0.99944: 1 up to the offset.
TEST(ToneMap, KeyOfConstantGreyIsAboutOne) {
  const Image grey(4, 3, vec3(0.18f));
  const double y = luminance(vec3(0.18f));
  const ToneMap tone = toneMapFor(grey);
  EXPECT_NEAR(tone.key, 0.18 / (1e-4 + y), 1e-6);
  EXPECT_NEAR(tone.key, 1.0, 1e-3);
}

// Two pixels with 1e-4 + Y = 0.1 and 1.0: the geometric mean is sqrt(0.1) = 0.3162278, so
// k = 0.18 / 0.3162278 = 0.5692100. The NaN and infinite pixels are skipped.
TEST(ToneMap, KeyIsGeometricMeanOfFinitePixels) {
  Image image(4, 1);
  image.pixels = {vec3(0.0999f), vec3(0.9999f), vec3(kNaN, 0.0f, 0.0f), vec3(kInf)};
  const double y0 = 1e-4 + luminance(vec3(0.0999f)), y1 = 1e-4 + luminance(vec3(0.9999f));
  EXPECT_NEAR(toneMapFor(image).key, 0.18 / std::sqrt(y0 * y1), 1e-6);
  EXPECT_NEAR(toneMapFor(image).key, 0.5692100, 1e-5);
}

TEST(ToneMap, KeyOfEmptyOrAllNonFiniteImageIsOne) {
  EXPECT_EQ(toneMapFor(Image{}).key, 1.0f);
  EXPECT_EQ(toneMapFor(Image(2, 2, vec3(kNaN))).key, 1.0f);
}

// k = 2: L = 0.5 -> 1/2 = 0.5; L = 1.5 -> 3/4 = 0.75; L = -1 -> clamped to 0; L = inf -> 1.
// value of (0.5, 1.5, 0.5) = 0.2126 * 0.5 + 0.7152 * 0.75 + 0.0722 * 0.5 = 0.6788.
TEST(ToneMap, ApplyByHand) {
  const ToneMap tone{2.0f};
  const vec3 t = tone.apply(vec3(0.5f, 1.5f, -1.0f));
  EXPECT_FLOAT_EQ(t.x, 0.5f);
  EXPECT_FLOAT_EQ(t.y, 0.75f);
  EXPECT_EQ(t.z, 0.0f);
  EXPECT_EQ(tone.apply(vec3(kInf)).x, 1.0f);
  EXPECT_NEAR(tone.value(vec3(0.5f, 1.5f, 0.5f)), 0.6788f, 1e-6f);
}

TEST(ToneMap, InvertUndoesApply) {
  for (float key : {0.3f, 1.0f, 2.5f}) {
    const ToneMap tone{key};
    for (float l : {0.0f, 1e-3f, 0.05f, 0.18f, 0.5f, 1.0f, 3.0f, 10.0f}) {
      const vec3 back = tone.invert(tone.apply(vec3(l, 2.0f * l, 0.5f * l)));
      EXPECT_NEAR(back.x, l, 1e-5f * (1.0f + l)) << "key " << key;
      EXPECT_NEAR(back.y, 2.0f * l, 1e-5f * (1.0f + 2.0f * l)) << "key " << key;
      EXPECT_NEAR(back.z, 0.5f * l, 1e-5f * (1.0f + l)) << "key " << key;
    }
    for (float t : {0.0f, 0.1f, 0.5f, 0.9f})
      EXPECT_NEAR(tone.apply(tone.invert(vec3(t))).x, t, 1e-6f);
  }
  // t = 1 would be infinite radiance; it is clamped to 1 - 1e-6, which in float (spacing 6e-8
  // below 1) is 1 - 1.0133e-6, so L = 0.99999899 / 1.0133e-6 = 986894 with k = 1.
  const vec3 top = ToneMap{1.0f}.invert(vec3(1.0f));
  EXPECT_TRUE(std::isfinite(top.x));
  EXPECT_NEAR(top.x, 986894.0f, 1.0f);
  EXPECT_EQ(ToneMap{1.0f}.invert(vec3(-0.5f)).x, 0.0f);
}

// Phi = {0.3, 0.45, 0.7, 0.85}; the index is the number of thresholds <= bias, so a value on a
// threshold goes to the narrower filter.
TEST(Reconstruct, AlphaIndexAtEachThreshold) {
  const FilterConfig config;
  const std::vector<float>& phi = config.phi;
  EXPECT_EQ(alphaIndexForBias(0.0f, phi), 0);
  EXPECT_EQ(alphaIndexForBias(0.2999f, phi), 0);
  EXPECT_EQ(alphaIndexForBias(0.3f, phi), 1);
  EXPECT_EQ(alphaIndexForBias(0.3001f, phi), 1);
  EXPECT_EQ(alphaIndexForBias(0.4499f, phi), 1);
  EXPECT_EQ(alphaIndexForBias(0.45f, phi), 2);
  EXPECT_EQ(alphaIndexForBias(0.4501f, phi), 2);
  EXPECT_EQ(alphaIndexForBias(0.6999f, phi), 2);
  EXPECT_EQ(alphaIndexForBias(0.7f, phi), 3);
  EXPECT_EQ(alphaIndexForBias(0.7001f, phi), 3);
  EXPECT_EQ(alphaIndexForBias(0.8499f, phi), 3);
  EXPECT_EQ(alphaIndexForBias(0.85f, phi), 4);
  EXPECT_EQ(alphaIndexForBias(0.8501f, phi), 4);
  EXPECT_EQ(alphaIndexForBias(100.0f, phi), 4);
  EXPECT_EQ(alphaIndexForBias(-1.0f, phi), 0);
  EXPECT_EQ(alphaIndexForBias(kInf, phi), 4);
  EXPECT_EQ(alphaIndexForBias(-kInf, phi), 0);
  EXPECT_EQ(alphaIndexForBias(kNaN, phi), int(config.alphas.size()) - 1);
}

// Eq. 18 on a 2x1 image, r = 1, alpha = 2, sigma_c = 0.5, k = 1. Pixel 0 is black (T = 0),
// pixel 1 is grey 1 (T = 1/2 per channel). The 3x3 windows are clipped to the two pixels.
//   spatial w = exp(-2 * 1 / 2) = e^-1;  range w = exp(-3 * 0.25 / (2 * 0.25)) = e^-1.5
//   w = e^-2.5 = 0.0820850;  out_0 = w * 1 / (1 + w) = 0.0758582;  out_1 = 1 / (1 + w) = 0.9241418
TEST(Reconstruct, BilateralPassByHandOnTwoPixels) {
  Image image(2, 1);
  image.pixels = {vec3(0.0f), vec3(1.0f)};
  const std::vector<float> alphas{2.0f, 2.0f};
  const Image out = bilateralPass(image, alphas, ToneMap{1.0f}, 1, 0.5f);
  const double w = std::exp(-2.5);
  EXPECT_NEAR(out.pixels[0].x, w / (1.0 + w), 1e-7);
  EXPECT_NEAR(out.pixels[0].z, 0.0758582, 1e-7);
  EXPECT_NEAR(out.pixels[1].y, 1.0 / (1.0 + w), 1e-7);
  EXPECT_NEAR(out.pixels[1].z, 0.9241418, 1e-7);
}

// Alpha is taken at the centre pixel: with alpha_0 = 0 (no spatial falloff) and alpha_1 huge,
// pixel 0 sees w = e^-1.5 (range term only) while pixel 1 keeps its own value.
//   out_0 = e^-1.5 / (1 + e^-1.5) = 0.1824255;  out_1 = (1 + e^-1001.5 * 0) / 1 = 1
TEST(Reconstruct, BilateralPassUsesTheCentrePixelsAlpha) {
  Image image(2, 1);
  image.pixels = {vec3(0.0f), vec3(1.0f)};
  const std::vector<float> alphas{0.0f, 2000.0f};
  const Image out = bilateralPass(image, alphas, ToneMap{1.0f}, 1, 0.5f);
  EXPECT_NEAR(out.pixels[0].x, 0.1824255, 1e-7);
  EXPECT_EQ(out.pixels[1].x, 1.0f);
}

// A tiny sigma_c makes 1 / (2 sigma_c^2) overflow float; the centre tap must still weigh 1
// (not 0 * inf = NaN) and the other colour 0.
TEST(Reconstruct, TinySigmaCKeepsEveryPixel) {
  Image image(2, 1);
  image.pixels = {vec3(0.0f), vec3(1.0f)};
  const Image out = bilateralPass(image, std::vector<float>{2.0f, 2.0f}, ToneMap{1.0f}, 1, 1e-30f);
  EXPECT_EQ(out.pixels[0].x, 0.0f);
  EXPECT_EQ(out.pixels[1].x, 1.0f);
}

TEST(Reconstruct, ConstantImagePassesThroughForAnyBias) {
  const vec3 value(0.3f, 0.5f, 0.7f);
  const Image image(13, 11, value);
  std::vector<float> bias = randomBias(image.pixels.size(), 3);
  bias[5] = kNaN;
  bias[6] = 2.0f;
  const FilterConfig config;
  const Reconstruction r = reconstruct(image, bias, toneMapFor(image), config);
  expectConstant(r.firstPass, value, 1e-6f);
  expectConstant(r.output, value, 1e-6f);
  ASSERT_EQ(r.alphaIndex.size(), bias.size());
  for (size_t i = 0; i < bias.size(); ++i)
    EXPECT_EQ(r.alphaIndex[i], alphaIndexForBias(bias[i], config.phi));
  EXPECT_EQ(r.alphaIndex[5], 4);
  EXPECT_EQ(r.alphaIndex[6], 4);
}

// A 9x9 image with r = 4: the corner's window is clipped to 5x5 of its 81 taps, and the
// centre's spans the whole image. Renormalising by the weights used keeps both at the
// constant, also with the widest alpha where all taps weigh almost the same.
TEST(Reconstruct, BordersAreRenormalised) {
  const vec3 value(2.0f, 0.25f, 0.0f);
  const Image image(9, 9, value);
  const ToneMap tone = toneMapFor(image);
  for (float alpha : {0.0f, 0.1f, 3.0f}) {
    const std::vector<float> alphas(image.pixels.size(), alpha);
    expectConstant(bilateralPass(image, alphas, tone, 4, 0.3f), value, 1e-6f);
  }
  FilterConfig config;
  const Reconstruction r =
      reconstruct(image, std::vector<float>(image.pixels.size(), 0.0f), tone, config);
  EXPECT_NEAR(r.output.at(0, 0).x, 2.0f, 1e-6f);
  EXPECT_NEAR(r.output.at(8, 8).y, 0.25f, 1e-6f);
}

// Left half 0.01, right half 10: the key is 0.18 / sqrt(0.0101 * 10.0001) = 0.5664, so
// T = 0.0056 vs 0.8500 per channel, |dT|^2 = 3 * 0.844^2 = 2.14 and the range weight across
// the edge is exp(-2.14 / 0.18) = 7e-6. Even with the widest alpha (a near box, so a pixel
// next to the edge has ~36 of its 81 taps across it) a left pixel moves by at most
// 36 * 7e-6 * 10 / 45 = 6e-5, and a right pixel by 10 * 36 * 7e-6 / 45 = 6e-5.
TEST(Reconstruct, RangeTermPreservesHighContrastEdge) {
  Image image(20, 10);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) image.at(x, y) = vec3(x < 10 ? 0.01f : 10.0f);
  const ToneMap tone = toneMapFor(image);
  EXPECT_NEAR(tone.key, 0.5664, 1e-3);
  const std::vector<float> lowBias(image.pixels.size(), 0.0f);  // alpha_1 = 0.1 everywhere
  const Reconstruction r = reconstruct(image, lowBias, tone, FilterConfig{});
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 20; ++x) {
      if (x < 10) {
        ASSERT_NEAR(r.output.at(x, y).y, 0.01f, 1e-4f) << x << "," << y;
      } else {
        ASSERT_NEAR(r.output.at(x, y).y, 10.0f, 1e-3f) << x << "," << y;
      }
    }
  }
  // Without the range term (sigma_c huge) the same filter smears the edge: the left pixel
  // next to it averages in roughly 36/81 of 10.
  FilterConfig noRange;
  noRange.sigmaC = 1e6f;
  const Reconstruction blurred = reconstruct(image, lowBias, tone, noRange);
  EXPECT_GT(blurred.output.at(9, 5).y, 2.0f);
}

// Grey 0.5 with +-20% uniform noise: low bias selects alpha_1 = 0.1 (nearly a 9x9 box,
// variance down by ~1/60), high bias alpha_5 = 10 (neighbours weigh e^-5 = 0.7%, so the
// variance barely changes). The range term hardly matters: |dT| < 0.05 per channel.
TEST(Reconstruct, NoisyFlatRegionIsSmoothedMoreWithLowBias) {
  const Image image = noisyImage(40, 40, 0.5f, 0.2f, 17);
  const ToneMap tone = toneMapFor(image);
  FilterConfig config;
  config.secondPass = false;  // compare the alphas themselves
  const Reconstruction low =
      reconstruct(image, std::vector<float>(image.pixels.size(), 0.1f), tone, config);
  const Reconstruction high =
      reconstruct(image, std::vector<float>(image.pixels.size(), 0.9f), tone, config);
  const double input = interiorVariance(image, 4);
  const double varLow = interiorVariance(low.output, 4);
  const double varHigh = interiorVariance(high.output, 4);
  EXPECT_LT(varLow, 0.05 * input);
  EXPECT_GT(varHigh, 0.8 * input);
  EXPECT_LT(varHigh, input);
  EXPECT_LT(varLow, 0.1 * varHigh);
}

TEST(Reconstruct, SecondPassUsesAlpha3Everywhere) {
  const Image image = noisyImage(24, 20, 0.4f, 0.5f, 23);
  const std::vector<float> bias = randomBias(image.pixels.size(), 29);
  const ToneMap tone = toneMapFor(image);
  FilterConfig config;
  const Reconstruction r = reconstruct(image, bias, tone, config);

  std::vector<float> alphaOf(bias.size());
  for (size_t i = 0; i < bias.size(); ++i)
    alphaOf[i] = config.alphas[size_t(alphaIndexForBias(bias[i], config.phi))];
  expectIdentical(r.firstPass, bilateralPass(image, alphaOf, tone, config.radius, config.sigmaC));
  const std::vector<float> alpha3(bias.size(), 3.0f);
  expectIdentical(r.output, bilateralPass(r.firstPass, alpha3, tone, config.radius, config.sigmaC));

  FilterConfig other = config;
  other.secondPassAlpha = 0;
  const Reconstruction widest = reconstruct(image, bias, tone, other);
  expectIdentical(widest.firstPass, r.firstPass);
  double difference = 0.0;
  for (size_t i = 0; i < r.output.pixels.size(); ++i)
    difference += std::abs(widest.output.pixels[i].y - r.output.pixels[i].y);
  EXPECT_GT(difference / double(r.output.pixels.size()), 1e-3);
}

TEST(Reconstruct, WithoutSecondPassOutputIsFirstPass) {
  const Image image = noisyImage(16, 12, 0.4f, 0.5f, 31);
  const std::vector<float> bias = randomBias(image.pixels.size(), 37);
  FilterConfig config;
  config.secondPass = false;
  config.secondPassAlpha = 99;  // ignored without a second pass
  const Reconstruction r = reconstruct(image, bias, toneMapFor(image), config);
  expectIdentical(r.output, r.firstPass);
  config.secondPass = true;
  config.secondPassAlpha = 2;
  expectIdentical(reconstruct(image, bias, toneMapFor(image), config).firstPass, r.firstPass);
}

// A NaN pixel stays NaN itself and is ignored by its neighbours, which stay at the constant.
TEST(Reconstruct, NonFinitePixelsDoNotSpread) {
  Image image(7, 7, vec3(0.6f));
  image.at(3, 3) = vec3(kNaN, 0.6f, 0.6f);
  image.at(0, 6) = vec3(kInf);
  const std::vector<float> alphas(image.pixels.size(), 0.1f);
  const Image out = bilateralPass(image, alphas, toneMapFor(image), 4, 0.3f);
  EXPECT_TRUE(std::isnan(out.at(3, 3).x));
  EXPECT_EQ(out.at(3, 3).y, 0.6f);
  EXPECT_TRUE(std::isinf(out.at(0, 6).x));
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 7; ++x) {
      if ((x == 3 && y == 3) || (x == 0 && y == 6)) continue;
      ASSERT_NEAR(out.at(x, y).x, 0.6f, 1e-6f) << x << "," << y;
    }
  }
}

TEST(Reconstruct, IdenticalForOneAndTwoThreads) {
  const Image image = noisyImage(67, 53, 0.3f, 0.9f, 41);
  const std::vector<float> bias = randomBias(image.pixels.size(), 43);
  const ToneMap tone = toneMapFor(image);
  Reconstruction one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = reconstruct(image, bias, tone, FilterConfig{});
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = reconstruct(image, bias, tone, FilterConfig{});
  }
  expectIdentical(one.firstPass, two.firstPass);
  expectIdentical(one.output, two.output);
}

TEST(Reconstruct, RejectsMismatchedSizesAndBadConfigurations) {
  const Image image(4, 3, vec3(0.5f));
  const ToneMap tone{1.0f};
  const std::vector<float> bias(image.pixels.size(), 0.5f);
  const std::vector<float> shortBias(image.pixels.size() - 1, 0.5f);
  EXPECT_THROW(reconstruct(image, shortBias, tone, FilterConfig{}), std::invalid_argument);
  EXPECT_THROW(bilateralPass(image, shortBias, tone, 4, 0.3f), std::invalid_argument);
  EXPECT_NO_THROW(reconstruct(image, bias, tone, FilterConfig{}));

  auto expectRejected = [&](auto change) {
    FilterConfig config;
    change(config);
    EXPECT_THROW(reconstruct(image, bias, tone, config), std::invalid_argument);
  };
  expectRejected([](FilterConfig& c) { c.phi.pop_back(); });
  expectRejected([](FilterConfig& c) { c.alphas.clear(); });
  expectRejected([](FilterConfig& c) { c.radius = -1; });
  expectRejected([](FilterConfig& c) { c.sigmaC = 0.0f; });
  expectRejected([](FilterConfig& c) { c.secondPassAlpha = 5; });
  expectRejected([](FilterConfig& c) { c.secondPassAlpha = -1; });
  expectRejected([](FilterConfig& c) { c.alphas[1] = kNaN; });
  expectRejected([](FilterConfig& c) { c.alphas[1] = -1.0f; });
  expectRejected([](FilterConfig& c) { c.phi = {0.3f, 0.7f, 0.45f, 0.85f}; });

  Image broken(4, 3);
  broken.pixels.pop_back();
  EXPECT_THROW(reconstruct(broken, shortBias, tone, FilterConfig{}), std::invalid_argument);
}

TEST(Reconstruct, EmptyImageGivesEmptyResult) {
  const Reconstruction r = reconstruct(Image{}, {}, ToneMap{}, FilterConfig{});
  EXPECT_TRUE(r.output.empty());
  EXPECT_TRUE(r.firstPass.empty());
  EXPECT_TRUE(r.alphaIndex.empty());
}

}  // namespace
}  // namespace penumbra
