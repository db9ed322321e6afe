// The adaptive baselines' error measures on hand-made pixels, and the shared allocation
// framework on a real scene (the exact budget, determinism across threads) and on a floor
// half flat, half noisy (adaptivity: the samples go where the criterion says).
#include "methods/allocation.h"

#include "methods/cycles/cycles.h"
#include "methods/factory.h"
#include "methods/fdiv/fdiv.h"
#include "methods/fuzzy/fuzzy.h"
#include "methods/gem/gem.h"
#include "present/overlays.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace penumbra {
namespace {

using adaptive::LuminanceSums;

LuminanceSums sumsOf(std::initializer_list<double> values) {
  LuminanceSums s;
  for (double v : values) s.add(v);
  return s;
}

TEST(AdaptiveMeasures, EqualSamplesHaveNoDivergence) {
  const LuminanceSums s = sumsOf({0.3, 0.3, 0.3, 0.3});
  for (Divergence d : {Divergence::Hellinger, Divergence::KullbackLeibler, Divergence::ChiSquare}) {
    EXPECT_NEAR(adaptive::divergence(s, d), 0.0, 1e-12);
    EXPECT_NEAR(adaptive::fDivergenceScore(s, d), 0.0, 1e-7);
  }
}

TEST(AdaptiveMeasures, OneBrightSampleOfFour) {
  // p = (1, 0, 0, 0) against uniform 1/4.
  const LuminanceSums s = sumsOf({2.0, 0.0, 0.0, 0.0});
  EXPECT_NEAR(adaptive::divergence(s, Divergence::Hellinger), 0.5, 1e-12);
  EXPECT_NEAR(adaptive::divergence(s, Divergence::KullbackLeibler), std::log(4.0), 1e-12);
  EXPECT_NEAR(adaptive::divergence(s, Divergence::ChiSquare), 3.0, 1e-12);
  // Mean 0.5 x sqrt(0.5) / 4.
  EXPECT_NEAR(adaptive::fDivergenceScore(s, Divergence::Hellinger), 0.5 * std::sqrt(0.5) / 4,
              1e-12);
}

TEST(AdaptiveMeasures, HellingerMatchesItsDefinition) {
  const std::vector<double> L{0.1, 0.7, 0.05, 1.3, 0.4};
  LuminanceSums s;
  for (double v : L) s.add(v);
  const double total = std::accumulate(L.begin(), L.end(), 0.0);
  double h = 0;
  for (double v : L) h += std::pow(std::sqrt(v / total) - std::sqrt(1.0 / L.size()), 2);
  EXPECT_NEAR(adaptive::divergence(s, Divergence::Hellinger), 0.5 * h, 1e-12);
}

TEST(AdaptiveMeasures, ScoreFallsAsSamplesAccumulate) {
  LuminanceSums few = sumsOf({1.0, 0.0}), many;
  for (int i = 0; i < 32; ++i) many.add(i % 2 ? 1.0 : 0.0);
  EXPECT_GT(adaptive::fDivergenceScore(few, Divergence::Hellinger),
            adaptive::fDivergenceScore(many, Divergence::Hellinger));
  EXPECT_EQ(adaptive::fDivergenceScore(sumsOf({5.0}), Divergence::Hellinger), 0.0);
  EXPECT_EQ(adaptive::fDivergenceScore(sumsOf({0.0, 0.0}), Divergence::Hellinger), 0.0);
}

TEST(AdaptiveMeasures, FuzzyEntropy) {
  // Two-valued pixels are crisp: memberships 0 and 1 carry no fuzziness.
  const std::vector<float> crisp{0.0f, 1.0f, 0.0f, 1.0f};
  EXPECT_EQ(adaptive::fuzzyScore(crisp, 0.0, 1.0, 0.5, 4), 0.0);
  // {0, 0.5, 1}: only the middle one is fuzzy, with entropy ln 2 -> H_F = 1/3.
  const std::vector<float> three{0.0f, 0.5f, 1.0f};
  const double expected = (1.0 / 3.0) * (1.0 / (1.0 + 1e-4)) * 0.5 / std::sqrt(3.0);
  EXPECT_NEAR(adaptive::fuzzyScore(three, 0.0, 1.0, 0.5, 3), expected, 1e-9);
  // A flat pixel has no uncertainty.
  const std::vector<float> flat{0.4f, 0.4f, 0.4f};
  EXPECT_EQ(adaptive::fuzzyScore(flat, 0.4, 0.4, 0.4, 3), 0.0);
  // A dimmer pixel with the same shape scores lower.
  const std::vector<float> dim{0.0f, 0.05f, 0.1f};
  EXPECT_LT(adaptive::fuzzyScore(dim, 0.0, 0.1, 0.05, 3),
            adaptive::fuzzyScore(three, 0.0, 1.0, 0.5, 3));
}

TEST(AdaptiveMeasures, CyclesError) {
  EXPECT_EQ(adaptive::cyclesError(vec3(0.5f), vec3(0.5f)), 0.0);
  // Sum of I = 3 >= 1: divide by it. |diff| = 0.3.
  EXPECT_NEAR(adaptive::cyclesError(vec3(1.0f), vec3(1.1f, 1.0f, 0.8f)), 0.3 / (1e-4 + 3.0), 1e-6);
  // Sum of I = 0.25 < 1: divide by its square root.
  EXPECT_NEAR(adaptive::cyclesError(vec3(0.25f, 0.0f, 0.0f), vec3(0.35f, 0.0f, 0.0f)),
              0.1 / (1e-4 + 0.5), 1e-6);
}

TEST(AllocationConfig, Validates) {
  MethodSpec spec{RunShape{}, fdivMethod().defaults()};
  AllocationConfig& c = spec.config.as<FDivConfig>();
  EXPECT_EQ(validate(spec), "");
  EXPECT_EQ(c.effectiveInitialSpp(spec.shape), 4);
  EXPECT_EQ(c.effectiveBatch(spec.shape), 16);
  spec.shape.spp = 2;
  EXPECT_EQ(c.effectiveInitialSpp(spec.shape), 2);
  c.rounds = 0;  // the table's range
  EXPECT_NE(validate(spec).find("--rounds"), std::string::npos);
  c.rounds = 8;
  c.initialSpp = 3;  // the check beyond the table
  EXPECT_NE(validate(spec).find("--initial-spp"), std::string::npos);
}

using test::mapOf;
using test::runToEnd;

using Method = const MethodDescriptor*;

MethodSpec specFor(Method method, int spp, uint64_t seed) {
  return {RunShape::batch(spp, seed), method->defaults()};
}

// An open-ended run of roundSpp per round up to maxSpp.
MethodSpec openEndedSpecFor(Method method, int roundSpp, int maxSpp, uint64_t seed) {
  return {RunShape::progressive(roundSpp, seed, maxSpp), method->defaults()};
}

// The schedule every baseline's configuration shares.
AllocationConfig& allocationOf(MethodSpec& spec) {
  MethodConfig& c = spec.config;
  if (auto* f = c.get<FDivConfig>()) return *f;
  if (auto* f = c.get<FuzzyConfig>()) return *f;
  if (auto* g = c.get<GemConfig>()) return *g;
  if (auto* y = c.get<CyclesConfig>()) return *y;
  throw std::logic_error("not a baseline");
}

class Baseline : public ::testing::TestWithParam<Method> {};

TEST_P(Baseline, SpendsExactlyTheBudget) {
  auto prepared = test::shippedScene("cornell", 16);
  for (int spp : {5, 16}) {
    MethodSpec spec = specFor(GetParam(), spp, 2);
    allocationOf(spec).rounds = 3;
    auto method = makeMethod(*prepared, spec);
    const auto snap = runToEnd(*method);
    const uint64_t pixels = 16 * 16;
    EXPECT_EQ(snap->tracedSamples, uint64_t(spp) * pixels) << "spp " << spp;
    EXPECT_EQ(snap->keptSamples + snap->nonFiniteSamples, uint64_t(spp) * pixels);
    EXPECT_EQ(snap->round, 4);  // the initial pass and 3 rounds
    uint64_t perPixel = 0;
    for (float c : mapOf(*snap, maps::TracedCount)) perPixel += uint64_t(c);
    EXPECT_EQ(perPixel, snap->tracedSamples);
  }
}

// A floor under a uniform white sky, seen from straight above (image x is world x). The
// left half of the image is a uniform emitter that reflects nothing: every sample of a pixel
// there has exactly the same radiance, its emission. The right half is a diffuse checker of
// about 2.7 cells per pixel under the sky: its pixels' samples are 0.1 or 0.9 times the sky
// (and the noise of sampling it), so their means are noisy.
std::unique_ptr<PreparedScene> flatAndNoisyHalves(int width, int height) {
  Scene scene = parseSceneJson(R"({
    "render": {"max_depth": 4},
    "camera": {"eye": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 53.130102},
    "background": 1,
    "textures": {"fine": {"type": "checker", "colors": [0.1, 0.9], "scale": [96, 96]}},
    "materials": {"flat": {"type": "emissive", "radiance": 0.5},
                  "checker": {"type": "diffuse", "albedo": "fine"}},
    "objects": [
      {"shape": "rectangle", "size": [3, 3], "material": "flat",
       "transform": {"translate": [-1.5, 0, 0]}},
      {"shape": "rectangle", "size": [3, 3], "material": "checker",
       "transform": {"translate": [1.5, 0, 0]}}]})",
                               "halves.json", ".");
  scene.settings.width = width;
  scene.settings.height = height;
  return prepareScene(std::move(scene));
}

