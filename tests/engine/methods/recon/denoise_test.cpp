// Tests for engine/methods/recon/denoise: constant and converged images pass through, SURE
// tracks the true error of every scale, a directly seen emitter's edge stays sharp (and would
// not without the emission buffer), the error falls and the identity takes over as the
// variance shrinks, demodulation keeps a checker sharp, bad input throws naming the field, and
// the output depends neither on the thread count nor on non-finite neighbours.
#include "methods/recon/denoise.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::recon {
namespace {

// A synthetic render: the clean image and what a renderer would hand the denoiser.
struct Scene {
  int width = 0, height = 0;
  std::vector<vec3> clean;  // the true pixel values (emission included)
  std::vector<vec3> mean, variance, halfA, halfB, emission, albedo, albedoVariance, normal;
  std::vector<float> normalVariance, depth, depthVariance;

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

size_t pixelCount(const Scene& s) { return size_t(s.width) * s.height; }

// Flat geometry: one normal and depth everywhere, known exactly.
void flatGeometry(Scene& s) {
  const size_t n = pixelCount(s);
  s.normal.assign(n, vec3(0.0f, 0.0f, 1.0f));
  s.normalVariance.assign(n, 0.0f);
  s.depth.assign(n, 3.0f);
  s.depthVariance.assign(n, 0.0f);
}

// Two independent half buffers with Gaussian noise of the given per-pixel sigma of the full
// mean (each half's mean has twice its variance), their mean and the known variance.
void addNoise(Scene& s, const std::vector<float>& sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  const size_t n = pixelCount(s);
  s.mean.resize(n);
  s.variance.resize(n);
  s.halfA.resize(n);
  s.halfB.resize(n);
  for (size_t p = 0; p < n; ++p) {
    const float half = std::sqrt(2.0f) * sigma[p];
    s.halfA[p] = s.clean[p] + half * vec3(gauss(rng), gauss(rng), gauss(rng));
    s.halfB[p] = s.clean[p] + half * vec3(gauss(rng), gauss(rng), gauss(rng));
    s.mean[p] = 0.5f * (s.halfA[p] + s.halfB[p]);
    s.variance[p] = vec3(sigma[p] * sigma[p]);
  }
}

// Mean squared error against the clean image, over pixels and channels.
using test::mse;

double identityShare(const DenoiseResult& r) {
  return double(std::count(r.scale.begin(), r.scale.end(), uint8_t(0))) / double(r.scale.size());
}

// A textured albedo: stripes of 0.3 and 0.7 four pixels wide, with a fine pattern on top.
vec3 texturedAlbedo(int x, int y) {
  const float stripe = (x / 4) % 2 ? 0.7f : 0.3f;
  const float fine = 0.05f * std::sin(1.3f * float(x) + 0.7f * float(y));
  return vec3(stripe + fine, 0.8f * stripe + fine, 0.6f * stripe + 0.5f * fine);
}

// Illumination: a smooth gradient with a few step edges.
float illumination(int x, int y, int width, int height) {
  float v = 0.4f + 0.5f * float(x) / float(width) + 0.2f * float(y) / float(height);
  if (x > width / 3) v += 0.4f;
  if (y > height / 2) v -= 0.25f;
  if (x + y > (width + height) * 3 / 4) v += 0.6f;
  return v;
}

// §3 of the test plan: albedo texture times a smooth, stepped illumination, with noise of
// sigma = sigmaScale * (0.5 + illumination) per pixel.
Scene gradientScene(int width, int height, float sigmaScale, uint32_t seed) {
  Scene s;
  s.width = width;
  s.height = height;
  const size_t n = pixelCount(s);
  s.clean.resize(n);
  s.albedo.resize(n);
  s.albedoVariance.assign(n, vec3(0.0f));
  std::vector<float> sigma(n);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t p = size_t(y) * width + x;
      const float light = illumination(x, y, width, height);
      s.albedo[p] = texturedAlbedo(x, y);
      s.clean[p] = light * s.albedo[p];
      sigma[p] = sigmaScale * (0.5f + light);
    }
  }
  flatGeometry(s);
  addNoise(s, sigma, seed);
  return s;
}

