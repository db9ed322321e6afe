// Tests for engine/methods/recon/denoise's bands: denoiseInBands gives the whole image's
// result bit for bit whatever the band height and configuration, with edges, varying features,
// non-finite pixels and images narrower than the halo; and it asks its source for each band's
// rows in turn.
#include "methods/recon/denoise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace penumbra::recon {
namespace {

// A noisy image with edges in colour and in every feature, and two bad pixels.
struct Noisy {
  int width, height;
  std::vector<vec3> mean, variance, halfA, halfB, emission, albedo, albedoVariance, normal;
  std::vector<float> normalVariance, depth, depthVariance;

  Noisy(int w, int h, uint32_t seed) : width(w), height(h) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    const size_t n = size_t(w) * size_t(h);
    for (auto* v : {&mean, &variance, &halfA, &halfB, &emission, &albedo, &albedoVariance, &normal})
      v->resize(n);
    for (auto* v : {&normalVariance, &depth, &depthVariance}) v->resize(n);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t p = size_t(y) * w + x;
        const bool right = x > w / 2 + y / 3, low = y > h / 2;
        const vec3 clean =
            vec3(0.2f + 0.01f * float(x % 17), right ? 0.8f : 0.3f, low ? 1.5f : 0.4f);
        const float sigma = 0.05f + 0.1f * float((x * 7 + y * 3) % 5);
        halfA[p] = clean + 1.41f * sigma * vec3(gauss(rng), gauss(rng), gauss(rng));
        halfB[p] = clean + 1.41f * sigma * vec3(gauss(rng), gauss(rng), gauss(rng));
        mean[p] = 0.5f * (halfA[p] + halfB[p]);
        variance[p] = vec3(sigma * sigma);
        emission[p] = (x + y) % 29 == 0 ? vec3(2.0f) : vec3(0.0f);
        albedo[p] = right ? vec3(0.7f, 0.6f, 0.5f) : vec3(0.2f, 0.3f, 0.4f);
        albedoVariance[p] = vec3(1e-3f * float(x % 3));
        normal[p] = low ? vec3(0.0f, 0.0f, 1.0f) : vec3(0.6f, 0.0f, 0.8f);
        normalVariance[p] = 1e-3f * float(y % 4);
        depth[p] = 1.0f + 0.02f * float(y) + (right ? 0.5f : 0.0f);
        depthVariance[p] = 1e-4f;
      }
    }
    if (n > 40) {
      mean[n / 2].y = std::numeric_limits<float>::quiet_NaN();
      variance[n / 3] = vec3(std::numeric_limits<float>::infinity());
    }
  }

  DenoiseInput input() const {
    DenoiseInput in;
    in.width = width;
    in.height = height;
    in.mean = mean;
    in.variance = variance;
    in.halfA = halfA;
    in.halfB = halfB;
    in.emission = emission;
    in.albedo = albedo;
    in.albedoVariance = albedoVariance;
    in.normal = normal;
    in.normalVariance = normalVariance;
    in.depth = depth;
    in.depthVariance = depthVariance;
    return in;
  }
};