TEST_P(Baseline, ConcentratesSamples) {
  // The image (2:1; the fov 53.13 spans [-1, 1] vertically) is [-2, 2] x [-1, 1] of the
  // floor: columns 0-23 flat, 24-47 noisy, 1/12 unit per pixel.
  constexpr int kWidth = 48, kHeight = 24, kSpp = 16, kInitialSpp = 4;
  auto prepared = flatAndNoisyHalves(kWidth, kHeight);
  auto method = makeMethod(*prepared, specFor(GetParam(), kSpp, 1));
  const auto snap = runToEnd(*method);
  const std::vector<float>& tracedMap = mapOf(*snap, maps::TracedCount);
  ASSERT_EQ(tracedMap.size(), size_t(kWidth * kHeight));

  // Samples beyond the initial pass, in each half and in the flat pixels more than 8
  // pixels from the noisy half (GEM places a chosen pixel's samples through a Gaussian of
  // its filter scale, sigma up to 8, so some land in flat pixels near the noisy half).
  double flatExtra = 0, noisyExtra = 0, farFlatExtra = 0;
  int farFlatPixels = 0, unchosenWithMore = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const uint32_t traced = uint32_t(tracedMap[size_t(y * kWidth + x)]);
      ASSERT_GE(traced, uint32_t(kInitialSpp)) << x << "," << y;
      const double extra = traced - kInitialSpp;
      if (x >= kWidth / 2) {
        noisyExtra += extra;
        continue;
      }
      flatExtra += extra;
      if (x < kWidth / 2 - 8) {
        farFlatExtra += extra;
        ++farFlatPixels;
      }
      // A flat pixel's samples agree, so its score is 0 and it is never chosen: with
      // FDiv and fuzzy it keeps its initial pass; Cycles dilates the chosen set by one
      // pixel, so only the flat column beside the noisy half may get more.
      if (GetParam() == &fdivMethod() || GetParam() == &fuzzyMethod() ||
          (GetParam() == &cyclesMethod() && x < kWidth / 2 - 1)) {
        unchosenWithMore += traced != uint32_t(kInitialSpp);
      }
    }
  EXPECT_EQ(unchosenWithMore, 0) << "flat pixels that got more than the initial pass";
  const double adaptive = double(kSpp - kInitialSpp) * kWidth * kHeight;
  EXPECT_EQ(flatExtra + noisyExtra, adaptive);
  // A score that ignored the samples (a random one, say) would spread the adaptive
  // samples evenly: its 864 batches of 16 would land half in each half (a fraction of
  // 0.5 +- 0.02), and a far-flat pixel would get as many as a noisy one on average (a
  // ratio of 1 +- 0.05), and flat pixels would be chosen. The criteria must put at least
  // three quarters of the adaptive samples in the noisy half, and give a noisy pixel at
  // least 3 times what a far-flat pixel gets.
  EXPECT_GE(noisyExtra, 0.75 * adaptive) << "flat half got " << flatExtra;
  const double noisyMean = kInitialSpp + noisyExtra / (kWidth * kHeight / 2);
  const double farFlatMean = kInitialSpp + farFlatExtra / farFlatPixels;
  EXPECT_GE(noisyMean, 3 * farFlatMean);

  const SnapshotMap* score = snap->map(maps::ErrorEstimate);
  ASSERT_NE(score, nullptr);
  ASSERT_EQ(score->values.size(), size_t(kWidth * kHeight));
  EXPECT_GT(*std::max_element(score->values.begin(), score->values.end()), 0.0f);
  // A score has no fixed scale: its colour bar ends at its 99th percentile.
  EXPECT_EQ(score->legend.maxValue, percentileOf(score->values, 0.99f));
  EXPECT_EQ(snap->method, GetParam()->name());
}