void expectRelativelyEqual(std::span<const vec3> a, std::span<const vec3> b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t p = 0; p < a.size(); ++p) {
    for (int c = 0; c < 3; ++c) {
      const double scale = std::max(std::abs(double(b[p][c])), 1e-6);
      ASSERT_LE(std::abs(double(a[p][c]) - double(b[p][c])) / scale, tolerance)
          << "pixel " << p << " channel " << c << ": " << a[p][c] << " vs " << b[p][c];
    }
  }
}

TEST(DenoiseConstant, ConstantImageComesOutUnchanged) {
  Scene s;
  s.width = 40;
  s.height = 32;
  const size_t n = pixelCount(s);
  const vec3 value(0.3f, 0.5f, 0.7f);
  s.clean.assign(n, value);
  s.mean.assign(n, value);
  s.halfA.assign(n, value);
  s.halfB.assign(n, value);
  s.variance.assign(n, vec3(0.02f, 0.05f, 0.01f));
  s.albedo.assign(n, vec3(0.6f, 0.4f, 0.2f));
  s.albedoVariance.assign(n, vec3(1e-3f));
  s.normal.assign(n, vec3(0.0f, 1.0f, 0.0f));
  s.normalVariance.assign(n, 1e-2f);
  s.depth.assign(n, 7.0f);
  s.depthVariance.assign(n, 0.1f);
  for (bool cross : {true, false}) {
    for (bool demodulate : {true, false}) {
      DenoiseConfig config;
      config.crossFilter = cross;
      config.demodulate = demodulate;
      const DenoiseResult r = denoise(s.input(), config);
      SCOPED_TRACE(std::string("cross ") + (cross ? "on" : "off") + ", demodulation " +
                   (demodulate ? "on" : "off"));
      expectRelativelyEqual(r.output.pixels, s.clean, 1e-5);
      // A constant has no bias, so a filter wins wherever V > 0.
      EXPECT_LT(identityShare(r), 0.01);
    }
  }
}

TEST(DenoiseConverged, ConvergedImageIsLeftAlone) {
  // Texture in the illumination and the albedo, steps, and noise of sigma 1e-6.
  Scene s;
  s.width = 72;
  s.height = 60;
  const size_t n = pixelCount(s);
  s.clean.resize(n);
  s.albedo.resize(n);
  s.albedoVariance.assign(n, vec3(0.0f));
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const size_t p = size_t(y) * s.width + x;
      const float light = illumination(x, y, s.width, s.height) +
                          0.15f * std::sin(0.9f * float(x) + 0.4f * float(y)) +
                          0.1f * std::cos(0.55f * float(y) - 0.2f * float(x));
      s.albedo[p] = texturedAlbedo(x, y);
      s.clean[p] = light * s.albedo[p];
    }
  }
  flatGeometry(s);
  addNoise(s, std::vector<float>(n, 1e-6f), 7);
  const DenoiseResult r = denoise(s.input(), DenoiseConfig{});
  expectRelativelyEqual(r.output.pixels, s.mean, 1e-4);
  EXPECT_GE(identityShare(r), 0.99);
  for (size_t p = 0; p < n; ++p) {
    if (r.scale[p] == 0) {
      ASSERT_EQ(r.varianceRatio[p], 1.0f);
    }
  }
}

