// GEM's filterbank and greedy scale choice on hand-made images.
#include "methods/gem.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

TEST(GemFilter, KeepsConstantsAndShrinksVariance) {
  const int w = 20, h = 14;
  std::vector<float> ones(size_t(w) * h, 1.0f), out(ones.size());
  gem::gaussianFilter(ones, out, w, h, 1, 2.0f, false);
  for (float v : out) EXPECT_NEAR(v, 1.0f, 1e-6f);
  // Variance of a filtered mean of i.i.d. values: v sum g^2 / (sum g)^2 < v, and more so
  // in the middle (wider support) than at a corner.
  gem::gaussianFilter(ones, out, w, h, 1, 2.0f, true);
  const float middle = out[size_t(7) * w + 10], corner = out[0];
  EXPECT_LT(middle, corner);
  EXPECT_LT(corner, 1.0f);
  double g1 = 0, g2 = 0;  // 1-D taps cut at 3 sigma = 6
  for (int i = -6; i <= 6; ++i) {
    const double g = std::exp(-i * i / 8.0);
    g1 += g;
    g2 += g * g;
  }
  EXPECT_NEAR(middle, (g2 / (g1 * g1)) * (g2 / (g1 * g1)), 1e-5);
}

TEST(GemFilter, RejectsSizeMismatch) {
  std::vector<float> a(10), b(12);
  EXPECT_THROW(gem::gaussianFilter(a, b, 5, 2, 1, 1.0f, false), std::invalid_argument);
}

TEST(GemScales, ConstantsAndGamma) {
  EXPECT_NEAR(gem::cGamma(0.2), 0.70, 0.01);
  ASSERT_EQ(gem::finalScales().size(), 8u);
  EXPECT_NEAR(gem::finalScales().front(), 0.7071f, 1e-4f);
  EXPECT_NEAR(gem::finalScales().back(), 8.0f, 1e-4f);
  EXPECT_EQ(gem::samplingScales(), (std::vector<float>{1, 2, 4, 8}));
}

gem::PixelStatistics noisyEdge(int w, int h, float variance) {
  gem::PixelStatistics s;
  s.width = w;
  s.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s.mean.push_back(vec3(x < w / 2 ? 0.1f : 0.9f));
      s.variance.push_back(vec3(variance));
      s.count.push_back(8.0f);
    }
  return s;
}

TEST(GemScales, FlatNoisyRegionsGoCoarseAndEdgesStayFine) {
  const int w = 64, h = 16;
  const gem::ScaleSelection sel =
      gem::selectScales(noisyEdge(w, h, 1e-3f), gem::finalScales(), 0.2, true);
  const auto at = [&](int x, int y) { return sel.scale[size_t(y) * w + x]; };
  // Next to the edge the squared bias of any blur outweighs the variance it removes.
  EXPECT_LE(at(w / 2, 8), 2);
  EXPECT_LE(at(w / 2 - 1, 8), 2);
  // Far from it (more than 3 sigma of the widest scale away is outside this image, so
  // compare): the far left is filtered more than the pixel beside the edge.
  EXPECT_GT(at(2, 8), at(w / 2 - 1, 8));
  EXPECT_GE(at(2, 8), 4);
  // The MSE estimate drops where filtering removed variance.
  EXPECT_LT(sel.mse[size_t(8) * w + 2], 1e-3f);
  EXPECT_NEAR(sel.mse[size_t(8) * w + w / 2], 1e-3f, 1e-3f);
}

TEST(GemScales, NoVarianceMeansNoFiltering) {
  const gem::ScaleSelection sel =
      gem::selectScales(noisyEdge(32, 8, 0.0f), gem::samplingScales(), 0.2, false);
  for (uint8_t s : sel.scale) EXPECT_EQ(s, 0);
  for (float m : sel.mse) EXPECT_EQ(m, 0.0f);
}

TEST(GemScales, PixelErrorIsRelativeMseTimesGain) {
  gem::ScaleSelection s;
  s.mse = {0.01f};
  s.count = {16.0f};
  s.estimate = {vec3(0.5f)};
  s.scale = {1};
  EXPECT_NEAR(gem::pixelError(s, 0, 16), 0.01 / (1e-3 + 0.25) * 0.5, 1e-6);
}

}  // namespace
}  // namespace penumbra
