// BP-network tests: the sigmoid approximation, back-propagation against finite differences,
// the update rule of one epoch, learning a smooth function, and the SIMD lane-group trainer
// against the scalar reference (per pixel, independent of batch and thread count).
#include "methods/bp/network.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/rng.h"

namespace penumbra {
namespace {

// n samples of a smooth function of the 4-input form (radius, u, v, t), or of the 5-input
// form (2dx, 2dy, u, v, t), with targets in the sigmoid range.
struct PixelData {
  std::vector<float> inputs;   // n * kMaxNetInputs
  std::vector<float> targets;  // n * kNetOutputs
  int n = 0;
};

PixelData smoothPixel(int inputs, int n, uint64_t seed, float noise = 0.0f) {
  Pcg32 rng(seed, 7);
  PixelData d;
  d.n = n;
  for (int k = 0; k < n; ++k) {
    const float dx = rng.nextFloat() - 0.5f, dy = rng.nextFloat() - 0.5f;
    const float u = rng.nextFloat(), v = rng.nextFloat(), t = rng.nextFloat();
    const float radius = std::sqrt(2.0f) * std::sqrt(dx * dx + dy * dy);
    if (inputs == 4) {
      d.inputs.insert(d.inputs.end(), {radius, u, v, t, 0.0f});
    } else {
      d.inputs.insert(d.inputs.end(), {2 * dx, 2 * dy, u, v, t});
    }
    auto jitter = [&] { return noise * (rng.nextFloat() - 0.5f); };
    d.targets.push_back(0.15f + 0.7f * radius + jitter());
    d.targets.push_back(0.8f - 0.5f * u * u + jitter());
    d.targets.push_back(0.3f + 0.4f * radius * v + 0.1f * t + jitter());
  }
  return d;
}

NetworkConfig makeConfig(int inputs, int hidden) {
  NetworkConfig c;
  c.inputs = inputs;
  c.hidden = hidden;
  return c;
}

bool sameBits(const PixelNet& a, const PixelNet& b) {
  return std::memcmp(a.w1, b.w1, sizeof(a.w1)) == 0 && std::memcmp(a.w2, b.w2, sizeof(a.w2)) == 0 &&
         std::memcmp(&a.mu, &b.mu, 4) == 0 && std::memcmp(&a.er, &b.er, 4) == 0 &&
         std::memcmp(&a.erPrev, &b.erPrev, 4) == 0 && std::memcmp(&a.erFirst, &b.erFirst, 4) == 0;
}

// Multiply-adds per sample and per update, as trainNetworks counts them.
uint64_t forwardMadds(const NetworkConfig& c) { return uint64_t(c.hidden * (c.inputs + 3)); }
uint64_t backwardMadds(const NetworkConfig& c) { return uint64_t(c.hidden * (c.inputs + 6)); }

TEST(BpNetworkTest, SigmoidMatchesStdExp) {
  double maxRel = 0.0, maxAbs = 0.0;
  for (int j = -400000; j <= 400000; ++j) {
    const float x = float(j) * 1e-4f;
    const double ref = 1.0 / (1.0 + std::exp(-double(x)));
    const double got = sigmoid(x);
    maxAbs = std::max(maxAbs, std::abs(got - ref));
    if (std::abs(x) <= 30.0f) maxRel = std::max(maxRel, std::abs(got - ref) / ref);
  }
  // Float rounding of the final divide alone contributes up to 6e-8.
  EXPECT_LT(maxRel, 1e-6);
  // Beyond +-30 the argument is clamped: the output moves by less than e^-30.
  EXPECT_LT(maxAbs, 1e-7);
  EXPECT_EQ(sigmoid(-40.0f), sigmoid(-30.0f));
  EXPECT_EQ(sigmoid(1e30f), sigmoid(30.0f));
  EXPECT_FLOAT_EQ(sigmoid(0.0f), 0.5f);
}

class BpGradientTest : public ::testing::TestWithParam<int> {};

TEST_P(BpGradientTest, MatchesCentralFiniteDifferences) {
  const NetworkConfig c = makeConfig(GetParam(), 8);
  const PixelData d = smoothPixel(c.inputs, 12, 99);
  PixelNet net;
  initNetwork(net, c, 1234);
  float g1[kMaxNetInputs][kMaxNetHidden], g2[kMaxNetHidden][kNetOutputs];
  networkGradient(net, c, d.inputs.data(), d.targets.data(), d.n, g1, g2);

  constexpr float kStep = 1e-3f;
  int checked = 0;
  auto check = [&](float& weight, float analytic, const std::string& name) {
    const float saved = weight;
    weight = saved + kStep;
    const float up = weight;
    const double erUp = networkError(net, c, d.inputs.data(), d.targets.data(), d.n);
    weight = saved - kStep;
    const float down = weight;
    const double erDown = networkError(net, c, d.inputs.data(), d.targets.data(), d.n);
    weight = saved;
    const double numeric = (erUp - erDown) / double(up - down);
    // Relative 1e-2, plus a floor for the float rounding of the forward pass (~1e-7 per
    // output, divided by the 2e-3 step).
    EXPECT_NEAR(analytic, numeric, 1e-2 * std::abs(numeric) + 5e-4) << name;
    ++checked;
  };
  for (int i = 0; i < c.inputs; ++i)
    for (int h = 0; h < c.hidden; ++h)
      check(net.w1[i][h], g1[i][h], "w1[" + std::to_string(i) + "][" + std::to_string(h) + "]");
  for (int h = 0; h < c.hidden; ++h)
    for (int o = 0; o < kNetOutputs; ++o)
      check(net.w2[h][o], g2[h][o], "w2[" + std::to_string(h) + "][" + std::to_string(o) + "]");
  EXPECT_EQ(checked, c.hidden * (c.inputs + kNetOutputs));

  // Unused entries get no gradient.
  for (int i = 0; i < kMaxNetInputs; ++i)
    for (int h = 0; h < kMaxNetHidden; ++h)
      if (i >= c.inputs || h >= c.hidden) {
        EXPECT_EQ(g1[i][h], 0.0f);
      }
  for (int h = c.hidden; h < kMaxNetHidden; ++h)
    for (int o = 0; o < kNetOutputs; ++o) EXPECT_EQ(g2[h][o], 0.0f);
}

INSTANTIATE_TEST_SUITE_P(Inputs, BpGradientTest, ::testing::Values(4, 5));

class BpStepTest : public ::testing::TestWithParam<bool> {};

TEST_P(BpStepTest, OneEpochMovesWeightsByMuTimesNegativeGradient) {
  NetworkConfig c = makeConfig(4, 8);
  c.epochs = 1;
  c.errorThreshold = 0.0f;
  c.rate = LearningRateMode::BoldDriver;
  c.meanGradient = GetParam();
  const PixelData d = smoothPixel(c.inputs, 16, 5);
  PixelNet before;
  initNetwork(before, c, 77);
  float g1[kMaxNetInputs][kMaxNetHidden], g2[kMaxNetHidden][kNetOutputs];
  networkGradient(before, c, d.inputs.data(), d.targets.data(), d.n, g1, g2);
  const float scale = c.meanGradient ? 1.0f / float(d.n) : 1.0f;

  PixelNet after = before;
  trainNetworkScalar(c, after, d.inputs.data(), d.targets.data(), d.n);
  double largestMove = 0.0;
  for (int i = 0; i < c.inputs; ++i) {
    for (int h = 0; h < c.hidden; ++h) {
      const double expected = before.w1[i][h] - double(before.mu) * scale * g1[i][h];
      EXPECT_NEAR(after.w1[i][h], expected, 1e-6) << i << "," << h;
      largestMove = std::max(largestMove, std::abs(double(after.w1[i][h]) - before.w1[i][h]));
    }
  }
  for (int h = 0; h < c.hidden; ++h) {
    for (int o = 0; o < kNetOutputs; ++o) {
      const double expected = before.w2[h][o] - double(before.mu) * scale * g2[h][o];
      EXPECT_NEAR(after.w2[h][o], expected, 1e-6) << h << "," << o;
      largestMove = std::max(largestMove, std::abs(double(after.w2[h][o]) - before.w2[h][o]));
    }
  }
  EXPECT_GT(largestMove, 1e-4);  // the step is real, not lost in the tolerance
  // Bold driver: the first epoch has nothing to compare with, so mu stays.
  EXPECT_EQ(after.mu, before.mu);
  const double erBefore = networkError(before, c, d.inputs.data(), d.targets.data(), d.n);
  const double erAfter = networkError(after, c, d.inputs.data(), d.targets.data(), d.n);
  EXPECT_NEAR(after.erFirst, erBefore, 1e-5 * erBefore);
  EXPECT_NEAR(after.er, erAfter, 1e-5 * erAfter);
  EXPECT_LT(erAfter, erBefore);  // a small step along -gradient descends
}

INSTANTIATE_TEST_SUITE_P(MeanGradient, BpStepTest, ::testing::Bool());

// er of the best constant predictor on d: each output predicted by its mean target, so
// 1/2 sum_k sum_o (d_o(k) - mean_o)^2. A network that has not learned the inputs'
// influence on the targets does no better than this.
double constantPredictorError(const PixelData& d) {
  double mean[kNetOutputs] = {};
  for (int k = 0; k < d.n; ++k)
    for (int o = 0; o < kNetOutputs; ++o) mean[o] += d.targets[size_t(k * kNetOutputs + o)];
  for (double& m : mean) m /= d.n;
  double er = 0;
  for (int k = 0; k < d.n; ++k)
    for (int o = 0; o < kNetOutputs; ++o)
      er += 0.5 * std::pow(d.targets[size_t(k * kNetOutputs + o)] - mean[o], 2);
  return er;
}

TEST(BpNetworkTest, TrainingLearnsSmoothFunction) {
  for (auto [inputs, epochs] : {std::pair{4, 3000}, std::pair{5, 10000}}) {
    // Enough epochs and hidden units to converge on this smooth, noise-free function
    // (the 5-input form must build the radius from 2dx and 2dy first, so it needs more).
    // One training of the renderer's default 60 epochs only starts the descent: er is
    // then still about half the constant predictor's or more.
    NetworkConfig c = makeConfig(inputs, 16);
    c.epochs = epochs;
    c.errorThreshold = 0.0f;
    const PixelData d = smoothPixel(inputs, 32, 2024);
    PixelNet scalarNet;
    initNetwork(scalarNet, c, 31);
    PixelNet simdNet = scalarNet;
    const double erStart = networkError(scalarNet, c, d.inputs.data(), d.targets.data(), d.n);
    const double erConstant = constantPredictorError(d);
    trainNetworkScalar(c, scalarNet, d.inputs.data(), d.targets.data(), d.n);
    const double erEnd = networkError(scalarNet, c, d.inputs.data(), d.targets.data(), d.n);
    // Learned: the trained network explains at least 90% of the targets' variance (its
    // er is at most a tenth of the best constant predictor's), and is far better than the
    // random network it started from. Untrained (0 epochs), both fail; stopped after 60
    // epochs, the first.
    EXPECT_LT(erEnd, 0.1 * erConstant)
        << "inputs " << inputs << ": constant predictor " << erConstant << ", trained " << erEnd;
    EXPECT_LT(erEnd, 0.1 * erStart) << "inputs " << inputs << ": " << erStart << " -> " << erEnd;
    EXPECT_NEAR(scalarNet.er, erEnd, 1e-5 * erEnd);
    EXPECT_GE(scalarNet.mu, c.muMin);
    EXPECT_LE(scalarNet.mu, c.muMax);

    TrainingBatch batch;
    batch.inputs = d.inputs;
    batch.targets = d.targets;
    batch.offsets.push_back(uint32_t(d.n));
    PixelNet* nets[] = {&simdNet};
    trainNetworks(c, nets, batch);
    EXPECT_NEAR(simdNet.er, scalarNet.er, 1e-3 * scalarNet.er);
  }
}

// A batch of 37 pixels with 0..40 samples, so lane groups of every width get padded lanes
// and padded samples. Pixel 11 has no sample; pixel 20's targets are its own predictions,
// so it stops in the first epoch.
struct Batch {
  NetworkConfig config;
  std::vector<PixelNet> nets;
  TrainingBatch batch;
};

Batch makeBatch(const NetworkConfig& config, int pixels = 37) {
  Batch b;
  b.config = config;
  b.nets.resize(size_t(pixels));
  for (int p = 0; p < pixels; ++p) {
    initNetwork(b.nets[size_t(p)], config, hashValues(42, uint64_t(p)));
    const int n = p == 11 ? 0 : 1 + (p * 17) % 40;
    PixelData d = smoothPixel(config.inputs, n, uint64_t(1000 + p), 0.2f);
    if (p == 20) {
      for (int k = 0; k < n; ++k) {
        const glm::vec3 y = predict(b.nets[size_t(p)], config, &d.inputs[size_t(k) * 5]);
        for (int o = 0; o < 3; ++o) d.targets[size_t(k) * 3 + size_t(o)] = y[o];
      }
    }
    b.batch.inputs.insert(b.batch.inputs.end(), d.inputs.begin(), d.inputs.end());
    b.batch.targets.insert(b.batch.targets.end(), d.targets.begin(), d.targets.end());
    b.batch.offsets.push_back(b.batch.offsets.back() + uint32_t(n));
  }
  return b;
}

std::vector<PixelNet*> pointers(std::vector<PixelNet>& nets) {
  std::vector<PixelNet*> out;
  for (PixelNet& n : nets) out.push_back(&n);
  return out;
}

class BpSimdTest : public ::testing::TestWithParam<NetworkConfig> {};

TEST_P(BpSimdTest, AgreesWithScalarPerPixel) {
  Batch b = makeBatch(GetParam());
  const std::vector<PixelNet> initial = b.nets;
  std::vector<PixelNet> reference = b.nets;
  for (int p = 0; p < b.batch.pixelCount(); ++p) {
    const uint32_t first = b.batch.offsets[size_t(p)];
    trainNetworkScalar(b.config, reference[size_t(p)], &b.batch.inputs[size_t(first) * 5],
                       &b.batch.targets[size_t(first) * 3],
                       int(b.batch.offsets[size_t(p) + 1] - first));
  }
  const std::vector<PixelNet*> nets = pointers(b.nets);
  EXPECT_GT(trainNetworks(b.config, nets, b.batch), 0u);

  int stoppedEarly = 0, ranAllEpochs = 0;
  for (int p = 0; p < b.batch.pixelCount(); ++p) {
    const PixelNet& got = b.nets[size_t(p)];
    const PixelNet& want = reference[size_t(p)];
    if (p == 11) {
      EXPECT_TRUE(sameBits(got, initial[size_t(p)])) << "pixel without samples changed";
      continue;
    }
    float maxDiff = 0.0f;
    for (int i = 0; i < kMaxNetInputs; ++i)
      for (int h = 0; h < kMaxNetHidden; ++h)
        maxDiff = std::max(maxDiff, std::abs(got.w1[i][h] - want.w1[i][h]));
    for (int h = 0; h < kMaxNetHidden; ++h)
      for (int o = 0; o < kNetOutputs; ++o)
        maxDiff = std::max(maxDiff, std::abs(got.w2[h][o] - want.w2[h][o]));
    EXPECT_LT(maxDiff, 1e-5f) << "pixel " << p;  // measured: below 5e-7
    EXPECT_NEAR(got.mu, want.mu, 1e-5f) << "pixel " << p;
    EXPECT_NEAR(got.er, want.er, 1e-4f * want.er + 1e-7f) << "pixel " << p;
    EXPECT_NEAR(got.erPrev, want.erPrev, 1e-4f * want.erPrev + 1e-7f) << "pixel " << p;
    EXPECT_NEAR(got.erFirst, want.erFirst, 1e-4f * want.erFirst + 1e-7f) << "pixel " << p;
    // After an early stop er is the er of the stopping epoch, which erPrev also holds.
    (want.er == want.erPrev ? stoppedEarly : ranAllEpochs) += 1;
  }
  // The batch exercises both: lanes that stop while others of their group go on.
  EXPECT_GT(stoppedEarly, 1);
  EXPECT_GT(ranAllEpochs, 1);
  // The self-predicting pixel stopped at once: weights as initialised, er ~ 0.
  EXPECT_EQ(std::memcmp(b.nets[20].w1, initial[20].w1, sizeof(initial[20].w1)), 0);
  EXPECT_LT(b.nets[20].er, 1e-8f);
}

TEST_P(BpSimdTest, PixelResultIndependentOfBatchAndThreads) {
  Batch b = makeBatch(GetParam());
  std::vector<PixelNet> together = b.nets;
  {
    const std::vector<PixelNet*> nets = pointers(together);
    trainNetworks(b.config, nets, b.batch);
  }
  std::vector<PixelNet> oneThread = b.nets;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    const std::vector<PixelNet*> nets = pointers(oneThread);
    trainNetworks(b.config, nets, b.batch);
  }
  for (int p = 0; p < b.batch.pixelCount(); ++p) {
    EXPECT_TRUE(sameBits(together[size_t(p)], oneThread[size_t(p)])) << "pixel " << p;
    const uint32_t first = b.batch.offsets[size_t(p)], last = b.batch.offsets[size_t(p) + 1];
    TrainingBatch alone;
    alone.inputs.assign(b.batch.inputs.begin() + first * 5, b.batch.inputs.begin() + last * 5);
    alone.targets.assign(b.batch.targets.begin() + first * 3, b.batch.targets.begin() + last * 3);
    alone.offsets.push_back(last - first);
    PixelNet single = b.nets[size_t(p)];
    PixelNet* nets[] = {&single};
    trainNetworks(b.config, nets, alone);
    EXPECT_TRUE(sameBits(single, together[size_t(p)])) << "pixel " << p;
  }
}

// The first four sizes have unrolled kernels, the last two run the generic one.
NetworkConfig variant(int inputs, int hidden, LearningRateMode rate, bool mean) {
  NetworkConfig c = makeConfig(inputs, hidden);
  c.rate = rate;
  c.meanGradient = mean;
  return c;
}

INSTANTIATE_TEST_SUITE_P(Configs, BpSimdTest,
                         ::testing::Values(variant(4, 8, LearningRateMode::BoldDriver, false),
                                           variant(5, 8, LearningRateMode::Proportional, false),
                                           variant(4, 16, LearningRateMode::BoldDriver, true),
                                           variant(5, 4, LearningRateMode::BoldDriver, false),
                                           variant(4, 5, LearningRateMode::Proportional, true),
                                           variant(3, 11, LearningRateMode::BoldDriver, false)));

TEST(BpNetworkTest, FlopCountFollowsExecutedWork) {
  NetworkConfig c = makeConfig(4, 8);
  c.epochs = 7;
  c.errorThreshold = 0.0f;  // nobody stops: every epoch runs and updates
  Batch b = makeBatch(c, 9);
  uint64_t expected = 0;
  for (int p = 0; p < 9; ++p) {
    const uint64_t n = b.batch.offsets[size_t(p) + 1] - b.batch.offsets[size_t(p)];
    if (n == 0) continue;
    expected += 2 * (c.epochs * (n * (forwardMadds(c) + backwardMadds(c)) + forwardMadds(c)) +
                     n * forwardMadds(c));
  }
  std::vector<PixelNet*> nets = pointers(b.nets);
  EXPECT_EQ(trainNetworks(c, nets, b.batch), expected);

  // Everybody stops in the first epoch: one forward + backward pass per sample, nothing else.
  c.errorThreshold = 1e30f;
  uint64_t firstEpoch = 0;
  for (int p = 0; p < 9; ++p) {
    const uint64_t n = b.batch.offsets[size_t(p) + 1] - b.batch.offsets[size_t(p)];
    firstEpoch += 2 * n * (forwardMadds(c) + backwardMadds(c));
  }
  EXPECT_EQ(trainNetworks(c, nets, b.batch), firstEpoch);
}

TEST(BpNetworkTest, HugeErrorThresholdStopsBeforeAnyUpdate) {
  NetworkConfig c = makeConfig(4, 8);
  c.errorThreshold = 1e30f;
  Batch b = makeBatch(c);
  const std::vector<PixelNet> initial = b.nets;
  std::vector<PixelNet*> nets = pointers(b.nets);
  trainNetworks(c, nets, b.batch);
  for (int p = 0; p < b.batch.pixelCount(); ++p) {
    const PixelNet& net = b.nets[size_t(p)];
    EXPECT_EQ(std::memcmp(net.w1, initial[size_t(p)].w1, sizeof(net.w1)), 0) << p;
    EXPECT_EQ(std::memcmp(net.w2, initial[size_t(p)].w2, sizeof(net.w2)), 0) << p;
    EXPECT_EQ(net.mu, initial[size_t(p)].mu);
    const uint32_t first = b.batch.offsets[size_t(p)];
    const int n = int(b.batch.offsets[size_t(p) + 1] - first);
    if (n == 0) continue;
    const double er =
        networkError(net, c, &b.batch.inputs[first * 5], &b.batch.targets[first * 3], n);
    EXPECT_NEAR(net.er, er, 1e-4 * er + 1e-7) << p;

    PixelNet scalarNet = initial[size_t(p)];
    trainNetworkScalar(c, scalarNet, &b.batch.inputs[first * 5], &b.batch.targets[first * 3], n);
    EXPECT_EQ(std::memcmp(scalarNet.w1, initial[size_t(p)].w1, sizeof(net.w1)), 0) << p;
    EXPECT_EQ(std::memcmp(scalarNet.w2, initial[size_t(p)].w2, sizeof(net.w2)), 0) << p;
  }
}

TEST(BpNetworkTest, UnusedInputsAndHiddenUnitsDoNotMatter) {
  NetworkConfig c = makeConfig(4, 6);
  c.epochs = 10;
  c.errorThreshold = 0.0f;
  Batch clean = makeBatch(c, 20);
  Batch dirty = clean;
  // Garbage in the fifth input slot of every sample and in every unused weight.
  for (size_t k = 0; k < dirty.batch.inputs.size(); k += 5) dirty.batch.inputs[k + 4] = 1e3f;
  for (PixelNet& net : dirty.nets) {
    for (int i = 0; i < kMaxNetInputs; ++i)
      for (int h = 0; h < kMaxNetHidden; ++h)
        if (i >= c.inputs || h >= c.hidden) net.w1[i][h] = 7.0f + float(i - h);
    for (int h = c.hidden; h < kMaxNetHidden; ++h)
      for (int o = 0; o < kNetOutputs; ++o) net.w2[h][o] = -5.0f + float(h + o);
  }
  const std::vector<PixelNet> dirtyInitial = dirty.nets;

  const float x[5] = {0.3f, 0.2f, 0.9f, 0.5f, 100.0f};
  const float xClean[5] = {0.3f, 0.2f, 0.9f, 0.5f, 0.0f};
  const glm::vec3 a = predict(clean.nets[0], c, xClean), b = predict(dirty.nets[0], c, x);
  EXPECT_EQ(a, b);

  std::vector<PixelNet*> cleanPtrs = pointers(clean.nets), dirtyPtrs = pointers(dirty.nets);
  trainNetworks(c, cleanPtrs, clean.batch);
  trainNetworks(c, dirtyPtrs, dirty.batch);
  for (size_t p = 0; p < clean.nets.size(); ++p) {
    const PixelNet& cn = clean.nets[p];
    const PixelNet& dn = dirty.nets[p];
    for (int i = 0; i < kMaxNetInputs; ++i) {
      for (int h = 0; h < kMaxNetHidden; ++h) {
        const bool used = i < c.inputs && h < c.hidden;
        EXPECT_EQ(dn.w1[i][h], used ? cn.w1[i][h] : dirtyInitial[p].w1[i][h]) << p;
      }
    }
    for (int h = 0; h < kMaxNetHidden; ++h)
      for (int o = 0; o < kNetOutputs; ++o)
        EXPECT_EQ(dn.w2[h][o], h < c.hidden ? cn.w2[h][o] : dirtyInitial[p].w2[h][o]) << p;
    EXPECT_EQ(cn.er, dn.er);
    EXPECT_EQ(cn.mu, dn.mu);
  }

  // The scalar reference ignores them too.
  const uint32_t n = clean.batch.offsets[1];
  PixelNet cs = makeBatch(c, 1).nets[0], ds = dirtyInitial[0];
  trainNetworkScalar(c, cs, clean.batch.inputs.data(), clean.batch.targets.data(), int(n));
  trainNetworkScalar(c, ds, dirty.batch.inputs.data(), dirty.batch.targets.data(), int(n));
  for (int i = 0; i < c.inputs; ++i)
    for (int h = 0; h < c.hidden; ++h) EXPECT_EQ(cs.w1[i][h], ds.w1[i][h]);
  EXPECT_EQ(cs.er, ds.er);
}

TEST(BpNetworkTest, InitNetworkIsDeterministicAndBounded) {
  const NetworkConfig c = makeConfig(5, 12);
  PixelNet a, b, other;
  // initNetwork must overwrite everything it owns, unused entries included.
  std::fill(&a.w1[0][0], &a.w1[0][0] + kMaxNetInputs * kMaxNetHidden, 3.0f);
  std::fill(&a.w2[0][0], &a.w2[0][0] + kMaxNetHidden * kNetOutputs, 3.0f);
  a.mu = a.er = a.erPrev = a.erFirst = 3.0f;
  initNetwork(a, c, 9);
  initNetwork(b, c, 9);
  initNetwork(other, c, 10);
  EXPECT_TRUE(sameBits(a, b));
  EXPECT_NE(std::memcmp(a.w1, other.w1, sizeof(a.w1)), 0);
  double sum = 0.0;
  for (int i = 0; i < kMaxNetInputs; ++i) {
    for (int h = 0; h < kMaxNetHidden; ++h) {
      if (h < c.hidden) {
        EXPECT_GT(a.w1[i][h], -1.0f);
        EXPECT_LT(a.w1[i][h], 1.0f);
        sum += std::abs(a.w1[i][h]);
      } else {
        EXPECT_EQ(a.w1[i][h], 0.0f);
      }
    }
  }
  EXPECT_GT(sum / (c.inputs * c.hidden), 0.25);  // spread over the interval, mean |w| ~ 0.5
  for (int h = c.hidden; h < kMaxNetHidden; ++h)
    for (int o = 0; o < kNetOutputs; ++o) EXPECT_EQ(a.w2[h][o], 0.0f);
  EXPECT_EQ(a.mu, c.muStart);
  EXPECT_EQ(a.er, 0.0f);
  EXPECT_EQ(a.erPrev, 0.0f);
  EXPECT_EQ(a.erFirst, 0.0f);
}

TEST(BpNetworkTest, ProportionalRateFollowsErrorRatio) {
  NetworkConfig c = makeConfig(4, 8);
  c.rate = LearningRateMode::Proportional;
  c.errorThreshold = 0.0f;
  c.epochs = 1;
  const PixelData d = smoothPixel(4, 16, 3);
  PixelNet net;
  initNetwork(net, c, 8);
  trainNetworkScalar(c, net, d.inputs.data(), d.targets.data(), d.n);
  EXPECT_FLOAT_EQ(net.mu, c.muMax);  // er / er_first = 1 after the first epoch
  c.epochs = 40;
  trainNetworkScalar(c, net, d.inputs.data(), d.targets.data(), d.n);
  EXPECT_GE(net.mu, c.muMin);
  EXPECT_LT(net.mu, c.muMax);  // er fell below er_first of this training
}

TEST(BpNetworkTest, FmaPeakIsPositiveAndFinite) {
  const double peak = measureFmaPeakGflops(1, 0.05);
  EXPECT_GT(peak, 0.0);
  EXPECT_TRUE(std::isfinite(peak));
  const std::string name = networkSimdName();
  EXPECT_TRUE(name == "avx512" || name == "avx2" || name == "sse") << name;
}

}  // namespace
}  // namespace penumbra