TEST(DenoiseSure, PerScaleEstimateTracksTrueError) {
  const Scene s = gradientScene(128, 128, 0.1f, 11);
  DenoiseDetail detail;
  const DenoiseConfig config;
  const DenoiseResult r = denoiseDetailed(s.input(), config, &detail);
  ASSERT_EQ(detail.scaleOutput.size(), config.radii.size() + 1);
  ASSERT_EQ(detail.scaleMse.size(), config.radii.size() + 1);
  for (size_t scale = 0; scale < detail.scaleOutput.size(); ++scale) {
    const double truth = mse(detail.scaleOutput[scale].pixels, s.clean);
    double estimate = 0.0;
    for (float e : detail.scaleMse[scale]) estimate += e;
    estimate /= double(detail.scaleMse[scale].size());
    EXPECT_NEAR(estimate, truth, 0.15 * truth) << "scale " << scale;
  }
  const double noisy = mse(s.mean, s.clean), denoised = mse(r.output.pixels, s.clean);
  EXPECT_LT(denoised, noisy / 3.0) << "noisy " << noisy << ", denoised " << denoised;
  // The chosen scale's smoothed estimate is what the result reports.
  for (size_t p = 0; p < r.scale.size(); ++p) {
    ASSERT_GE(r.mseEstimate[p], 0.0f);
    ASSERT_GE(r.varianceRatio[p], 0.0f);
    ASSERT_LE(r.varianceRatio[p], 1.0f);
    ASSERT_NEAR(r.mseEstimate[p], std::max(0.0f, detail.scaleMseSmoothed[r.scale[p]][p]),
                1e-6f * std::max(1.0f, r.mseEstimate[p]));
  }
}

// A bright emitter (x < kEdge, emission 50) meets a dim wall (0.5) along a jagged edge: the
// pixels of column kEdge are partly covered (coverage 0.2 .. 0.8 per row). Their emission is
// known exactly, but the variance of their mean is the per-sample one, 50^2 c (1 - c) / 16,
// as with stratified samples, which far overestimates the true one.
constexpr int kEdge = 30;

