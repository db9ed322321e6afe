// The environment map: its direction convention, and its importance sampler checked against
// the map (chi-square over the texels, pdfs that integrate to one and agree with the samples).
#include "scene/environment.h"

#include "core/image_io.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace penumbra {
namespace {

constexpr double kPi = 3.14159265358979323846;

constexpr float kDirectionTolerance = 1e-5f;
using test::expectNear;

TEST(Environment, MapConventionIsBlendersInAYUpWorld) {
  expectNear(equirectToDirection({0.5f, 0.0f}), {0, 1, 0},
             kDirectionTolerance);  // top row: straight up
  expectNear(equirectToDirection({0.3f, 1.0f}), {0, -1, 0},
             kDirectionTolerance);  // bottom row: straight down
  expectNear(equirectToDirection({0.5f, 0.5f}), {1, 0, 0}, kDirectionTolerance);  // centre: +x
  expectNear(equirectToDirection({0.75f, 0.5f}), {0, 0, 1},
             kDirectionTolerance);  // towards a default camera
  expectNear(equirectToDirection({0.25f, 0.5f}), {0, 0, -1}, kDirectionTolerance);  // Blender's +y
  expectNear(equirectToDirection({0.0f, 0.5f}), {-1, 0, 0}, kDirectionTolerance);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(0.01f, 0.99f);
  for (int i = 0; i < 100; ++i) {
    const glm::vec2 ut(U(rng), U(rng));
    const glm::vec2 back = directionToEquirect(equirectToDirection(ut));
    EXPECT_NEAR(back.x, ut.x, 1e-4f);
    EXPECT_NEAR(back.y, ut.y, 1e-4f);
  }
}

// A map with structure everywhere: a gradient in elevation, stripes in azimuth and a hot spot.
std::shared_ptr<const Image> structuredMap(int width, int height) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float v = 0.2f + float(y) / float(height) + ((x / 3) % 2 ? 0.5f : 0.0f);
      if (x == width / 3 && y == height / 4) v = 40.0f;
      image.at(x, y) = vec3(v, 0.5f * v, 0.1f);
    }
  // A black patch: its inner texel, whose bilinear lookup is black, is never sampled.
  for (int y = height - 3; y < height; ++y)
    for (int x = 0; x < 3; ++x) image.at(x, y) = vec3(0.0f);
  return std::make_shared<const Image>(std::move(image));
}

// Wilson-Hilferty: the chi-square statistic with k degrees of freedom as a standard normal.
double chiSquareZ(double statistic, double k) {
  const double a = 2.0 / (9.0 * k);
  return (std::cbrt(statistic / k) - (1 - a)) / std::sqrt(a);
}

TEST(Environment, SamplesFollowLuminanceTimesSolidAngle) {
  constexpr int kW = 24, kH = 12, kSamples = 400000;
  const auto map = structuredMap(kW, kH);
  const EnvironmentLight light(map, 2.0f, 0.0f);
  // Expected share of each texel: its mean luminance under the bilinear lookup (3/4 itself and
  // 1/8 each neighbour, per axis; wrapping in azimuth, clamped at the poles) times its solid
  // angle, normalised.
  auto lum = [&](int x, int y) {
    return double(luminance(map->at((x + kW) % kW, std::clamp(y, 0, kH - 1))));
  };
  auto rowMean = [&](int x, int y) {
    return 0.75 * lum(x, y) + 0.125 * (lum(x - 1, y) + lum(x + 1, y));
  };
  std::vector<double> expected(size_t(kW * kH));
  double total = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double solidAngle =
          2 * kPi / kW * (std::cos(kPi * y / kH) - std::cos(kPi * (y + 1) / kH));
      const double mean = 0.75 * rowMean(x, y) + 0.125 * (rowMean(x, y - 1) + rowMean(x, y + 1));
      expected[size_t(y * kW + x)] = mean * solidAngle;
      total += expected[size_t(y * kW + x)];
    }
  std::vector<double> counts(expected.size(), 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (int i = 0; i < kSamples; ++i) {
    vec3 d;
    float pdf = 0;
    ASSERT_TRUE(light.sample({U(rng), U(rng)}, d, pdf));
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-4f);
    const glm::vec2 ut = directionToEquirect(d);
    const int x = std::min(kW - 1, int(ut.x * kW)), y = std::min(kH - 1, int(ut.y * kH));
    counts[size_t(y * kW + x)] += 1;
    if (i % 97 == 0) {
      EXPECT_NEAR(light.pdf(d), pdf, 1e-3f * pdf) << "sample " << i;
    }
  }
  double statistic = 0;
  int cells = 0;
  for (size_t c = 0; c < counts.size(); ++c) {
    const double e = expected[c] / total * kSamples;
    if (e == 0) {
      EXPECT_EQ(counts[c], 0) << "a black texel was sampled";
      continue;
    }
    statistic += (counts[c] - e) * (counts[c] - e) / e;
    ++cells;
  }
  // The statistic's z-score: |z| < 4 holds by chance with probability 1 - 6e-5.
  EXPECT_LT(std::abs(chiSquareZ(statistic, cells - 1)), 4.0) << "chi-square " << statistic;
}

