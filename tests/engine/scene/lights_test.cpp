// Light charts (scene/lights.h): where a light sample landed, in coordinates continuous over
// its emitting object, and which object it is.
#include "scene/lights.h"
#include "core/constants.h"
#include "tests/test_paths.h"
#include "trace/integrator.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using test::sceneFrom;

// One emitting object (the JSON of its shape, material "lamp") above a floor, a point light
// and a blue sky: every kind of light in one scene.
std::unique_ptr<PreparedScene> sceneWith(const std::string& lampShape) {
  return prepareScene(sceneFrom(R"({
    "render": {"width": 8, "height": 8},
    "camera": {"eye": [0, 3, 6], "look_at": [0, 0, 0], "fov": 40},
    "background": [0.2, 0.3, 0.6],
    "materials": {"lamp": {"type": "emissive", "radiance": 50},
                  "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "lights": [{"type": "point", "position": [1, 3, 2], "intensity": 20}],
    "objects": [{"shape": "rectangle", "size": [10, 10], "material": "floor"},
                )" + lampShape + R"(]})"));
}

// Light samples from `reference` on the lamp (mesh 1): 1024 choices spread over its part of
// the light choice's cdf, each with its own light point.
std::vector<LightSample> lampSamples(const PreparedScene& prepared, vec3 reference) {
  const LightSampler& lights = prepared.lights;
  float lo = 1.0f, hi = 0.0f;
  for (size_t e = 0; e < lights.emitters.size(); ++e) {
    if (lights.emitters[e].punctual != -1 || lights.emitters[e].meshId != 1) continue;
    lo = std::min(lo, e == 0 ? 0.0f : lights.cdf[e - 1]);
    hi = std::max(hi, lights.cdf[e]);
  }
  std::vector<LightSample> samples;
  for (int i = 0; i < 1024; ++i) {
    const float choose = lo + (hi - lo) * (float(i) + 0.5f) / 1024.0f;
    const glm::vec2 u(std::fmod(0.618034f * float(i), 1.0f),
                      std::fmod(0.7548777f * float(i), 1.0f));
    LightSample ls;
    if (sampleLight(prepared.scene, lights, reference, 0.0f, choose, u, ls)) samples.push_back(ls);
  }
  return samples;
}

TEST(LightChart, ARectanglesChartIsItsOwnStAcrossTheDiagonal) {
  // A 2 x 1 rectangle 3 above the floor, facing down; no transform but the lift and the flip.
  const auto prepared = sceneWith(R"({"shape": "rectangle", "size": [2, 1], "material": "lamp",
      "transform": {"rotate": [180, 1, 0, 0], "translate": [0, 3, 0]}})");
  const std::vector<LightSample> samples = lampSamples(*prepared, vec3(0.1f, 0.0f, 0.2f));
  ASSERT_GT(samples.size(), 1000u) << "the rectangle faces the reference";
  const EmitterChart& chart = prepared->lights.charts[1];
  EXPECT_TRUE(chart.flat);
  glm::vec2 lo(1.0f), hi(0.0f);
  for (const LightSample& ls : samples) {
    EXPECT_EQ(ls.object, 1);
    const glm::vec2 c = lightChart(prepared->lights, ls);
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
    // The chart is the point's (x, z) on the rectangle, each axis scaled to [0, 1] (in some
    // order and sense): affine in the point, so continuous across the diagonal where the
    // triangles' own warped coordinates jump.
    const float s = (ls.point.x + 1.0f) / 2.0f, t = ls.point.z + 0.5f;
    EXPECT_NEAR(std::min(std::abs(c.x - s), std::abs(c.x - (1 - s))), 0.0f, 1e-4f);
    EXPECT_NEAR(std::min(std::abs(c.y - t), std::abs(c.y - (1 - t))), 0.0f, 1e-4f);
  }
  EXPECT_LT(lo.x, 0.05f);
  EXPECT_LT(lo.y, 0.05f);
  EXPECT_GT(hi.x, 0.95f);
  EXPECT_GT(hi.y, 0.95f);
  // Two points close together on either side of the diagonal are close in the chart.
  const glm::vec2 a = emitterChartAt(chart, vec3(0.01f, 3.0f, 0.0f));
  const glm::vec2 b = emitterChartAt(chart, vec3(-0.01f, 3.0f, 0.005f));
  EXPECT_LT(glm::length(a - b), 0.03f);
}

TEST(LightChart, ASpheresChartIsTheDirectionFromItsCentre) {
  const auto prepared = sceneWith(R"({"shape": "sphere", "radius": 0.5, "material": "lamp",
      "transform": {"translate": [0, 3, 0]}})");
  const EmitterChart& chart = prepared->lights.charts[1];
  EXPECT_FALSE(chart.flat);
  EXPECT_NEAR(glm::length(chart.origin - vec3(0, 3, 0)), 0.0f, 1e-3f);
  const std::vector<LightSample> samples = lampSamples(*prepared, vec3(0.3f, 0.0f, -0.2f));
  ASSERT_GT(samples.size(), 300u) << "the half facing the reference";
  for (const LightSample& ls : samples) {
    EXPECT_EQ(ls.object, 1);
    const glm::vec2 c = lightChart(prepared->lights, ls);
    const vec3 d = glm::normalize(ls.point - vec3(0, 3, 0));
    EXPECT_NEAR(c.y, 0.5f * (1.0f - d.y), 2e-3f);
    // Seen from below, the samples lie on the lower half: (1 - cos) / 2 above one half.
    EXPECT_GT(c.y, 0.45f);
  }
  // Continuous: nearby points of the sphere, nearby coordinates (away from the azimuth seam).
  const glm::vec2 a =
      emitterChartAt(chart, vec3(0, 3, 0) + 0.5f * glm::normalize(vec3(0.3f, -1, 0.2f)));
  const glm::vec2 b =
      emitterChartAt(chart, vec3(0, 3, 0) + 0.5f * glm::normalize(vec3(0.31f, -1, 0.2f)));
  EXPECT_LT(glm::length(a - b), 0.01f);
}