TEST_P(Baseline, SameImageWhateverTheThreadCount) {
  auto prepared = test::shippedScene("cornell", 20);
  const MethodSpec spec = specFor(GetParam(), 12, 7);
  std::shared_ptr<Snapshot> one, many;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    auto method = makeMethod(*prepared, spec);
    one = runToEnd(*method);
  }
  {
    auto method = makeMethod(*prepared, spec);
    many = runToEnd(*method);
  }
  EXPECT_EQ(one->raw.pixels, many->raw.pixels);
  EXPECT_EQ(one->reconstructed.pixels, many->reconstructed.pixels);
  EXPECT_EQ(mapOf(*one, maps::TracedCount), mapOf(*many, maps::TracedCount));
  // Another seed gives another image.
  auto other = makeMethod(*prepared, specFor(GetParam(), 12, 8));
  EXPECT_NE(runToEnd(*other)->raw.pixels, one->raw.pixels);
}

TEST_P(Baseline, OpenEndedRoundsAndInspection) {
  auto prepared = test::shippedScene("cornell", 16);
  const MethodSpec spec = openEndedSpecFor(GetParam(), 2, 10, 3);
  auto method = makeMethod(*prepared, spec);
  EXPECT_FALSE(method->inspect(3, 3).valid);
  method->runRound(nullptr);  // initial pass: 4 spp
  EXPECT_EQ(method->snapshot(false)->tracedSamples, 4u * 256);
  method->runRound(nullptr);
  EXPECT_EQ(method->snapshot(false)->tracedSamples, 6u * 256);
  const auto snap = runToEnd(*method);
  EXPECT_EQ(snap->tracedSamples, 10u * 256);
  const PixelInspection in = method->inspect(8, 8);
  ASSERT_TRUE(in.valid);
  EXPECT_EQ(in.method, GetParam()->name());
  EXPECT_EQ(float(in.traced), mapOf(*snap, maps::TracedCount)[8 * 16 + 8]);
  // The score is the method's own value, labelled as that score.
  ASSERT_NE(in.value(maps::ErrorEstimate), nullptr);
  EXPECT_EQ(in.value(maps::ErrorEstimate)->label, snap->map(maps::ErrorEstimate)->label);
  EXPECT_FALSE(in.subpixel.has_value());  // the baselines store no samples
  EXPECT_FALSE(in.reason.empty());
  EXPECT_GE(in.rank, 0);
  EXPECT_FALSE(method->inspect(16, 0).valid);
}

