// The low-discrepancy method in rounds: the image does not depend on the split into rounds, and
// renderImage is the method run to the end.
#include "methods/ld/ld.h"

#include "methods/render.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace penumbra {
namespace {

using test::runToEnd;

TEST(LdMethod, TheImageDoesNotDependOnHowRoundsSplitTheSamples) {
  auto prepared = test::shippedScene("cornell", 16);
  auto threeRounds = makeLdMethod(*prepared, RunShape::progressive(3, 3, 8));  // 3, 3, 2
  const auto split = runToEnd(*threeRounds);
  EXPECT_EQ(split->round, 3);
  EXPECT_EQ(split->keptSamples, 8u * 16 * 16);
  auto oneRound = makeLdMethod(*prepared, RunShape::progressive(8, 3, 8));
  const auto whole = runToEnd(*oneRound);
  EXPECT_EQ(whole->round, 1);
  EXPECT_EQ(split->raw.pixels, whole->raw.pixels);
  EXPECT_EQ(split->rays, whole->rays);
}

// One sample has no variance: a noise threshold must not call a pixel converged on it. With one
// sample per round the run once stopped after its first round at any threshold, filtered or not.
TEST(LdMethod, ANoiseThresholdWaitsForTwoSamplesAndThenForItsError) {
  auto prepared = test::shippedScene("cornell", 24);
  for (bool filter : {false, true}) {
    RunShape shape = RunShape::progressive(1, 3, 512);
    shape.noiseThreshold = 0.01f;
    LdConfig config;
    config.filter = filter;
    auto method = makeLdMethod(*prepared, shape, config);
    const auto snap = runToEnd(*method, 10000);
    EXPECT_GT(snap->round, 2) << "filter " << filter;
    EXPECT_GT(double(snap->keptSamples) / (24 * 24), 2.0) << "filter " << filter;
    const double e = method->estimatedError();
    // Stopped by the threshold (below it) or by the cap, never by an unknown error.
    EXPECT_TRUE((e == e && e < 0.01) || snap->round >= 512) << "filter " << filter << ": " << e;
  }
}

TEST(LdMethod, ABatchRunReportsProgressInRoundsAndRenderImageIsIt) {
  auto prepared = test::shippedScene("cornell", 16);
  LdMethod method(*prepared, RunShape::batch(40, 3));
  int rounds = 0;
  while (!method.done()) {
    method.runRound(nullptr);
    ++rounds;
  }
  EXPECT_EQ(rounds, kLdBatchRounds);  // 40 spp in 16 rounds of 3 or 2
  EXPECT_EQ(method.samplesPerPixel(), 40u);
  RenderOptions options;
  options.spp = 40;
  options.seed = 3;
  std::vector<double> progress;
  options.progress = [&](double f) { progress.push_back(f); };
  const RenderResult direct = renderImage(*prepared, options);
  EXPECT_EQ(method.snapshot(false, nullptr)->raw.pixels, direct.image.pixels);
  EXPECT_EQ(method.varianceOfMean().pixels, direct.varianceOfMean.pixels);
  ASSERT_EQ(progress.size(), size_t(kLdBatchRounds));
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  EXPECT_DOUBLE_EQ(progress.back(), 1.0);
}

}  // namespace
}  // namespace penumbra