// Bit for bit, NaN equal to NaN.
bool same(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

void expectSameResult(const DenoiseResult& whole, const DenoiseResult& bands, const char* what) {
  ASSERT_EQ(whole.output.pixels.size(), bands.output.pixels.size()) << what;
  ASSERT_EQ(whole.output.width, bands.output.width) << what;
  ASSERT_EQ(whole.output.height, bands.output.height) << what;
  for (size_t p = 0; p < whole.output.pixels.size(); ++p) {
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(same(whole.output.pixels[p][c], bands.output.pixels[p][c]))
          << what << ", pixel " << p << " channel " << c;
    ASSERT_EQ(whole.scale[p], bands.scale[p]) << what << ", pixel " << p;
    ASSERT_TRUE(same(whole.mseEstimate[p], bands.mseEstimate[p])) << what << ", pixel " << p;
    ASSERT_TRUE(same(whole.varianceRatio[p], bands.varianceRatio[p])) << what << ", pixel " << p;
  }
}

TEST(DenoiseBands, SameBitsAsTheWholeImageForAnyBandHeight) {
  const Noisy s(61, 73, 3);
  const DenoiseResult whole = denoise(s.input(), DenoiseConfig{});
  for (int rows : {1, 2, 5, 16, 30, 72, 73, 500}) {
    const DenoiseResult bands = denoiseInBands(s.input(), DenoiseConfig{}, rows);
    expectSameResult(whole, bands, ("band rows " + std::to_string(rows)).c_str());
  }
}

TEST(DenoiseBands, SameBitsAsTheWholeImageForOtherConfigurations) {
  const Noisy s(47, 58, 4);
  std::vector<std::pair<const char*, DenoiseConfig>> configs;
  auto add = [&](const char* name, auto&& change) {
    DenoiseConfig c;
    change(c);
    configs.push_back({name, c});
  };
  add("patch 2", [](DenoiseConfig& c) { c.patchRadius = 2; });
  add("patch 4", [](DenoiseConfig& c) { c.patchRadius = 4; });
  add("no SURE box", [](DenoiseConfig& c) { c.sureSmoothRadius = 0; });
  add("SURE box 9", [](DenoiseConfig& c) { c.sureSmoothRadius = 9; });
  add("radii 1, 3, 12", [](DenoiseConfig& c) { c.radii = {1, 3, 12}; });
  add("no cross-filter", [](DenoiseConfig& c) { c.crossFilter = false; });
  add("no features", [](DenoiseConfig& c) { c.useFeatures = false; });
  add("no demodulation", [](DenoiseConfig& c) { c.demodulate = false; });
  for (const auto& [name, config] : configs) {
    const DenoiseResult whole = denoise(s.input(), config);
    for (int rows : {3, 11}) expectSameResult(whole, denoiseInBands(s.input(), config, rows), name);
  }
}

TEST(DenoiseBands, ImagesNarrowerOrShorterThanTheHalo) {
  for (const auto& [w, h] :
       {std::pair{1, 40}, std::pair{40, 1}, std::pair{3, 5}, std::pair{2, 90}}) {
    const Noisy s(w, h, 5);
    const DenoiseResult whole = denoise(s.input(), DenoiseConfig{});
    expectSameResult(whole, denoiseInBands(s.input(), DenoiseConfig{}, 4), "small");
  }
}

TEST(DenoiseBands, AsksTheSourceForEachBandsRowsInTurn) {
  const Noisy s(20, 50, 6);
  const DenoiseInput whole = s.input();
  std::vector<std::pair<int, int>> asked;
  DenoiseConfig config;  // halo: 5 + 8 + 1 + 1 = 15 rows
  const DenoiseResult r = denoiseInBands(20, 50, config, 20, [&](int first, int last) {
    asked.push_back({first, last});
    DenoiseInput in = whole;
    in.height = last - first;
    const size_t at = size_t(first) * 20, count = size_t(last - first) * 20;
    for (auto* span : {&in.mean, &in.variance, &in.halfA, &in.halfB, &in.emission, &in.albedo,
                       &in.albedoVariance, &in.normal})
      *span = span->subspan(at, count);
    for (auto* span : {&in.normalVariance, &in.depth, &in.depthVariance})
      *span = span->subspan(at, count);
    return in;
  });
  const std::vector<std::pair<int, int>> expected{{0, 35}, {5, 50}, {25, 50}};
  EXPECT_EQ(asked, expected);
  expectSameResult(denoise(whole, config), r, "source");
}

TEST(DenoiseBands, RejectsABadSourceOrBandHeight) {
  const Noisy s(10, 10, 7);
  EXPECT_THROW(denoiseInBands(s.input(), DenoiseConfig{}, 0), std::invalid_argument);
  // The first band of a 60-row image needs rows 0 to 19, not the 10 given.
  EXPECT_THROW(denoiseInBands(10, 60, DenoiseConfig{}, 4, [&](int, int) { return s.input(); }),
               std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::recon