// The noise threshold: the run stops once the shown image's mean estimated relMSE is below
// it, and a pixel already below it gets no more samples meanwhile.
TEST_P(Baseline, StopsOnTheNoiseThreshold) {
  auto prepared = test::shippedScene("cornell", 16);
  MethodSpec spec = openEndedSpecFor(GetParam(), 4, 4096, 3);
  spec.shape.noiseThreshold = 0.01f;
  auto method = makeMethod(*prepared, spec);
  auto& baseline = dynamic_cast<AllocationMethod&>(*method);
  int skipped = 0;
  for (int rounds = 0; !method->done() && rounds < 2000; ++rounds) {
    const std::vector<float> error = baseline.shownRelativeError();
    const std::vector<float> before = mapOf(*method->snapshot(false), maps::TracedCount);
    method->runRound(nullptr);
    if (rounds == 0) continue;  // the first pass samples every pixel
    const std::vector<float> after = mapOf(*method->snapshot(false), maps::TracedCount);
    for (size_t p = 0; p < 256; ++p)
      if (error[p] < spec.shape.noiseThreshold) {
        EXPECT_EQ(after[p], before[p]) << "pixel " << p << " was below the threshold";
        ++skipped;
      }
  }
  EXPECT_GT(skipped, 0);
  ASSERT_TRUE(method->done()) << "never reached the threshold";
  EXPECT_LT(method->estimatedError(), 0.01);
  const auto snap = method->snapshot(false);
  EXPECT_LT(snap->tracedSamples, 4096u * 256) << "stopped by the threshold, not the cap";
  // Not uniform: the pixels that converged first got fewer samples.
  const std::vector<float>& traced = mapOf(*snap, maps::TracedCount);
  EXPECT_LT(*std::min_element(traced.begin(), traced.end()),
            *std::max_element(traced.begin(), traced.end()));
  // The variance of the mean, for --variance-out.
  const Image variance = method->rawVarianceOfMean();
  ASSERT_EQ(variance.pixels.size(), 256u);
  EXPECT_GT(variance.pixels[8 * 16 + 8].x, 0.0f);
}

