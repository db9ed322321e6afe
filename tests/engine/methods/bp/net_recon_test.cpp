// The networks as a control variate (methods/bp/net_recon.h) on a synthetic penumbra: the
// radiance is a step along a shear of the image's x and the light sample's s, so a network
// fitted on the neighbours' samples over (dx, dy, s, t) predicts each sample of the centre
// pixel. The corrected samples must keep the pixel's mean (the correction is a control variate:
// its mean over the pixel is zero) and vary far less than the raw ones.
#include "methods/bp/net_recon.h"

#include "core/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace penumbra {
namespace net_recon_test {

constexpr int kSize = 7;  // pixels per side; the centre pixel is (3, 3)
constexpr int kSpp = 16;
constexpr uint64_t kUnlimitedRays = uint64_t(1) << 40;  // no training budget

// The penumbra: lit where the light sample's s lies past an edge that moves with the image's x.
float radianceAt(float imageX, float s) { return s > 0.5f + 0.12f * (imageX - 3.5f) ? 1.0f : 0.0f; }

struct Sample {
  CameraSample camera;
  PathFeatures features;
  vec3 radiance;
};

Sample draw(int px, int py, Pcg32& rng) {
  Sample s;
  s.camera.imageX = float(px) + rng.nextFloat();
  s.camera.imageY = float(py) + rng.nextFloat();
  s.features.albedo = vec3(0.5f);
  s.features.lightObject = 0;
  s.features.lightChart = {rng.nextFloat(), rng.nextFloat()};
  s.radiance = vec3(0.5f * radianceAt(s.camera.imageX, s.features.lightChart.x));
  return s;
}

// kSpp samples of every pixel of the image into a film and the networks' store; `radiance`
// (px, py, the penumbra's radiance) may replace a sample's radiance.
template <class Radiance>
void recordImage(bp::NetRecon& nets, Film& film, Pcg32& rng, Radiance radiance) {
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px)
      for (int k = 0; k < kSpp; ++k) {
        const size_t p = size_t(py) * kSize + size_t(px);
        Sample s = draw(px, py, rng);
        s.radiance = radiance(px, py, s.radiance);
        nets.record(p, px, py, s.camera, s.radiance, s.features);
        film.add(p, s.radiance, s.features);
      }
}

// The penumbra into a film and the networks' store, then one training; true when the centre
// pixel's network corrects.
bool trainOnPenumbra(bp::NetRecon& nets, Film& film, Pcg32& rng) {
  recordImage(nets, film, rng, [](int, int, vec3 penumbra) { return penumbra; });
  return nets.train(film, kUnlimitedRays, nullptr) &&
         nets.trainedMap()[size_t(3) * kSize + 3] == 1.0f;
}

TEST(NetRecon, ACorrectedPenumbraKeepsItsMeanAndLosesMostOfItsVariance) {
  bp::NetReconConfig config;
  config.share = 1.0f;  // every pixel whose samples vary trains
  config.epochs = 300;
  const size_t centre = size_t(3) * kSize + 3;
  // A network corrects an eighth as many samples as it was fitted on (24 neighbours x 16):
  // 48 of the centre's fresh samples; pooled over 20 trainings on different samples.
  const int corrections = 24 * kSpp / 8;
  double raw = 0, rawSq = 0, corrected = 0, correctedSq = 0;
  int n = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    bp::NetRecon nets(kSize, kSize, false, false, config);
    Film film(kSize, kSize);
    Pcg32 rng(seed, 1);
    ASSERT_TRUE(trainOnPenumbra(nets, film, rng))
        << "seed " << seed << ": held-out error " << nets.heldOutMap()[centre];
    for (int k = 0; k <= corrections; ++k) {
      const Sample s = draw(3, 3, rng);
      const vec3 c = nets.correction(centre, 3, 3, s.camera, s.features);
      if (k == corrections) {
        EXPECT_EQ(c, vec3(0.0f)) << "a sample past the cap was corrected";
        break;
      }
      const float r = s.radiance.x, z = r - c.x;
      raw += r, rawSq += double(r) * r;
      corrected += z, correctedSq += double(z) * z;
      ++n;
    }
  }
  const double rawMean = raw / n, rawVar = rawSq / n - rawMean * rawMean;
  const double cMean = corrected / n, cVar = correctedSq / n - cMean * cMean;
  // The exact mean: the lit share of the light over the pixel is 1/2 (the edge passes through
  // s = 0.5 at the pixel's centre and moves linearly across it), times 0.5. The network's mean
  // over the pixel is taken over the neighbours' samples' light points (their distribution):
  // each training's own error is that of a mean of its 24 x 16 samples, shared by its 48
  // corrected samples.
  const double neighbours = 24.0 * kSpp, trainings = 20;
  EXPECT_NEAR(rawMean, 0.25, 4.0 * std::sqrt(rawVar / n));
  EXPECT_NEAR(cMean, 0.25, 4.0 * std::sqrt(cVar / n + rawVar / neighbours / trainings));
  EXPECT_LT(cVar, 0.3 * rawVar) << "raw variance " << rawVar << ", corrected " << cVar;
}

