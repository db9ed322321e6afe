// The BP method as a whole: budget, determinism, bounded memory, the bias of edge and flat
// pixels, and its building blocks (slot allocation, bias, network inputs).
#include "methods/bp/paper.h"

#include "methods/bp/candidates.h"
#include "methods/bp/error_estimate.h"
#include "methods/bp/state.h"
#include "methods/bp/trainer.h"
#include "methods/factory.h"

#include "methods/render.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <algorithm>

#include <cmath>
#include <numeric>

namespace penumbra {
namespace {

std::unique_ptr<PreparedScene> loadScaled(const std::string& name, int size) {
  return test::shippedScene(name, size);
}

using test::mapOf;

using test::runToEnd;

TEST(BpAllocate, SpendsTheBudgetExactlyInPriorityOrder) {
  const std::vector<uint32_t> order = {5, 2, 7};
  // 10 slots, 4 per pixel: pixel 5 gets 4, pixel 2 gets 4, pixel 7 the remaining 2.
  auto slots = bp::allocateSlots(order, 8, 10, 4);
  EXPECT_EQ(slots[5], 4u);
  EXPECT_EQ(slots[2], 4u);
  EXPECT_EQ(slots[7], 2u);
  EXPECT_EQ(std::accumulate(slots.begin(), slots.end(), 0u), 10u);
  // 29 slots over 3 pixels: two full passes (24), then 4 + 1 in order.
  slots = bp::allocateSlots(order, 8, 29, 4);
  EXPECT_EQ(slots[5], 12u);
  EXPECT_EQ(slots[2], 9u);
  EXPECT_EQ(slots[7], 8u);
  EXPECT_EQ(std::accumulate(slots.begin(), slots.end(), 0u), 29u);
  EXPECT_EQ(std::accumulate(slots.begin(), slots.end(), 0u) - slots[5] - slots[2] - slots[7], 0u);
  slots = bp::allocateSlots({}, 8, 29, 4);
  EXPECT_EQ(std::accumulate(slots.begin(), slots.end(), 0u), 0u);
}

TEST(BpBias, MatchesEquation13WithTheRegulariser) {
  // |0.6-0.5| + |0.2-0.2| + |0.1-0.3| = 0.3; sum I = 1.0; 0.3 / (1.0 + 0.02).
  EXPECT_NEAR(bp::biasOf({0.6f, 0.2f, 0.1f}, {0.5f, 0.2f, 0.3f}, 0.02f), 0.3f / 1.02f, 1e-6f);
  // An all-black pixel has no bias whatever the prediction [A13].
  EXPECT_EQ(bp::biasOf({0.3f, 0.3f, 0.3f}, vec3(0.0f), 0.02f), 0.0f);
  // A dark pixel is held back by eps: 0.03 / (0.003 + 0.02).
  EXPECT_NEAR(bp::biasOf(vec3(0.011f), vec3(0.001f), 0.02f), 0.03f / 0.023f, 1e-4f);
}

TEST(BpInputs, FourAndFiveInputForms) {
  float x[kMaxNetInputs];
  bp::networkInputs(5, -0.25f, 0.5f, 0.1f, 0.2f, 0.3f, x);
  EXPECT_FLOAT_EQ(x[0], -0.5f);
  EXPECT_FLOAT_EQ(x[1], 1.0f);
  EXPECT_FLOAT_EQ(x[4], 0.3f);
  // Radius of the corner (0.5, 0.5) scaled by sqrt 2 is 1.
  bp::networkInputs(4, 0.5f, -0.5f, 0.1f, 0.2f, 0.3f, x);
  EXPECT_NEAR(x[0], 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(x[1], 0.1f);
  EXPECT_FLOAT_EQ(x[3], 0.3f);
  EXPECT_FLOAT_EQ(x[4], 0.0f);
}

TEST(BpPrediction, PointsAreInTheUnitCubeAndDistinct) {
  std::vector<float> uvt(8 * 3);
  bp::predictionPoints(8, 1234, uvt.data());
  for (float v : uvt) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LT(v, 1.0f);
  }
  for (int i = 0; i < 8; ++i)
    for (int j = i + 1; j < 8; ++j) EXPECT_NE(uvt[3 * i], uvt[3 * j]);
  std::vector<float> other(8 * 3);
  bp::predictionPoints(8, 1235, other.data());
  EXPECT_NE(uvt, other);
}

// Trains a network on samples of `radiance(dx, dy)` spread over the pixel and returns the
// bias of eq. 13 at the pixel centre, as the method computes it.
struct TrainedPixel {
  float bias, er;
};
TrainedPixel trainedBias(int inputs, float (*radiance)(float, float), uint64_t seed,
                         float errorThreshold) {
  NetworkConfig config;
  config.inputs = inputs;
  config.epochs = 400;
  config.errorThreshold = errorThreshold;
  PixelNet net;
  initNetwork(net, config, seed);
  std::vector<float> x, targets;
  vec3 mean(0.0f);
  const int n = 16;
  for (int i = 0; i < n; ++i) {
    // A stratified 4 x 4 grid of offsets with jitter from a fixed pattern.
    const float dx = ((i % 4) + 0.5f + 0.3f * std::sin(float(i))) / 4.0f - 0.5f;
    const float dy = ((i / 4) + 0.5f + 0.3f * std::cos(float(i))) / 4.0f - 0.5f;
    float in[kMaxNetInputs];
    bp::networkInputs(inputs, dx, dy, 0.5f, 0.5f, 0.5f, in);
    x.insert(x.end(), in, in + kMaxNetInputs);
    const float t = radiance(dx, dy);
    targets.insert(targets.end(), {t, t, t});
    mean += vec3(t);
  }
  mean /= float(n);
  trainNetworkScalar(config, net, x.data(), targets.data(), n);
  float centre[kMaxNetInputs];
  bp::networkInputs(inputs, 0, 0, 0.5f, 0.5f, 0.5f, centre);
  return {bp::biasOf(predict(net, config, centre), mean, 0.02f), net.er};
}

TEST(BpBias, HardEdgeIsDifficultAndAFlatPixelIsNot) {
  const float psi = BpPaperConfig{}.psi;
  // An edge at dx = 0.25: the centre lies on the bright side while only 3/4 of the pixel
  // is bright, so I' ~ 0.8 and the mean ~ 0.6 (tone-mapped targets 0.8 and 0.0).
  auto edge = [](float dx, float) { return dx < 0.25f ? 0.8f : 0.0f; };
  // A dark disc around the centre (radius 0.3) in a bright pixel: the 4-input form sees it.
  auto disc = [](float dx, float dy) { return dx * dx + dy * dy < 0.09f ? 0.05f : 0.7f; };
  // Flat with a little noise.
  auto flat = [](float dx, float dy) { return 0.5f + 0.01f * std::sin(37.0f * dx + 11.0f * dy); };
  // Trained to convergence (no early stop), bias tells the edge from the flat pixel.
  for (uint64_t seed : {1u, 2u, 3u}) {
    EXPECT_GT(trainedBias(5, edge, seed, 0.0f).bias, psi) << seed;
    EXPECT_GT(trainedBias(4, disc, seed, 0.0f).bias, psi) << seed;
    EXPECT_LT(trainedBias(5, flat, seed, 0.0f).bias, psi) << seed;
    EXPECT_LT(trainedBias(4, flat, seed, 0.0f).bias, psi) << seed;
  }
  // With the default early stop at er < e the flat pixel's training may end before its
  // bias is small, but then er <= e marks it converged: difficult = bias > Psi and er > e.
  const float e = NetworkConfig{}.errorThreshold;
  for (uint64_t seed : {1u, 2u, 3u}) {
    const TrainedPixel hard = trainedBias(5, edge, seed, e);
    EXPECT_TRUE(hard.bias > psi && hard.er > e) << seed;
    const TrainedPixel easy = trainedBias(5, flat, seed, e);
    EXPECT_FALSE(easy.bias > psi && easy.er > e) << seed;
  }
}

TEST(BpMethod, SpendsTheSampleBudgetExactly) {
  auto prepared = loadScaled("cornell", 24);
  for (int spp : {8, 16, 13}) {
    RunShape shape;
    BpPaperConfig config;
    shape.spp = spp;
    shape.seed = 5;
    auto method = makeBpPaperMethod(*prepared, shape, config);
    const auto snap = runToEnd(*method);
    const uint64_t pixels = 24 * 24;
    ASSERT_EQ(snap->nonFiniteSamples, 0u);
    EXPECT_EQ(snap->keptSamples, uint64_t(spp) * pixels) << spp;
    const std::vector<float>& kept = mapOf(*snap, maps::SampleCount);
    EXPECT_EQ(std::accumulate(kept.begin(), kept.end(), uint64_t(0)), uint64_t(spp) * pixels);
    // Traced mode traces N_candi candidates per adaptive sample in a non-empty slice.
    EXPECT_GT(snap->tracedSamples, snap->keptSamples);
    EXPECT_LE(snap->tracedSamples,
              uint64_t(config.effectiveCoarseSpp(shape)) * pixels +
                  uint64_t(spp - config.effectiveCoarseSpp(shape)) * pixels * 4);
    EXPECT_LE(snap->round, config.maxRounds + 1);
    const std::vector<float>& traced = mapOf(*snap, maps::TracedCount);
    for (size_t p = 0; p < pixels; ++p) EXPECT_GE(traced[p], kept[p]);
  }
}

TEST(BpMethod, PredictedCandidatesTraceOneRayPerSampleAndCountRejections) {
  auto prepared = loadScaled("cornell", 20);
  RunShape shape;
  BpPaperConfig config;
  shape.spp = 16;
  config.candidateMode = CandidateMode::Predicted;
  auto method = makeBpPaperMethod(*prepared, shape, config);
  const auto snap = runToEnd(*method);
  const uint64_t pixels = 20 * 20;
  // Every traced sample is either kept or rejected as an outlier.
  EXPECT_EQ(snap->tracedSamples, snap->keptSamples + snap->rejectedSamples);
  // Make-up rounds spend what rejections left, unless 2 x rounds were not enough.
  EXPECT_LE(snap->keptSamples, 16 * pixels);
  EXPECT_GT(snap->keptSamples, 15 * pixels);
}

TEST(BpMethod, SameSeedGivesTheSameImageWhateverTheThreadCount) {
  auto prepared = loadScaled("balls", 32);
  RunShape shape;
  BpPaperConfig config;
  shape.spp = 8;
  shape.seed = 11;
  std::shared_ptr<Snapshot> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    auto method = makeBpPaperMethod(*prepared, shape, config);
    one = runToEnd(*method);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    auto method = makeBpPaperMethod(*prepared, shape, config);
    two = runToEnd(*method);
  }
  EXPECT_EQ(one->raw.pixels, two->raw.pixels);
  EXPECT_EQ(one->reconstructed.pixels, two->reconstructed.pixels);
  EXPECT_EQ(mapOf(*one, maps::ErrorEstimate), mapOf(*two, maps::ErrorEstimate));
  EXPECT_EQ(mapOf(*one, maps::SampleCount), mapOf(*two, maps::SampleCount));
  EXPECT_EQ(one->rays, two->rays);
  shape.seed = 12;
  auto other = makeBpPaperMethod(*prepared, shape, config);
  EXPECT_NE(runToEnd(*other)->raw.pixels, one->raw.pixels);
}

TEST(BpMethod, DifficultPixelsAreSampledFirstInDescendingBias) {
  auto prepared = loadScaled("tire", 48);
  RunShape shape;
  BpPaperConfig config;
  shape.spp = 16;
  config.maxRounds = 16;  // a round's budget (0.75 spp) covers only some pixels
  auto method = makeBpPaperMethod(*prepared, shape, config);
  method->runRound(nullptr);
  const auto coarse = method->snapshot();
  method->runRound(nullptr);
  const auto next = method->snapshot();
  const float e = config.network.errorThreshold;
  const std::vector<float>& bias = mapOf(*coarse, maps::ErrorEstimate);
  const std::vector<float>& er = mapOf(*coarse, maps::NetworkError);
  const std::vector<float>& chosen = mapOf(*next, maps::Selected);
  const std::vector<float>& keptBefore = mapOf(*coarse, maps::SampleCount);
  const std::vector<float>& keptAfter = mapOf(*next, maps::SampleCount);
  size_t difficult = 0, selected = 0;
  float lowestSelectedBias = 1e30f;
  for (size_t p = 0; p < bias.size(); ++p) {
    const bool hard = bias[p] > config.psi && er[p] > e;
    difficult += hard;
    if (chosen[p]) {
      ++selected;
      lowestSelectedBias = std::min(lowestSelectedBias, bias[p]);
    }
  }
  ASSERT_GT(difficult, 0u);
  ASSERT_GT(selected, 0u);
  ASSERT_LT(selected, bias.size());
  for (size_t p = 0; p < bias.size(); ++p) {
    const bool hard = bias[p] > config.psi && er[p] > e;
    if (selected <= difficult) {
      // Only difficult pixels were sampled, and none left out has a higher bias.
      if (chosen[p]) {
        EXPECT_TRUE(hard) << p;
      }
      if (hard && !chosen[p]) {
        EXPECT_LE(bias[p], lowestSelectedBias) << p;
      }
    } else {
      EXPECT_TRUE(!hard || chosen[p]) << p;  // every difficult pixel was sampled
    }
    // Each sampled pixel got S^2 = 4 samples, but the last one may get the remainder.
    if (chosen[p]) {
      EXPECT_LE(keptAfter[p] - keptBefore[p], 4.0f);
    }
  }
}

TEST(BpMethod, OpenEndedMemoryStaysFlat) {
  auto prepared = loadScaled("cornell", 16);
  RunShape shape = RunShape::progressive(4);
  BpPaperConfig config;
  config.reservoir = 12;
  config.network.epochs = 5;
  auto method = makeBpPaperMethod(*prepared, shape, config);
  size_t atFive = 0;
  for (int round = 0; round < 16; ++round) {
    method->runRound(nullptr);
    if (round == 5) atFive = method->memoryBytes();
  }
  EXPECT_FALSE(method->done());
  const auto snap = method->snapshot();
  // 4 + 15 x 4 = 64 kept spp on average, over five times the reservoir.
  EXPECT_EQ(snap->keptSamples, 64u * 16 * 16);
  EXPECT_EQ(method->memoryBytes(), atFive);
}

TEST(BpMethod, OpenEndedStopsAtMaxSpp) {
  auto prepared = loadScaled("cornell", 8);
  const RunShape shape = RunShape::progressive(3, 0, 10);
  BpPaperConfig config;
  auto method = makeBpPaperMethod(*prepared, shape, config);
  const auto snap = runToEnd(*method);
  EXPECT_EQ(snap->keptSamples, 10u * 64);
}

TEST(BpMethod, RejectsABadConfigurationWithTheFlagName) {
  auto prepared = loadScaled("cornell", 8);
  RunShape shape;
  BpPaperConfig config;
  config.filter.phi = {0.3f};
  try {
    makeBpPaperMethod(*prepared, shape, config);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--phi"), std::string::npos);
  }
  config = BpPaperConfig{};
  config.reservoir = 2;
  EXPECT_THROW(makeBpPaperMethod(*prepared, shape, config), std::invalid_argument);
}

// `paper` names the defaults; `tuned` changes four settings of them and nothing else.
TEST(BpPreset, TunedChangesOnlyItsFourSettingsOfThePaperDefaults) {
  const MethodRegistry& methods = builtinMethods();
  EXPECT_EQ(methods.find("bp", "paper"), &bpPaperMethod());
  EXPECT_EQ(methods.find("bp", "tuned"), &bpPaperMethod());
  EXPECT_EQ(bpPaperMethod().defaultPreset()->name, "paper");
  const MethodConfig paper = methods.configFor("bp", "paper");
  EXPECT_EQ(describeChanges(paper, bpPaperMethod().defaults()), "");
  const MethodConfig tuned = methods.configFor("bp", "tuned");
  EXPECT_EQ(describeChanges(tuned, paper),
            "sigma-c=0.05 warping=false outlier-removal=false stratified-mean=false");
  EXPECT_FALSE(tuned.as<BpPaperConfig>().outlierRemoval);
}

TEST(BpPreset, TunedTracesOneSamplePerKeptSampleAndKeepsTheBudget) {
  auto prepared = loadScaled("cornell", 12);
  RunShape shape;
  shape.spp = 8;
  shape.seed = 5;
  const MethodConfig tuned = builtinMethods().configFor("bp", "tuned");
  auto method = makeBpPaperMethod(*prepared, shape, tuned.as<BpPaperConfig>());
  const auto snap = runToEnd(*method);
  EXPECT_EQ(snap->keptSamples, 8u * 12 * 12);
  EXPECT_EQ(snap->tracedSamples, snap->keptSamples);  // no candidates traced and dropped
}

TEST(BpInspect, ExplainsThePixelWithItsSamplesSlicesAndCandidates) {
  auto prepared = loadScaled("cornell", 12);
  RunShape shape;
  BpPaperConfig config;
  shape.spp = 16;
  shape.seed = 2;
  config.network.epochs = 10;
  auto method = makeBpPaperMethod(*prepared, shape, config);
  EXPECT_FALSE(method->inspect(3, 4).valid);  // nothing before the coarse pass
  method->setInspectedPixel(3, 4);
  method->runRound(nullptr);
  PixelInspection coarse = method->inspect(3, 4);
  ASSERT_TRUE(coarse.valid);
  EXPECT_EQ(coarse.kept, 4u);
  ASSERT_TRUE(coarse.subpixel.has_value());
  EXPECT_EQ(coarse.subpixel->samples.size(), 4u);
  EXPECT_NE(coarse.reason.find("coarse"), std::string::npos);
  // Inspect the pixel of highest bias after the coarse pass (the likeliest to be chosen; not
  // pixel 0, checked below), and find a round in which it got samples: its candidates are
  // recorded.
  const auto afterCoarse = method->snapshot();
  const std::vector<float>& bias = mapOf(*afterCoarse, maps::ErrorEstimate);
  const size_t p = size_t(std::max_element(bias.begin() + 1, bias.end()) - bias.begin());
  const int px = int(p % 12), py = int(p / 12);
  method->setInspectedPixel(px, py);
  PixelInspection in;
  while (!method->done()) {
    method->runRound(nullptr);
    in = method->inspect(px, py);
    if (in.addedLastRound > 0) break;
  }
  ASSERT_GT(in.addedLastRound, 0u) << "the pixel never got samples";
  const auto snap = method->snapshot();
  EXPECT_EQ(float(in.kept), mapOf(*snap, maps::SampleCount)[p]);
  ASSERT_NE(in.value(maps::ErrorEstimate), nullptr);
  EXPECT_FLOAT_EQ(in.value(maps::ErrorEstimate)->values[0], mapOf(*snap, maps::ErrorEstimate)[p]);
  ASSERT_TRUE(in.subpixel.has_value());
  const SubpixelInspection& sub = *in.subpixel;
  EXPECT_EQ(float(sub.sliceB), mapOf(*snap, maps::SliceB)[p]);
  EXPECT_EQ(sub.slices.size(), 4u);
  uint32_t sliceTotal = 0;
  for (const InspectedSlice& s : sub.slices) sliceTotal += s.count;
  EXPECT_EQ(sliceTotal, in.kept);
  for (const InspectedSample& s : sub.samples) {
    EXPECT_GE(s.ox, 0.0f);
    EXPECT_LT(s.ox, 1.0f);
    EXPECT_EQ(s.slice, sliceOf(s.ox, s.oy, 2));
  }
  // Traced mode: N_candi candidates per new sample, exactly one kept per sample added.
  size_t keptCandidates = 0;
  for (const InspectedCandidate& c : sub.candidates) keptCandidates += c.kept;
  EXPECT_EQ(keptCandidates, in.addedLastRound);
  EXPECT_GE(sub.candidates.size(), in.addedLastRound);
  EXPECT_GE(in.rank, 0);
  EXPECT_NE(in.reason.find("rank"), std::string::npos);
  // Another pixel: no candidates recorded for it.
  EXPECT_TRUE(method->inspect(0, 0).subpixel->candidates.empty());
  EXPECT_FALSE(method->inspect(12, 0).valid);
}

}  // namespace
}  // namespace penumbra
