// GEM's filterbank and greedy scale choice on hand-made images.
#include "methods/gem/gem.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

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

// GEM's MSE estimate of pixel (x, y) of noisyEdge(w, h, v) at scale s of `sigmas`, worked
// out independently of selectScales. The scales' estimates are unbiased blurs of the
// pixel means, so filtering at sigma leaves the variance of a weighted mean of
// independent pixels, v sum g^2 / (sum g)^2 (g the Gaussian taps, clipped at the image
// border, separably in x and y), and adds a squared bias that GEM estimates from the
// change of the estimate between consecutive scales, beta_s (I_{s-1} - I_s)^2 with
// beta_1 = 1 and beta_s = (sigma_s^2 + sigma_{s-1}^2) / (sigma_s^2 - sigma_{s-1}^2):
//   mse_s = v_0 + sum_{j <= s} (loss_j - gain_j) = V_s + sum_{j <= s} beta_j d_j^2,
// the variance removed (gain) telescoping to v_0 - V_s. The image is constant along y,
// so the blurred mean only depends on x.
struct Taps {
  std::vector<double> g;
  int radius;
};
Taps gaussianTaps(double sigma) {
  Taps t;
  t.radius = std::max(1, int(std::ceil(3.0 * sigma)));
  for (int i = -t.radius; i <= t.radius; ++i) t.g.push_back(std::exp(-i * i / (2 * sigma * sigma)));
  return t;
}
// sum g^2 / (sum g)^2 of the taps around i that fall inside [0, length).
double varianceFactor(const Taps& t, int i, int length) {
  double s1 = 0, s2 = 0;
  for (int j = std::max(0, i - t.radius); j <= std::min(length - 1, i + t.radius); ++j) {
    const double g = t.g[size_t(j - i + t.radius)];
    s1 += g;
    s2 += g * g;
  }
  return s2 / (s1 * s1);
}
double blurredMean(const Taps& t, int x, int w) {  // of noisyEdge's 0.1 | 0.9 profile
  double s = 0, sm = 0;
  for (int j = std::max(0, x - t.radius); j <= std::min(w - 1, x + t.radius); ++j) {
    const double g = t.g[size_t(j - x + t.radius)];
    s += g;
    sm += g * (j < w / 2 ? 0.1 : 0.9);
  }
  return sm / s;
}
// v sum g^2 / (sum g)^2 over x and y, divided by v: what the blur at sigma leaves of
// the variance of pixel (x, y)'s mean.
double filteredVarianceFactor(int x, int y, int w, int h, double sigma) {
  const Taps t = gaussianTaps(sigma);
  return varianceFactor(t, x, w) * varianceFactor(t, y, h);
}
struct MseParts {
  double variance = 0, squaredBias = 0;
  double total() const { return variance + squaredBias; }
};
MseParts expectedMse(int x, int y, int w, int h, double v, std::span<const float> sigmas,
                     int scale) {
  MseParts parts;
  parts.variance =
      scale == 0 ? v : v * filteredVarianceFactor(x, y, w, h, sigmas[size_t(scale - 1)]);
  double previousMean = x < w / 2 ? 0.1 : 0.9, previousSigma = 0;
  for (int s = 1; s <= scale; ++s) {
    const double sigma = sigmas[size_t(s - 1)];
    const double mean = blurredMean(gaussianTaps(sigma), x, w);
    const double beta = s == 1 ? 1.0
                               : (sigma * sigma + previousSigma * previousSigma) /
                                     (sigma * sigma - previousSigma * previousSigma);
    parts.squaredBias += beta * (previousMean - mean) * (previousMean - mean);
    previousMean = mean;
    previousSigma = sigma;
  }
  return parts;
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
  // The MSE estimate, derived above from the input alone (given each pixel's scale),
  // within 1e-3 relative: far below a factor-2 error, far above float rounding (~1e-5).
  // Beside the edge the first blur's squared bias (d ~ 0.17, d^2 ~ 0.03) dwarfs the 1e-3
  // of variance it could remove, so the pixel stays unfiltered and keeps the variance of
  // its mean. Far from it no blur reaches the edge (3 sigma = 24 < 30 pixels): none adds
  // bias and each removes variance, so the widest, sigma 8, is chosen and only the
  // variance of the blurred mean is left.
  const size_t far = size_t(8) * w + 2, edge = size_t(8) * w + w / 2;
  ASSERT_EQ(sel.scale[edge], 0);
  EXPECT_NEAR(sel.mse[edge], 1e-3, 1e-6);
  ASSERT_EQ(sel.scale[far], gem::finalScales().size());
  const double farMse = 1e-3 * filteredVarianceFactor(2, 8, w, h, 8.0);
  EXPECT_NEAR(sel.mse[far], farMse, 1e-3 * farMse);
  // Every pixel, the blurs that include the edge (where the squared-bias terms make up
  // to 60% of the estimate) among them.
  int withBias = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = size_t(y) * w + size_t(x);
      const MseParts e = expectedMse(x, y, w, h, 1e-3, gem::finalScales(), sel.scale[p]);
      withBias += e.squaredBias > 0.1 * e.total();
      EXPECT_NEAR(sel.mse[p], e.total(), 1e-3 * e.total())
          << x << "," << y << " at scale " << int(sel.scale[p]);
    }
  EXPECT_GT(withBias, 0);
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
