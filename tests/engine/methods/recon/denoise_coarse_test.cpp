// Tests for engine/methods/recon/denoise's coarse reconstruction (denoiseCoarse): it removes
// most of a low-count image's noise, close to the full reconstruction, while textures,
// geometry edges and lights stay at full resolution; odd sizes and non-finite pixels work;
// bands and thread counts give the same bits; and coarseConfig halves the bank.
#include "methods/recon/denoise.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace penumbra::recon {
namespace {

// An image as a renderer hands it over, with its clean values.
struct Picture {
  int width = 0, height = 0;
  std::vector<vec3> clean, mean, variance, halfA, halfB, emission, albedo, normal;
  std::vector<float> depth;

  Picture(int w, int h) : width(w), height(h) {
    const size_t n = size_t(w) * size_t(h);
    for (auto* v : {&clean, &mean, &variance, &halfA, &halfB, &emission, &albedo, &normal})
      v->assign(n, vec3(0.0f));
    depth.assign(n, 1.0f);
  }
  size_t at(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }

  // Noisy halves of sigma per pixel around the clean values (each half's mean has twice the
  // variance of the whole).
  void addNoise(const std::vector<float>& sigma, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    for (size_t p = 0; p < clean.size(); ++p) {
      const float s = std::sqrt(2.0f) * sigma[p];
      halfA[p] = clean[p] + s * vec3(gauss(rng), gauss(rng), gauss(rng));
      halfB[p] = clean[p] + s * vec3(gauss(rng), gauss(rng), gauss(rng));
      mean[p] = 0.5f * (halfA[p] + halfB[p]);
      variance[p] = vec3(sigma[p] * sigma[p]);
    }
  }

  DenoiseInput input() const {
    DenoiseInput in;
    in.width = width;
    in.height = height;
    in.mean = mean, in.variance = variance, in.halfA = halfA, in.halfB = halfB;
    in.emission = emission, in.albedo = albedo, in.normal = normal, in.depth = depth;
    return in;
  }
};

using test::mse;

// A checker of 3-pixel squares (albedo 0.2 / 0.8: finer than the blocks) under smooth light,
// with noise of sigma 0.35 x light: about what one sample per pixel gives.
Picture checker(int w, int h, uint32_t seed) {
  Picture s(w, h);
  std::vector<float> sigma(s.clean.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = s.at(x, y);
      const float a = ((x / 3) + (y / 3)) % 2 ? 0.8f : 0.2f;
      const float light = 0.6f + 0.4f * float(x) / float(w) + 0.3f * float(y) / float(h);
      s.albedo[p] = vec3(a);
      s.normal[p] = vec3(0.0f, 0.0f, 1.0f);
      s.clean[p] = vec3(a * light);
      sigma[p] = 0.35f * light;
    }
  }
  s.addNoise(sigma, seed);
  return s;
}

TEST(DenoiseCoarse, RemovesMostNoiseAndKeepsATextureFinerThanItsBlocks) {
  const Picture s = checker(128, 96, 3);
  const DenoiseResult coarse = denoiseCoarse(s.input(), DenoiseConfig{});
  const DenoiseResult full = denoise(s.input(), DenoiseConfig{});
  const double raw = mse(s.mean, s.clean);
  const double coarseMse = mse(coarse.output.pixels, s.clean);
  const double fullMse = mse(full.output.pixels, s.clean);
  EXPECT_LT(coarseMse, 0.1 * raw) << "raw " << raw << ", full " << fullMse;
  EXPECT_LT(coarseMse, 2.0 * fullMse) << "raw " << raw;
  // The checker's contrast across its vertical edges survives (albedo multiplies back in).
  double contrast = 0.0, truth = 0.0;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 3; x < s.width; x += 3) {
      contrast +=
          std::abs(coarse.output.pixels[s.at(x, y)].y - coarse.output.pixels[s.at(x - 1, y)].y);
      truth += std::abs(s.clean[s.at(x, y)].y - s.clean[s.at(x - 1, y)].y);
    }
  }
  EXPECT_NEAR(contrast, truth, 0.1 * truth);
}

