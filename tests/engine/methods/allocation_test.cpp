// The adaptive baselines' error measures on hand-made pixels, and the shared allocation
// framework on a real scene: the exact budget, adaptivity, determinism across threads.
#include "methods/allocation.h"

#include "methods/factory.h"
#include "present/overlays.h"
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
  AllocationConfig c;
  EXPECT_EQ(c.validate(), "");
  EXPECT_EQ(c.effectiveInitialSpp(), 4);
  EXPECT_EQ(c.effectiveBatch(), 16);
  c.spp = 2;
  EXPECT_EQ(c.effectiveInitialSpp(), 2);
  c.rounds = 0;
  EXPECT_NE(c.validate().find("rounds"), std::string::npos);
  c.rounds = 8;
  c.initialSpp = 3;
  EXPECT_NE(c.validate().find("initial"), std::string::npos);
}

// The values of the snapshot's map `id` (the test fails when it has none).
const std::vector<float>& mapOf(const Snapshot& s, MapId id) {
  static const std::vector<float> none;
  const SnapshotMap* m = s.map(id);
  EXPECT_NE(m, nullptr) << "no " << mapName(id) << " map";
  return m ? m->values : none;
}

std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method) {
  int guard = 0;
  while (!method.done() && guard++ < 100) method.runRound(nullptr);
  EXPECT_TRUE(method.done());
  return method.snapshot();
}

MethodSpec specFor(MethodKind kind, int spp, uint64_t seed) {
  MethodSpec s;
  s.kind = kind;
  s.spp = spp;
  s.seed = seed;
  return s;
}

class Baseline : public ::testing::TestWithParam<MethodKind> {};

TEST_P(Baseline, SpendsExactlyTheBudget) {
  auto prepared = test::shippedScene("cornell", 16);
  for (int spp : {5, 16}) {
    MethodSpec spec = specFor(GetParam(), spp, 2);
    spec.allocation.rounds = 3;
    auto method = makeMethod(*prepared, spec);
    const auto snap = runToEnd(*method);
    const uint64_t pixels = 16 * 16;
    EXPECT_EQ(snap->tracedSamples, uint64_t(spp) * pixels) << "spp " << spp;
    EXPECT_EQ(snap->keptSamples + snap->nonFiniteSamples, uint64_t(spp) * pixels);
    EXPECT_EQ(snap->round, 4);  // the initial pass and 3 rounds
    uint64_t perPixel = 0;
    for (float c : mapOf(*snap, MapId::TracedCount)) perPixel += uint64_t(c);
    EXPECT_EQ(perPixel, snap->tracedSamples);
  }
}

TEST_P(Baseline, ConcentratesSamples) {
  // The cornell box has a light, edges and flat walls: an adaptive criterion gives some
  // pixels far more than the average and some only the initial pass.
  auto prepared = test::shippedScene("cornell", 24);
  auto method = makeMethod(*prepared, specFor(GetParam(), 16, 1));
  const auto snap = runToEnd(*method);
  const std::vector<float>& traced = mapOf(*snap, MapId::TracedCount);
  const auto [lo, hi] = std::minmax_element(traced.begin(), traced.end());
  EXPECT_LE(*lo, 8.0f);
  EXPECT_GE(*hi, 32.0f);
  const SnapshotMap* score = snap->map(MapId::ErrorEstimate);
  ASSERT_NE(score, nullptr);
  ASSERT_EQ(score->values.size(), size_t(24 * 24));
  EXPECT_GT(*std::max_element(score->values.begin(), score->values.end()), 0.0f);
  // A score has no fixed scale: its colour bar ends at its 99th percentile.
  EXPECT_EQ(score->legend.maxValue, percentileOf(score->values, 0.99f));
  EXPECT_EQ(snap->method, toString(GetParam()));
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
  EXPECT_EQ(mapOf(*one, MapId::TracedCount), mapOf(*many, MapId::TracedCount));
  // Another seed gives another image.
  auto other = makeMethod(*prepared, specFor(GetParam(), 12, 8));
  EXPECT_NE(runToEnd(*other)->raw.pixels, one->raw.pixels);
}