Scene emitterScene(uint32_t seed) {
  Scene s;
  s.width = 64;
  s.height = 64;
  const size_t n = pixelCount(s);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coverage(0.2f, 0.8f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  const float wallSigma = 0.05f;
  s.clean.resize(n);
  s.emission.resize(n);
  s.mean.resize(n);
  s.variance.resize(n);
  s.halfA.resize(n);
  s.halfB.resize(n);
  s.albedo.assign(n, vec3(0.8f));
  s.albedoVariance.assign(n, vec3(0.0f));
  flatGeometry(s);
  for (int y = 0; y < s.height; ++y) {
    const float c = coverage(rng);
    for (int x = 0; x < s.width; ++x) {
      const size_t p = size_t(y) * s.width + x;
      // Share of the pixel that is wall, whose light is noisy.
      const float wall = x < kEdge ? 0.0f : (x == kEdge ? 1.0f - c : 1.0f);
      const float emitted = x < kEdge ? 50.0f : (x == kEdge ? 50.0f * c : 0.0f);
      s.clean[p] = vec3(emitted + 0.5f * wall);
      s.emission[p] = vec3(emitted);
      const float sigma = wallSigma * std::sqrt(std::max(wall, 1e-3f));
      const float half = std::sqrt(2.0f) * sigma;
      s.halfA[p] = s.clean[p] + half * vec3(gauss(rng), gauss(rng), gauss(rng));
      s.halfB[p] = s.clean[p] + half * vec3(gauss(rng), gauss(rng), gauss(rng));
      s.mean[p] = 0.5f * (s.halfA[p] + s.halfB[p]);
      const float coverageVariance = x == kEdge ? 2500.0f * c * (1.0f - c) / 16.0f : 0.0f;
      s.variance[p] = vec3(sigma * sigma + coverageVariance);
    }
  }
  return s;
}

// The largest relative error of column x, and the relative error of its mean.
struct ColumnError {
  double worst = 0.0, ofMean = 0.0;
};

ColumnError columnError(const Scene& s, const Image& out, int x) {
  ColumnError e;
  double sum = 0.0, truth = 0.0;
  for (int y = 0; y < s.height; ++y) {
    const size_t p = size_t(y) * s.width + x;
    for (int c = 0; c < 3; ++c) {
      const double t = s.clean[p][c], v = out.pixels[p][c];
      e.worst = std::max(e.worst, std::abs(v - t) / t);
      sum += v;
      truth += t;
    }
  }
  e.ofMean = std::abs(sum - truth) / truth;
  return e;
}

TEST(DenoiseEmission, EmitterEdgeStaysSharp) {
  const Scene s = emitterScene(5);
  const double tolerance = 0.05;  // relative, per pixel on the emitter and the edge
  const DenoiseResult r = denoise(s.input(), DenoiseConfig{});
  const ColumnError emitter = columnError(s, r.output, kEdge - 1);
  const ColumnError edge = columnError(s, r.output, kEdge);
  EXPECT_LE(emitter.worst, tolerance);
  EXPECT_LE(edge.worst, tolerance);
  // The wall next to the edge is noisy per pixel; what must not happen is light leaking into
  // it, which would move the column's mean.
  for (int x = kEdge + 1; x <= kEdge + 2; ++x)
    EXPECT_LE(columnError(s, r.output, x).ofMean, tolerance) << "column " << x;

  // Without the emission buffer the edge's overestimated variance lets its pixels average
  // their very different neighbours along the edge: the same check fails.
  Scene without = s;
  without.emission.clear();
  const DenoiseResult blurred = denoise(without.input(), DenoiseConfig{});
  EXPECT_GT(columnError(without, blurred.output, kEdge).worst, tolerance);
}

TEST(DenoiseConsistency, ErrorFallsAndIdentityTakesOverAsVarianceShrinks) {
  // The same clean image with the variance falling 4x per step (sigma halves), from noisy to
  // nearly converged. The share of identity pixels is a noisy count while it is small, so it
  // may dip by a point or two between neighbouring steps. With the SURE maps smoothed over
  // 11x11 (sureSmoothRadius 5) the identity takes over one step later than over 3x3 (share
  // 0.94 at step 13, against 0.99), at an MSE equal to the mean's, and the MSE is lower at
  // every noisier step (0.0061 against 0.0098 at step 0): hence 15 steps.
  double previousMse = std::numeric_limits<double>::infinity(), previousShare = 0.0;
  std::vector<double> shares;
  for (int step = 0; step < 15; ++step) {
    const float sigma = 0.2f / float(1 << step);
    const Scene s = gradientScene(96, 96, sigma, 21);
    const DenoiseResult r = denoise(s.input(), DenoiseConfig{});
    const double error = mse(r.output.pixels, s.clean), share = identityShare(r);
    SCOPED_TRACE("step " + std::to_string(step) + ", sigma " + std::to_string(sigma));
    EXPECT_LT(error, previousMse);
    EXPECT_LE(error, mse(s.mean, s.clean));  // never worse than the noisy mean
    EXPECT_GE(share, previousShare - 0.02);
    previousMse = error;
    previousShare = share;
    shares.push_back(share);
  }
  EXPECT_LT(shares.front(), 0.05);
  EXPECT_GT(shares.back(), 0.95);
  EXPECT_GT(shares[shares.size() - 2], shares[shares.size() - 4]);
}

TEST(DenoiseDemodulation, CheckerAlbedoStaysSharp) {
  // A checker of 4-pixel squares (albedo 0.2 / 0.8) under smooth light, noisy.
  Scene s;
  s.width = 96;
  s.height = 96;
  const size_t n = pixelCount(s);
  s.clean.resize(n);
  s.albedo.resize(n);
  s.albedoVariance.assign(n, vec3(0.0f));
  std::vector<float> sigma(n);
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const size_t p = size_t(y) * s.width + x;
      const float a = ((x / 4) + (y / 4)) % 2 ? 0.8f : 0.2f;
      const float light = 0.6f + 0.4f * float(x) / float(s.width) + 0.2f * float(y) / s.height;
      s.albedo[p] = vec3(a);
      s.clean[p] = vec3(a * light);
      sigma[p] = 0.08f * light;
    }
  }
  flatGeometry(s);
  addNoise(s, sigma, 31);

  DenoiseConfig plain;
  plain.demodulate = false;
  const DenoiseResult demodulated = denoise(s.input(), DenoiseConfig{});
  const DenoiseResult notDemodulated = denoise(s.input(), plain);
  const double withDemodulation = mse(demodulated.output.pixels, s.clean);
  const double withoutDemodulation = mse(notDemodulated.output.pixels, s.clean);
  EXPECT_LT(withDemodulation, 0.7 * withoutDemodulation);

  // Contrast across the vertical checker edges (x = 4k - 1 | 4k), averaged over the image.
  double contrast = 0.0, truth = 0.0;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 4; x < s.width; x += 4) {
      const size_t left = size_t(y) * s.width + x - 1, right = left + 1;
      contrast += std::abs(demodulated.output.pixels[right].y - demodulated.output.pixels[left].y);
      truth += std::abs(s.clean[right].y - s.clean[left].y);
    }
  }
  EXPECT_NEAR(contrast, truth, 0.1 * truth);
}