TEST(Environment, PdfIntegratesToOneAndTheIntegralIsTheMapsLuminance) {
  const auto map = structuredMap(16, 8);
  for (float rotation : {0.0f, 37.0f}) {
    const EnvironmentLight light(map, 3.0f, rotation);
    // Midpoint quadrature in (theta, phi) on a grid whose cells each lie in one texel (the map
    // is 16 x 8): the piecewise-constant pdf is integrated up to the sin theta rule's error.
    constexpr int kTheta = 800, kPhi = 1600;
    double pdfSum = 0, radianceSum = 0;
    for (int i = 0; i < kTheta; ++i) {
      const double theta = kPi * (i + 0.5) / kTheta;
      const double weight = std::sin(theta) * (kPi / kTheta) * (2 * kPi / kPhi);
      for (int j = 0; j < kPhi; ++j) {
        // Unrotated grid directions: with rotation the grid turns with the map.
        const vec3 m = equirectToDirection({float((j + 0.5) / kPhi), float(theta / kPi)});
        const float r = rotation * float(kPi) / 180.0f;
        const vec3 d(std::cos(r) * m.x + std::sin(r) * m.z, m.y,
                     -std::sin(r) * m.x + std::cos(r) * m.z);
        pdfSum += light.pdf(d) * weight;
        radianceSum += luminance(light.radiance(d)) * weight;
      }
    }
    EXPECT_NEAR(pdfSum, 1.0, 1e-4) << "rotation " << rotation;
    // The light's integral takes each texel's bilinear mean in (u, t) times its solid angle;
    // within a texel the lookup's slope and sin theta correlate, which on 8 rows moves the
    // integral by about half a percent.
    EXPECT_NEAR(radianceSum, light.integratedLuminance(), 0.01 * light.integratedLuminance());
  }
}

TEST(Environment, ConstantMapIsSampledUniformlyOverTheSphere) {
  const EnvironmentLight light = EnvironmentLight::constant(vec3(0.5f, 1.0f, 2.0f));
  EXPECT_NEAR(light.integratedLuminance(), 4 * kPi * luminance(vec3(0.5f, 1.0f, 2.0f)), 1e-4);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  double meanY = 0;
  constexpr int kN = 20000;
  for (int i = 0; i < kN; ++i) {
    vec3 d;
    float pdf = 0;
    ASSERT_TRUE(light.sample({U(rng), U(rng)}, d, pdf));
    EXPECT_NEAR(pdf, 1 / (4 * kPi), 1e-6);
    expectNear(light.radiance(d), vec3(0.5f, 1.0f, 2.0f), kDirectionTolerance);
    meanY += d.y;
  }
  EXPECT_NEAR(meanY / kN, 0.0, 4 * std::sqrt(1.0 / 3.0 / kN));
}