TEST_P(Baseline, ViewerOverlaysHaveTheirMaps) {
  auto prepared = test::shippedScene("cornell", 16);
  auto method = makeMethod(*prepared, specFor(GetParam(), 8, 1));
  const auto snap = runToEnd(*method);
  for (MapId o : {MapId(maps::ErrorEstimate), MapId(maps::Selected), MapId(maps::SampleCount),
                  MapId(maps::TracedCount)}) {
    const OverlayImage image = buildOverlay(*snap, o, snap->reconstructed, nullptr);
    EXPECT_TRUE(image.available()) << o.name() << ": " << image.unavailable;
  }
  const OverlayImage bias = buildOverlay(*snap, maps::ErrorEstimate, snap->reconstructed, nullptr);
  // Labelled as the criterion's own score, not as BP's bias.
  EXPECT_EQ(bias.label, snap->map(maps::ErrorEstimate)->label);
  EXPECT_NE(bias.label, "bias");
  EXPECT_GT(bias.legend.maxValue, 0.0f);
  // The filter scale: GEM has its own, labelled by sigma; the box-mean criteria none.
  const OverlayImage scale = buildOverlay(*snap, maps::FilterScale, snap->reconstructed, nullptr);
  if (GetParam() == &gemMethod()) {
    ASSERT_TRUE(scale.available());
    ASSERT_EQ(scale.legend.categories.size(), 9u);
    EXPECT_EQ(scale.legend.categories[1], "s=0.71");
  } else {
    EXPECT_FALSE(scale.available());
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, Baseline,
                         ::testing::Values(&fdivMethod(), &fuzzyMethod(), &gemMethod(),
                                           &cyclesMethod()),
                         [](const auto& info) { return info.param->name(); });

}  // namespace
}  // namespace penumbra