// Expects denoise to throw std::invalid_argument whose message names `field`.
void expectThrowNaming(const std::function<void()>& call, const std::string& field) {
  try {
    call();
    ADD_FAILURE() << "no exception for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos)
        << "message '" << e.what() << "' does not name " << field;
  }
}

TEST(DenoiseValidation, BadInputAndConfigThrowNamingTheField) {
  const Scene s = gradientScene(16, 12, 0.1f, 3);
  const std::vector<vec3> short3(10, vec3(0.5f));
  const std::vector<float> short1(10, 0.5f);
  auto withInput = [&](const std::function<void(DenoiseInput&)>& spoil, const std::string& f) {
    DenoiseInput in = s.input();
    spoil(in);
    expectThrowNaming([&] { denoise(in, DenoiseConfig{}); }, f);
  };
  withInput([&](DenoiseInput& in) { in.mean = short3; }, "mean");
  withInput([&](DenoiseInput& in) { in.mean = {}; }, "mean");
  withInput([&](DenoiseInput& in) { in.variance = short3; }, "variance");
  withInput([&](DenoiseInput& in) { in.variance = {}; }, "variance");
  withInput([&](DenoiseInput& in) { in.halfA = short3; }, "halfA");
  withInput([&](DenoiseInput& in) { in.halfB = {}; }, "halfB");
  withInput([&](DenoiseInput& in) { in.emission = short3; }, "emission");
  withInput([&](DenoiseInput& in) { in.albedo = short3; }, "albedo");
  withInput([&](DenoiseInput& in) { in.albedoVariance = short3; }, "albedoVariance");
  withInput([&](DenoiseInput& in) { in.normal = short3; }, "normal");
  withInput([&](DenoiseInput& in) { in.normalVariance = short1; }, "normalVariance");
  withInput([&](DenoiseInput& in) { in.depth = short1; }, "depth");
  withInput([&](DenoiseInput& in) { in.depthVariance = short1; }, "depthVariance");
  withInput([&](DenoiseInput& in) { in.width = 0; }, "width");
  withInput([&](DenoiseInput& in) { in.height = -1; }, "height");

  auto withConfig = [&](const std::function<void(DenoiseConfig&)>& spoil, const std::string& f) {
    DenoiseConfig config;
    spoil(config);
    EXPECT_NE(validate(config).find(f), std::string::npos) << validate(config);
    expectThrowNaming([&] { denoise(s.input(), config); }, f);
  };
  EXPECT_EQ(validate(DenoiseConfig{}), "");
  withConfig([](DenoiseConfig& c) { c.radii = {2, 1}; }, "radii");
  withConfig([](DenoiseConfig& c) { c.radii = {1, 1}; }, "radii");
  withConfig([](DenoiseConfig& c) { c.radii = {0, 2}; }, "radii");
  withConfig([](DenoiseConfig& c) { c.radii = {1, 1000}; }, "radii");
  // A setting with a flag is named by its flag (recon::denoiseParams()); the others by field.
  withConfig([](DenoiseConfig& c) { c.k = 0.0f; }, "--nl-k");
  withConfig([](DenoiseConfig& c) { c.k = std::numeric_limits<float>::quiet_NaN(); }, "--nl-k");
  withConfig([](DenoiseConfig& c) { c.noiseCancel = -1.0f; }, "noiseCancel");
  withConfig([](DenoiseConfig& c) { c.patchRadius = -1; }, "--nl-patch");
  withConfig([](DenoiseConfig& c) { c.kFeature = -0.5f; }, "--feature-k");
  withConfig([](DenoiseConfig& c) { c.tau = 0.0f; }, "tau");
  withConfig([](DenoiseConfig& c) { c.sureSmoothRadius = -2; }, "--sure-smooth");
  withConfig([](DenoiseConfig& c) { c.albedoEpsilon = 0.0f; }, "albedoEpsilon");
  withConfig([](DenoiseConfig& c) { c.radii = {1, 5}; }, "denseRadius");
}