TEST_P(Baseline, OpenEndedRoundsAndInspection) {
  auto prepared = test::shippedScene("cornell", 16);
  MethodSpec spec = specFor(GetParam(), 0, 3);
  spec.openEnded = true;
  spec.roundSpp = 2;
  spec.maxSpp = 10;
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
  EXPECT_EQ(in.method, toString(GetParam()));
  EXPECT_EQ(float(in.traced), mapOf(*snap, MapId::TracedCount)[8 * 16 + 8]);
  // The score is the method's own value, labelled as that score.
  ASSERT_NE(in.value(MapId::ErrorEstimate), nullptr);
  EXPECT_EQ(in.value(MapId::ErrorEstimate)->label, snap->map(MapId::ErrorEstimate)->label);
  EXPECT_FALSE(in.subpixel.has_value());  // the baselines store no samples
  EXPECT_FALSE(in.reason.empty());
  EXPECT_GE(in.rank, 0);
  EXPECT_FALSE(method->inspect(16, 0).valid);
}

TEST_P(Baseline, ViewerOverlaysHaveTheirMaps) {
  auto prepared = test::shippedScene("cornell", 16);
  auto method = makeMethod(*prepared, specFor(GetParam(), 8, 1));
  const auto snap = runToEnd(*method);
  for (MapId o : {MapId::ErrorEstimate, MapId::Selected, MapId::SampleCount, MapId::TracedCount}) {
    const OverlayImage image = buildOverlay(*snap, o, snap->reconstructed, nullptr);
    EXPECT_TRUE(image.available()) << mapName(o) << ": " << image.unavailable;
  }
  const OverlayImage bias = buildOverlay(*snap, MapId::ErrorEstimate, snap->reconstructed, nullptr);
  // Labelled as the criterion's own score, not as BP's bias.
  EXPECT_EQ(bias.label, snap->map(MapId::ErrorEstimate)->label);
  EXPECT_NE(bias.label, "bias");
  EXPECT_GT(bias.legend.maxValue, 0.0f);
  // The filter scale: GEM has its own, labelled by sigma; the box-mean criteria none.
  const OverlayImage scale = buildOverlay(*snap, MapId::FilterScale, snap->reconstructed, nullptr);
  if (GetParam() == MethodKind::Gem) {
    ASSERT_TRUE(scale.available());
    ASSERT_EQ(scale.legend.categories.size(), 9u);
    EXPECT_EQ(scale.legend.categories[1], "s=0.71");
  } else {
    EXPECT_FALSE(scale.available());
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, Baseline,
                         ::testing::Values(MethodKind::FDiv, MethodKind::Fuzzy, MethodKind::Gem,
                                           MethodKind::Cycles),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(Methods, NamesRoundTrip) {
  for (const std::string& name : methodNames()) {
    const auto kind = parseMethodKind(name);
    ASSERT_TRUE(kind) << name;
    EXPECT_EQ(toString(*kind), name);
    EXPECT_STRNE(describe(*kind), "?");
  }
  EXPECT_FALSE(parseMethodKind("nope"));
  EXPECT_NE(std::string(describe(MethodKind::Fuzzy)).find("re-implemented"), std::string::npos);
}

TEST(Methods, RejectBadSpecs) {
  auto prepared = test::shippedScene("cornell", 8);
  MethodSpec s = specFor(MethodKind::Gem, 16, 0);
  s.gamma = 0.9f;
  EXPECT_NE(validate(s).find("gamma"), std::string::npos);
  EXPECT_THROW(makeMethod(*prepared, s), std::invalid_argument);
  s = specFor(MethodKind::FDiv, 0, 0);
  EXPECT_THROW(makeMethod(*prepared, s), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