TEST(Environment, RotationTurnsTheMapAboutUpByTheRightHandRule) {
  const auto map = structuredMap(16, 8);
  const EnvironmentLight still(map, 1.0f, 0.0f), turned(map, 1.0f, 90.0f);
  // Turned by +90 degrees, what was seen along +x is seen along -z.
  expectNear(turned.radiance({0, 0, -1}), still.radiance({1, 0, 0}), kDirectionTolerance);
  expectNear(turned.radiance({1, 0, 0}), still.radiance({0, 0, 1}), kDirectionTolerance);
  EXPECT_NEAR(turned.pdf({0, 0.3f, -0.95393920f}), still.pdf({0.95393920f, 0.3f, 0}), 1e-4f);
}

TEST(Environment, BlackMapIsNotALight) {
  const EnvironmentLight black = EnvironmentLight::constant(vec3(0.0f));
  EXPECT_TRUE(black.black());
  vec3 d;
  float pdf = 1;
  EXPECT_FALSE(black.sample({0.5f, 0.5f}, d, pdf));
  EXPECT_EQ(black.pdf({0, 1, 0}), 0.0f);
}

TEST(Environment, BuiltinMapIsGreyBrighterAboveAndDeterministic) {
  const auto a = builtinEnvironmentMap(), b = builtinEnvironmentMap();
  ASSERT_EQ(a->pixels.size(), b->pixels.size());
  EXPECT_EQ(0, std::memcmp(a->pixels.data(), b->pixels.data(), a->pixels.size() * sizeof(vec3)));
  const EnvironmentLight light(a, 1.0f, 0.0f);
  for (const vec3& c : a->pixels) EXPECT_TRUE(c.x == c.y && c.y == c.z) << "not grey";
  EXPECT_GT(luminance(light.radiance({0, 1, 0})), 2 * luminance(light.radiance({0, -1, 0})));
  EXPECT_GT(light.integratedLuminance(), 0.0);
}

TEST(Environment, TexelsBelowZeroOrNotFiniteReadAsZeroWithAWarning) {
  // Real maps have them: lossy compression (DWA) rings below zero next to a bright sun, by
  // thousands where the sun is tens of thousands.
  Image image(4, 2);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = vec3(float(i) + 1.0f);
  image.pixels[2] = vec3(5.0f, -3394.0f, 0.5f);
  image.pixels[5] = vec3(std::numeric_limits<float>::quiet_NaN(), 2.0f, -0.25f);
  image.pixels[6] = vec3(std::numeric_limits<float>::infinity());
  const std::string path = test::outputPath("environment/repaired.exr");
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  writeImage(path, image);
  std::string warning;
  const std::shared_ptr<const Image> map = readEnvironmentMap(path, &warning);
  for (size_t i : {0u, 1u, 3u, 4u, 7u}) EXPECT_EQ(map->pixels[i], image.pixels[i]) << i;
  EXPECT_EQ(map->pixels[2], vec3(5.0f, 0.0f, 0.5f));
  EXPECT_EQ(map->pixels[5], vec3(0.0f, 2.0f, 0.0f));
  EXPECT_EQ(map->pixels[6], vec3(0.0f));
  for (const char* part : {"repaired.exr", "2 negative and 4 non-finite texel values read as 0",
                           "pixel (2, 0)", "the lowest -3394"})
    EXPECT_NE(warning.find(part), std::string::npos) << "'" << part << "' not in: " << warning;
  // A clean map gives no warning, and its light is the map's.
  image.pixels[2] = image.pixels[5] = image.pixels[6] = vec3(1.0f);
  writeImage(path, image);
  warning = "stale";
  EXPECT_EQ(readEnvironmentMap(path, &warning)->pixels, image.pixels);
  EXPECT_EQ(warning, "stale") << "untouched without repairs";
}

}  // namespace
}  // namespace penumbra