TEST(DenoiseDeterminism, SameOutputForOneAndTwoThreads) {
  const Scene s = gradientScene(64, 56, 0.1f, 41);
  DenoiseResult one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = denoise(s.input(), DenoiseConfig{});
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = denoise(s.input(), DenoiseConfig{});
  }
  ASSERT_EQ(one.output.pixels.size(), two.output.pixels.size());
  for (size_t p = 0; p < one.output.pixels.size(); ++p) {
    ASSERT_EQ(one.output.pixels[p], two.output.pixels[p]) << "pixel " << p;
    ASSERT_EQ(one.scale[p], two.scale[p]) << "pixel " << p;
    ASSERT_EQ(one.mseEstimate[p], two.mseEstimate[p]) << "pixel " << p;
  }
}

// The sweep is compiled for the baseline, AVX2 and AVX-512 and picked at run time; all must
// give the same bits (on a CPU without the wider sets this compares the baseline with itself).
TEST(DenoiseDeterminism, SameOutputForEveryInstructionSet) {
  const Scene s = gradientScene(64, 56, 0.1f, 42);
  const DenoiseResult widest = denoise(s.input(), DenoiseConfig{});
  for (const char* cap : {"avx2", "sse"}) {
    ASSERT_EQ(setenv("PENUMBRA_RECON_SIMD", cap, 1), 0);
    const DenoiseResult narrower = denoise(s.input(), DenoiseConfig{});
    unsetenv("PENUMBRA_RECON_SIMD");
    for (size_t p = 0; p < widest.output.pixels.size(); ++p) {
      ASSERT_EQ(widest.output.pixels[p], narrower.output.pixels[p]) << cap << ", pixel " << p;
      ASSERT_EQ(widest.mseEstimate[p], narrower.mseEstimate[p]) << cap << ", pixel " << p;
    }
  }
}

TEST(DenoiseNonFinite, BadPixelIsKeptAndIgnoredByItsNeighbours) {
  Scene s = gradientScene(48, 40, 0.1f, 51);
  const size_t nanPixel = size_t(20) * s.width + 24, infPixel = size_t(5) * s.width + 7;
  s.mean[nanPixel].y = std::numeric_limits<float>::quiet_NaN();
  s.variance[infPixel] = vec3(std::numeric_limits<float>::infinity());
  const DenoiseResult r = denoise(s.input(), DenoiseConfig{});
  EXPECT_TRUE(std::isnan(r.output.pixels[nanPixel].y));
  EXPECT_EQ(r.scale[nanPixel], 0);
  EXPECT_EQ(r.output.pixels[infPixel], s.mean[infPixel]);
  EXPECT_EQ(r.scale[infPixel], 0);
  for (size_t p = 0; p < r.output.pixels.size(); ++p) {
    if (p == nanPixel) continue;
    ASSERT_TRUE(isFinite(r.output.pixels[p])) << "pixel " << p;
  }
  // Extreme but finite values do not turn into NaN either.
  Scene extreme = gradientScene(24, 20, 0.1f, 52);
  extreme.mean[30] = vec3(3e38f);
  extreme.halfA[30] = extreme.halfB[30] = vec3(3e38f);
  extreme.variance[31] = vec3(3e38f);
  extreme.variance[32] = vec3(0.0f);
  const DenoiseResult e = denoise(extreme.input(), DenoiseConfig{});
  for (size_t p = 0; p < e.output.pixels.size(); ++p)
    ASSERT_TRUE(isFinite(e.output.pixels[p])) << "pixel " << p;
}