TEST(LightChart, TheEnvironmentAndPunctualLightsHaveTheirOwnObjects) {
  const auto prepared = sceneWith(R"({"shape": "rectangle", "size": [1, 1], "material": "lamp",
      "transform": {"rotate": [180, 1, 0, 0], "translate": [0, 3, 0]}})");
  const LightSampler& lights = prepared->lights;
  ASSERT_EQ(lights.meshCount, 2u);
  ASSERT_EQ(lights.punctualCount, 1u);
  bool sawPoint = false, sawSky = false;
  for (int i = 0; i < 256; ++i) {
    LightSample ls;
    const float choose = (float(i) + 0.5f) / 256.0f;
    const glm::vec2 u(std::fmod(0.618034f * float(i), 1.0f),
                      std::fmod(0.7548777f * float(i), 1.0f));
    if (!sampleLight(prepared->scene, lights, vec3(0.2f, 0.0f, 0.1f), 0.0f, choose, u, ls))
      continue;
    const glm::vec2 c = lightChart(lights, ls);
    if (ls.object == 2) {  // the point light: one point, the middle of its chart
      sawPoint = true;
      EXPECT_EQ(c, glm::vec2(0.5f));
    } else if (ls.object == 3) {  // the sky: the direction's chart
      sawSky = true;
      EXPECT_EQ(c, directionChart(ls.wi));
      EXPECT_NEAR(c.y, 0.5f * (1.0f - ls.wi.y), 1e-6f);
    } else {
      EXPECT_EQ(ls.object, 1);
    }
  }
  EXPECT_TRUE(sawPoint);
  EXPECT_TRUE(sawSky);
  // The direction chart's azimuth is the environment map's u.
  for (const vec3 d : {vec3(1, 0, 0), vec3(0, 0, 1), vec3(0.3f, 0.5f, -0.8f)}) {
    const vec3 n = glm::normalize(d);
    EXPECT_NEAR(directionChart(n).x, directionToEquirect(n).x, 1e-6f);
  }
}

TEST(LightChart, PathsRecordTheirFirstVertexsLightSampleAsAFeature) {
  const auto prepared = sceneWith(R"({"shape": "rectangle", "size": [2, 1], "material": "lamp",
      "transform": {"rotate": [180, 1, 0, 0], "translate": [0, 3, 0]}})");
  PixelSampler sampler(SamplerKind::LowDiscrepancy, 3, 64);
  PathCounters counters;
  int lamp = 0, other = 0;
  bool directSeen = false;
  for (int i = 0; i < 64; ++i) {
    sampler.startSample(4, 5, uint32_t(i));
    const CameraSample cs = sampler.cameraSample(false, false);
    PixelSampler again = sampler;
    PathFeatures features;
    const vec3 withFeatures = traceRadiance(*prepared, cs, sampler, counters, &features);
    // Recording consumes no random numbers and leaves the radiance as it is.
    const vec3 without = traceRadiance(*prepared, cs, again, counters);
    EXPECT_EQ(withFeatures, without);
    ASSERT_GE(features.lightObject, 1) << "the floor's vertex samples some light";
    EXPECT_LE(features.lightObject, 3);
    EXPECT_GE(features.lightChart.x, 0.0f);
    EXPECT_LE(features.lightChart.x, 1.0f);
    EXPECT_GE(features.lightChart.y, 0.0f);
    EXPECT_LE(features.lightChart.y, 1.0f);
    (features.lightObject == 1 ? lamp : other)++;
    // The light sample's part of the radiance: some of it, never more (all terms are >= 0).
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(features.directLight[c], 0.0f);
      EXPECT_LE(features.directLight[c], withFeatures[c] * (1 + 1e-5f));
    }
    directSeen = directSeen || features.directLight.x > 0;
  }
  EXPECT_GT(lamp, 0);
  EXPECT_TRUE(directSeen) << "the floor is lit by the lamp and the point light";
  // A path that escapes at once records no light: the camera turned to the sky.
  Camera camera = prepared->scene.camera;
  camera.lookAt = camera.eye + vec3(0, 1, 0);
  camera.up = vec3(0, 0, 1);
  const auto sky = prepareView(*prepared, camera);
  PathFeatures escaped;
  sampler.startSample(4, 4, 0);
  traceRadiance(*sky, sampler.cameraSample(false, false), sampler, counters, &escaped);
  EXPECT_EQ(escaped.lightObject, -1);
  EXPECT_EQ(escaped.lightChart, glm::vec2(0.5f));
}

}  // namespace
}  // namespace penumbra