TEST(NetRecon, PixelsWithoutSpreadTrainNoNetworkAndAreNotCorrected) {
  bp::NetReconConfig config;
  config.share = 1.0f;
  bp::NetRecon nets(kSize, kSize, false, false, config);
  Film film(kSize, kSize);
  Pcg32 rng(3, 1);
  recordImage(nets, film, rng, [](int, int, vec3) { return vec3(0.3f); });  // nothing to explain
  ASSERT_TRUE(nets.train(film, kUnlimitedRays, nullptr));
  EXPECT_EQ(nets.trainedPixels(), 0u);
  const Sample s = draw(3, 3, rng);
  EXPECT_EQ(nets.correction(size_t(3) * kSize + 3, 3, 3, s.camera, s.features), vec3(0.0f));
}

// The inspector's fit: along the light's s the penumbra is a step, so the network's partial
// dependence on s rises from dark to lit and the inspector picks s as the input that matters
// most; the curve then follows the pixel's own samples (which it never saw) better than their
// mean does.
TEST(NetRecon, TheInspectorsFitFollowsThePenumbraAlongTheLightsPosition) {
  bp::NetReconConfig config;
  config.share = 1.0f;
  config.epochs = 300;
  bp::NetRecon nets(kSize, kSize, false, false, config);
  Film film(kSize, kSize);
  Pcg32 rng(5, 1);
  ASSERT_TRUE(trainOnPenumbra(nets, film, rng));
  const size_t centre = size_t(3) * kSize + 3;
  const auto fit = nets.fitAlong(centre);
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->input, "light s");
  ASSERT_GE(fit->curve.size(), 3u);
  // Demodulated: lit is 0.5 / (0.5 + 0.01).
  const float lit = 0.5f / 0.51f;
  EXPECT_LT(fit->curve.front(), 0.3f * lit);
  EXPECT_GT(fit->curve.back(), 0.7f * lit);
  EXPECT_EQ(fit->samples.size(), size_t(24 * kSpp));
  ASSERT_EQ(fit->own.size(), size_t(kSpp));
  double curveErr = 0, meanErr = 0, mean = 0;
  for (const glm::vec2& o : fit->own) mean += o.y / kSpp;
  for (const glm::vec2& o : fit->own) {
    const float at = (o.x - fit->lo) / (fit->hi - fit->lo) * float(fit->curve.size() - 1);
    const size_t i = size_t(std::clamp(std::lround(at), 0L, long(fit->curve.size() - 1)));
    curveErr += std::pow(fit->curve[i] - o.y, 2.0);
    meanErr += std::pow(mean - o.y, 2.0);
  }
  EXPECT_LT(curveErr, 0.5 * meanErr);
  // A pixel without a network has no fit.
  bp::NetRecon untrained(kSize, kSize, false, false, config);
  EXPECT_FALSE(untrained.fitAlong(centre).has_value());
}

// The networks map: the pixels with a network correct (or wait for more samples), the ones
// that only keep samples for them say so, and a pixel with nothing to explain has no role.
TEST(NetRecon, TheNetworksMapSaysWhatEachPixelDoes) {
  bp::NetReconConfig config;
  config.share = 1.5f / float(kSize * kSize);  // one network: the widest spread
  config.reach = 1;
  bp::NetRecon nets(kSize, kSize, false, false, config);
  Film film(kSize, kSize);
  Pcg32 rng(9, 1);
  recordImage(nets, film, rng, [](int px, int py, vec3 penumbra) {
    return px == 3 && py == 3 ? penumbra : vec3(0.25f);  // only the centre varies
  });
  std::vector<float> roles = nets.roleMap();
  EXPECT_EQ(roles[0], float(bp::NetRecon::kStores)) << "before a choice every pixel stores";
  ASSERT_TRUE(nets.train(film, kUnlimitedRays, nullptr));
  roles = nets.roleMap();
  ASSERT_EQ(roles.size(), size_t(kSize * kSize));
  const size_t centre = size_t(3) * kSize + 3;
  // The centre's network: fitted on flat neighbours, it cannot predict the centre's spread.
  EXPECT_EQ(roles[centre], float(bp::NetRecon::kHeldOut));
  for (int py = 0; py < kSize; ++py)
    for (int px = 0; px < kSize; ++px) {
      const size_t p = size_t(py) * kSize + size_t(px);
      if (p == centre) continue;
      const bool near = std::abs(px - 3) <= 1 && std::abs(py - 3) <= 1;
      EXPECT_EQ(roles[p], float(near ? bp::NetRecon::kStores : bp::NetRecon::kRoleNone))
          << px << ", " << py;
    }
  EXPECT_EQ(bp::NetRecon::roleLabels().size(), size_t(bp::NetRecon::kRoles));
}

}  // namespace net_recon_test
}  // namespace penumbra