TEST(DenoiseTiny, ImagesSmallerThanTheWindowsWork) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{3, 2}, std::pair{1, 9}, std::pair{17, 1}}) {
    const Scene s = gradientScene(w, h, 0.1f, 71);
    const DenoiseResult r = denoise(s.input(), DenoiseConfig{});
    ASSERT_EQ(r.output.pixels.size(), size_t(w) * h);
    for (const vec3& c : r.output.pixels) ASSERT_TRUE(isFinite(c)) << w << "x" << h;
  }
  // A single pixel has nothing to average with: it is its own mean.
  const Scene one = gradientScene(1, 1, 0.1f, 72);
  EXPECT_EQ(denoise(one.input(), DenoiseConfig{}).output.pixels[0], one.mean[0]);
}

TEST(DenoiseCancel, CancelledRunReturnsSizedResult) {
  const Scene s = gradientScene(32, 32, 0.1f, 61);
  const std::atomic<bool> cancel{true};
  const DenoiseResult r = denoise(s.input(), DenoiseConfig{}, &cancel);
  EXPECT_EQ(r.output.width, 32);
  EXPECT_EQ(r.output.pixels.size(), size_t(32 * 32));
  EXPECT_EQ(r.scale.size(), size_t(32 * 32));
}

TEST(DenoiseBoxMean, AveragesTheClippedNeighbourhood) {
  // 5x4: one value 25 at (2, 1), a NaN at (4, 3), zeros elsewhere.
  std::vector<float> v(20, 0.0f);
  v[1 * 5 + 2] = 25.0f;
  v[3 * 5 + 4] = std::nanf("");
  const auto m = boxMean(v, 5, 4, 1);
  EXPECT_FLOAT_EQ(m[1 * 5 + 2], 25.0f / 9.0f);  // inside: 9 values
  EXPECT_FLOAT_EQ(m[0 * 5 + 1], 25.0f / 6.0f);  // the top row: 6 values
  EXPECT_FLOAT_EQ(m[0 * 5 + 4], 0.0f);          // out of reach
  EXPECT_FLOAT_EQ(m[2 * 5 + 3], 25.0f / 8.0f);  // 9 values, the NaN left out
  EXPECT_FLOAT_EQ(m[3 * 5 + 4], 0.0f);          // its own NaN left out: 3 zeros
  // Radius 0 is the identity on finite values; the whole image when it reaches every pixel.
  const auto same = boxMean(v, 5, 4, 0);
  EXPECT_FLOAT_EQ(same[1 * 5 + 2], 25.0f);
  const auto all = boxMean(v, 5, 4, 10);
  for (float x : all) EXPECT_FLOAT_EQ(x, 25.0f / 19.0f);
  // Only the valid pixels count; an invalid one keeps its value.
  std::vector<float> valid(20, 1.0f);
  valid[1 * 5 + 1] = 0.0f;
  const auto masked = boxMean(v, 5, 4, 1, valid);
  EXPECT_FLOAT_EQ(masked[1 * 5 + 2], 25.0f / 8.0f);
  EXPECT_FLOAT_EQ(masked[1 * 5 + 1], 0.0f);
}

}  // namespace
}  // namespace penumbra::recon