TEST(DenoiseCoarse, GeometryEdgesThroughABlockAndLightsStaySharp) {
  // Two surfaces meeting at x = 33 (inside the block of pixels 32 and 33), lit 0.2 and 1.0, with
  // hardly any noise, and one directly seen light.
  Picture s(64, 48);
  std::vector<float> sigma(s.clean.size(), 1e-4f);
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const size_t p = s.at(x, y);
      const bool right = x >= 33;
      s.albedo[p] = vec3(0.5f);
      s.normal[p] = right ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
      s.depth[p] = right ? 2.0f : 1.0f;
      s.clean[p] = vec3(right ? 0.5f : 0.1f);
    }
  }
  const size_t light = s.at(20, 21);
  s.emission[light] = vec3(5.0f);
  s.clean[light] += vec3(5.0f);
  s.addNoise(sigma, 5);
  const DenoiseResult r = denoiseCoarse(s.input(), DenoiseConfig{});
  for (size_t p = 0; p < s.clean.size(); ++p)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(r.output.pixels[p][c], s.clean[p][c], 0.02 * s.clean[p][c])
          << "pixel " << p % s.width << ", " << p / s.width;
}

TEST(DenoiseCoarse, OddSizesAndNonFinitePixels) {
  Picture s = checker(37, 23, 9);
  const size_t bad = s.at(17, 11);
  s.mean[bad].y = std::numeric_limits<float>::quiet_NaN();
  s.variance[s.at(4, 4)] = vec3(std::numeric_limits<float>::infinity());
  const DenoiseConfig config;
  const DenoiseResult r = denoiseCoarse(s.input(), config);
  ASSERT_EQ(r.output.width, 37);
  ASSERT_EQ(r.output.height, 23);
  ASSERT_EQ(r.scale.size(), s.clean.size());
  for (size_t p = 0; p < s.clean.size(); ++p) {
    EXPECT_LE(r.scale[p], config.radii.size());
    if (p == bad) {
      EXPECT_TRUE(std::isnan(r.output.pixels[p].y)) << "a non-finite pixel keeps its mean";
      EXPECT_EQ(r.scale[p], 0);
    } else {
      EXPECT_TRUE(isFinite(r.output.pixels[p])) << "pixel " << p;
    }
  }
}

bool sameBits(const DenoiseResult& a, const DenoiseResult& b) {
  return a.output.pixels.size() == b.output.pixels.size() &&
         !std::memcmp(a.output.pixels.data(), b.output.pixels.data(),
                      a.output.pixels.size() * sizeof(vec3)) &&
         a.scale == b.scale &&
         !std::memcmp(a.mseEstimate.data(), b.mseEstimate.data(),
                      a.mseEstimate.size() * sizeof(float));
}

TEST(DenoiseCoarse, SameBitsInBandsAndForOneOrTwoThreads) {
  const Picture s = checker(90, 61, 11);
  const DenoiseInput in = s.input();
  const DenoiseResult whole = denoiseCoarse(in, DenoiseConfig{});
  int asked = 0;
  auto rows = [&](int first, int last) {
    ++asked;
    return rowsOf(in, first, last);
  };
  for (int band : {1, 7, 16, 61}) {
    const DenoiseResult bands = denoiseCoarse(90, 61, DenoiseConfig{}, band, rows, rows);
    EXPECT_TRUE(sameBits(whole, bands)) << "bands of " << band << " rows";
  }
  EXPECT_GT(asked, 8);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_TRUE(sameBits(whole, denoiseCoarse(in, DenoiseConfig{})));
}

TEST(DenoiseCoarse, ItsConfigurationHalvesTheBank) {
  const DenoiseConfig half = coarseConfig(DenoiseConfig{});
  EXPECT_EQ(half.radii, (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(half.denseRadius, 2);
  EXPECT_EQ(half.sureSmoothRadius, 3);
  EXPECT_EQ(half.coarseReconSpp, 0);
  EXPECT_EQ(validate(half), "");
  DenoiseConfig odd;
  odd.radii = {1, 3, 6};
  odd.denseRadius = 4;
  const DenoiseConfig oddHalf = coarseConfig(odd);
  EXPECT_EQ(oddHalf.radii, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(validate(oddHalf), "") << "radius 3 next to dense radius 2 is made dense";
}

TEST(DenoiseCoarse, RejectsABadConfigurationOrSource) {
  const Picture s = checker(16, 16, 1);
  DenoiseConfig bad;
  bad.radii = {4, 2};
  EXPECT_THROW(denoiseCoarse(s.input(), bad), std::invalid_argument);
  auto wrong = [&](int first, int last) { return rowsOf(s.input(), first, last - 1); };
  EXPECT_THROW(denoiseCoarse(16, 16, DenoiseConfig{}, 8, wrong, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::recon
