// Allocation by estimated error: the water-filling split of a round's budget.
#include "methods/error_allocation.h"

#include "methods/run_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace penumbra {
namespace {

uint64_t sum(const std::vector<uint32_t>& v) { return std::accumulate(v.begin(), v.end(), 0ull); }

TEST(ErrorAllocation, SpendsTheBudgetAndFavoursTheNoisyPixels) {
  // 1000 pixels with 8 samples each; a tenth of them 100x noisier.
  std::vector<float> error(1000, 1e-4f);
  for (size_t p = 0; p < error.size(); p += 10) error[p] = 1e-2f;
  const std::vector<uint32_t> count(1000, 8);
  const uint64_t budget = 8000;
  const auto dn = allocateByError(error, count, budget, {}, 1, 0);
  EXPECT_NEAR(double(sum(dn)), double(budget), 0.02 * budget);
  // Optimum without floors: n ~ sqrt(e n) (the noisy ones about 10x the others' total),
  // so the noisy pixels get far more than the rest.
  double noisy = 0, quiet = 0;
  for (size_t p = 0; p < dn.size(); ++p) (p % 10 == 0 ? noisy : quiet) += dn[p];
  EXPECT_GT(noisy / 100.0, 5.0 * quiet / 900.0);
}

TEST(ErrorAllocation, TheFloorKeepsEveryPixelSampled) {
  std::vector<float> error(100, 0.0f);
  error[0] = 1.0f;
  std::vector<uint32_t> count(100, 4);
  ErrorAllocation config;
  config.floorFraction = 0.5f;
  // Run many rounds: every pixel's count keeps growing at least as half the mean.
  for (int round = 0; round < 20; ++round) {
    const auto dn = allocateByError(error, count, 400, config, 2, round);
    for (size_t p = 0; p < count.size(); ++p) count[p] += dn[p];
  }
  const double mean = double(sum(count)) / count.size();
  for (size_t p = 1; p < count.size(); ++p) EXPECT_GE(count[p], 0.45 * mean) << p;
  EXPECT_GT(count[0], 2 * mean);
}

// The pixels a noise threshold marks converged (RunShape::converged) get nothing.
TEST(ErrorAllocation, PixelsBelowTheNoiseThresholdGetNothing) {
  std::vector<float> error{1e-5f, 1e-1f, 1e-5f, 1e-2f};
  const std::vector<uint32_t> count(4, 16);
  const auto convergedBelow = [&](float threshold) {
    RunShape shape;
    shape.noiseThreshold = threshold;
    std::vector<uint8_t> converged;
    for (float e : error) converged.push_back(shape.converged(e));
    return converged;
  };
  const auto dn = allocateByError(error, count, 100, {}, 3, 0, convergedBelow(1e-3f));
  EXPECT_EQ(dn[0], 0u);
  EXPECT_EQ(dn[2], 0u);
  EXPECT_GT(dn[1], dn[3]);
  EXPECT_NEAR(double(dn[1] + dn[3]), 100.0, 2.0);
  // Everything converged.
  EXPECT_EQ(sum(allocateByError(error, count, 100, {}, 3, 0, convergedBelow(1.0f))), 0u);
}

TEST(ErrorAllocation, IsDeterministicAndHandlesNonFiniteErrors) {
  std::vector<float> error(64);
  for (size_t p = 0; p < error.size(); ++p) error[p] = float(p % 7) * 1e-3f;
  error[5] = NAN;
  error[6] = INFINITY;
  const std::vector<uint32_t> count(64, 2);
  const auto a = allocateByError(error, count, 300, {}, 9, 4);
  EXPECT_EQ(a, allocateByError(error, count, 300, {}, 9, 4));
  EXPECT_NEAR(double(sum(a)), 300.0, 12.0);
  EXPECT_GT(a[5], 0u);  // counts as the largest finite error
}

TEST(ErrorAllocation, Dilate3x3TakesTheNeighbourhoodsLargest) {
  std::vector<float> v(16, 0.0f);
  v[5] = 9.0f;  // (1, 1) of a 4x4 map
  v[15] = NAN;
  const auto s = dilate3x3(v, 4, 4);
  EXPECT_FLOAT_EQ(s[0], 9.0f);
  EXPECT_FLOAT_EQ(s[10], 9.0f);  // (2, 2) touches (1, 1)
  EXPECT_FLOAT_EQ(s[3], 0.0f);   // (3, 0) does not
  EXPECT_FLOAT_EQ(s[15], 0.0f);  // a NaN is skipped
}

}  // namespace
}  // namespace penumbra
