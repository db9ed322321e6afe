// Environment lighting against answers known in closed form: a white furnace under a constant
// map, a diffuse plane under a map that varies with elevation only, and a small, very bright sun
// whose low noise at 16 spp shows that it is importance-sampled. Plus what camera rays see:
// the map, the backdrop, or nothing when transparent.
#include "core/constants.h"
#include "methods/render.h"
#include "scene/lights.h"
#include "scene/materials.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"
#include "trace/integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>

namespace penumbra {
namespace {

using test::sceneFrom;

constexpr uint64_t kSeed = 5;

struct Stats {
  double mean, standardError, relativeSpread;  // spread: std of the pixels over their mean
};
Stats pixelStats(const RenderResult& r) {
  double sum = 0, sum2 = 0, var = 0;
  const double n = double(r.image.pixels.size());
  for (size_t i = 0; i < r.image.pixels.size(); ++i) {
    const double v = luminance(r.image.pixels[i]);
    sum += v;
    sum2 += v * v;
    var += luminance(r.varianceOfMean.pixels[i]);
  }
  const double mean = sum / n;
  return {mean, std::sqrt(var) / n, std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean};
}

void setEnvironment(Scene& scene, Image map) {
  scene.environment.map = std::make_shared<const Image>(std::move(map));
  scene.environment.file = "test map";
}

// The luminance of (albedo / pi) x integral over the upper hemisphere of L cos theta, by
// quadrature of the light's own radiance on a fine grid in (cos theta, phi).
double lambertianUpRadiance(const EnvironmentLight& light, double albedo) {
  constexpr int kN = 2000;
  double sum = 0;
  for (int i = 0; i < kN; ++i) {
    const double z = (i + 0.5) / kN;  // cos theta in (0, 1)
    const double s = std::sqrt(1 - z * z);
    for (int j = 0; j < kN; ++j) {
      const double phi = 2 * kPiD * (j + 0.5) / kN;
      sum += luminance(light.radiance(
                 vec3(float(s * std::cos(phi)), float(z), float(s * std::sin(phi))))) *
             z;
    }
  }
  return albedo / kPiD * sum * (2 * kPiD / (double(kN) * kN));
}

// A Lambertian plane (albedo 0.5) seen straight down through a narrow field of view, lit only
// by the environment, direct lighting only.
Scene planeScene() {
  return sceneFrom(R"({
    "render": {"width": 16, "height": 16, "max_depth": 1},
    "camera": {"eye": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 2},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.5}},
    "objects": [{"shape": "rectangle", "size": [100, 100], "material": "ground"}]})");
}

TEST(EnvironmentLighting, WhiteFurnaceUnderAConstantMap) {
  // A white (albedo 1) convex sphere under a constant map of radiance 1 reflects exactly 1.
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 8},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 4},
    "materials": {"ball": {"type": "diffuse", "albedo": 1}},
    "objects": [{"shape": "sphere", "radius": 1, "material": "ball"}]})");
  setEnvironment(scene, Image(8, 4, vec3(1.0f)));
  const Stats s =
      pixelStats(test::renderScene(std::move(scene), 128, SamplerKind::Independent, kSeed));
  EXPECT_NEAR(s.mean, 1.0, std::max(4 * s.standardError, 2e-3));
  EXPECT_LT(s.standardError, 0.01);
}

// A black pbr plane (albedo 0: only its specular layer reflects) of roughness 0.05 under a
// constant map of radiance 1, seen at `degrees` from its normal, direct light only: the mean
// radiance, which is the layer's directional albedo there.
Stats glossyBlackPlane(float degrees, float ior, float specular = 1.0f,
                       const std::function<void(Material&, Scene&)>& change = nullptr) {
  const float a = degrees * float(kPiD) / 180.0f;
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 1},
    "camera": {"eye": [0, )" +
                          std::to_string(5 * std::cos(a)) + ", " + std::to_string(5 * std::sin(a)) +
                          R"(], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 1},
    "materials": {"ground": {"type": "pbr", "albedo": 0, "roughness": 0.05, "ior": )" +
                          std::to_string(ior) + R"(}},
    "objects": [{"shape": "rectangle", "size": [100, 100], "material": "ground"}]})");
  scene.materials[0].specular = specular;
  if (change) change(scene.materials[0], scene);
  setEnvironment(scene, Image(8, 4, vec3(1.0f)));
  return pixelStats(test::renderScene(std::move(scene), 256, SamplerKind::Independent, kSeed));
}

TEST(EnvironmentLighting, GltfDielectricsReflectTheirFresnelShareOfTheSky) {
  // glTF's dielectric base has a specular layer: black plastic of ior 1.5 reflects
  // ((1.5 - 1) / (1.5 + 1))^2 = 4 % of a uniform sky straight on, and more towards grazing
  // (Schlick: 0.04 + 0.96 (1 - cos 75)^5 = 0.25 at 75 degrees, less the rough layer's
  // shadowing). With ior 1 the layer's f0 is 0 and straight on it reflects next to nothing
  // (Schlick's (1 - cos)^5 of the rare steep microfacets).
  const Stats normal = glossyBlackPlane(0.0f, 1.5f);
  EXPECT_NEAR(normal.mean, 0.04, std::max(4 * normal.standardError, 2e-3));
  const Stats grazing = glossyBlackPlane(75.0f, 1.5f);
  EXPECT_NEAR(grazing.mean, 0.25, 0.03);
  EXPECT_LT(glossyBlackPlane(0.0f, 1.0f).mean, 1e-6);
  // KHR_materials_specular scales the layer: half of it reflects 2 % straight on, none nothing.
  const Stats half = glossyBlackPlane(0.0f, 1.5f, 0.5f);
  EXPECT_NEAR(half.mean, 0.02, std::max(4 * half.standardError, 1e-3));
  EXPECT_EQ(glossyBlackPlane(75.0f, 1.5f, 0.0f).mean, 0.0);
}

TEST(EnvironmentLighting, AClearCoatReflectsItsFresnelShareOverTheMaterial) {
  // Black and without its own specular layer, the plane reflects only its coat: 4 % of a
  // uniform sky straight on at full weight, 2 % at half, more towards grazing; a rough coat
  // reflects as much.
  auto coated = [](float degrees, float weight, float roughness) {
    return glossyBlackPlane(degrees, 1.5f, 0.0f, [&](Material& m, Scene&) {
      m.clearcoat = weight;
      m.clearcoatRoughness = roughness;
    });
  };
  const Stats full = coated(0.0f, 1.0f, 0.05f);
  EXPECT_NEAR(full.mean, 0.04, std::max(4 * full.standardError, 2e-3));
  const Stats half = coated(0.0f, 0.5f, 0.05f);
  EXPECT_NEAR(half.mean, 0.02, std::max(4 * half.standardError, 1e-3));
  EXPECT_NEAR(coated(75.0f, 1.0f, 0.05f).mean, 0.25, 0.03);
  const Stats rough = coated(0.0f, 1.0f, 0.5f);
  EXPECT_NEAR(rough.mean, 0.04, std::max(4 * rough.standardError, 4e-3));
  // Over a white diffuse base under the same sky: the coat takes its share from the base and
  // gives it back as reflection, so nearly all the light still returns.
  const Stats white = glossyBlackPlane(0.0f, 1.5f, 0.0f, [](Material& m, Scene&) {
    m.albedo = vec3(1.0f);
    m.clearcoat = 1.0f;
    m.clearcoatRoughness = 0.1f;
  });
  EXPECT_GT(white.mean, 0.95 - 4 * white.standardError);
  EXPECT_LT(white.mean, 1.0 + 4 * white.standardError);
}

TEST(EnvironmentLighting, TexturesScaleTheSpecularLayerAndTheCoat) {
  // A uniform texture of 0.5 halves what its factor gives: the specular layer's weight or tint
  // (2 % of the sky straight on instead of 4 %), and the coat's weight.
  const auto halvedBy = [](int Material::*slot, float specular) {
    return glossyBlackPlane(0.0f, 1.5f, specular, [&](Material& m, Scene& scene) {
      scene.images.push_back(makeTextureImage(Image(1, 1, vec3(0.5f))));
      Texture t;
      t.kind = Texture::Kind::Image;
      t.imageIndex = int(scene.images.size()) - 1;
      scene.textures.push_back(t);
      m.*slot = int(scene.textures.size()) - 1;
      if (slot == &Material::clearcoatTexture) m.clearcoat = 1.0f;
    });
  };
  for (const auto& [slot, specular] : {std::pair{&Material::specularTexture, 1.0f},
                                       std::pair{&Material::specularColorTexture, 1.0f},
                                       std::pair{&Material::clearcoatTexture, 0.0f}}) {
    const Stats half = halvedBy(slot, specular);
    EXPECT_NEAR(half.mean, 0.02, std::max(4 * half.standardError, 1e-3));
  }
}

TEST(EnvironmentLighting, SheenReflectsItsDirectionalAlbedoOfTheSky) {
  // A black plane without a specular layer, under white sheen of roughness 0.5, reflects E(cos)
  // of a uniform sky of 1 (direct light only): little straight on, far more towards grazing. A
  // sheen colour texture of 0.5 halves it.
  const auto sheen = [](float degrees, bool textured) {
    return glossyBlackPlane(degrees, 1.5f, 0.0f, [&](Material& m, Scene& scene) {
      m.sheenColor = vec3(1.0f);
      m.sheenRoughness = 0.5f;
      if (!textured) return;
      scene.images.push_back(makeTextureImage(Image(1, 1, vec3(0.5f))));
      Texture t;
      t.kind = Texture::Kind::Image;
      t.imageIndex = int(scene.images.size()) - 1;
      scene.textures.push_back(t);
      m.sheenColorTexture = int(scene.textures.size()) - 1;
    });
  };
  for (float degrees : {0.0f, 60.0f, 80.0f}) {
    const double e = sheenAlbedo(std::cos(degrees * float(kPiD) / 180.0f), 0.25f);
    const Stats s = sheen(degrees, false);
    EXPECT_NEAR(s.mean, e, std::max(4 * s.standardError, 0.01 * e)) << degrees << " degrees";
    if (degrees == 60.0f) {
      const Stats half = sheen(degrees, true);
      EXPECT_NEAR(half.mean, 0.5 * e, std::max(4 * half.standardError, 0.005 * e));
    }
  }
  EXPECT_GT(sheenAlbedo(std::cos(80.0f * float(kPiD) / 180.0f), 0.25f),
            4 * sheenAlbedo(1.0f, 0.25f));
}

TEST(EnvironmentLighting, AnIridescentFilmReplacesItsShareOfTheFresnelReflectance) {
  // Black plastic (4 % straight on) under a film of index 1.3 thick enough that its two
  // interfaces add incoherently: R12 + (1 - R12)^2 R23 / (1 - R12 R23) = 2.194 % straight on.
  // The factor's texture (red 0.5) keeps half of the plastic's own; the thickness texture's
  // green (1) picks the maximum of the range.
  const auto film = [](bool textured) {
    return glossyBlackPlane(0.0f, 1.5f, 1.0f, [&](Material& m, Scene& scene) {
      m.iridescence = 1.0f;
      m.iridescenceIor = 1.3f;
      m.iridescenceThicknessMin = 0.0f;
      m.iridescenceThicknessMax = 50000.0f;
      if (!textured) return;
      scene.images.push_back(makeTextureImage(Image(1, 1, vec3(0.5f, 1.0f, 0.0f))));
      Texture t;
      t.kind = Texture::Kind::Image;
      t.imageIndex = int(scene.images.size()) - 1;
      scene.textures.push_back(t);
      m.iridescenceTexture = m.iridescenceThicknessTexture = int(scene.textures.size()) - 1;
    });
  };
  const Stats thick = film(false);
  EXPECT_NEAR(thick.mean, 0.02194, std::max(4 * thick.standardError, 2e-3));
  const Stats half = film(true);
  EXPECT_NEAR(half.mean, 0.5 * (0.04 + 0.02194), std::max(4 * half.standardError, 2e-3));
}

TEST(EnvironmentLighting, PbrBaseUnderAConstantMapLosesNoMoreThanItsFresnelShare) {
  // A white dielectric base (albedo 1) under a constant sky of 1: the diffuse part carries
  // 1 - F of the light and the layer F, so nearly all of it comes back (glTF's fresnel_mix is
  // not exactly energy-conserving: between 1 - F(0) and 1).
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 1},
    "camera": {"eye": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 1},
    "materials": {"ground": {"type": "pbr", "albedo": 1, "roughness": 0.4}},
    "objects": [{"shape": "rectangle", "size": [100, 100], "material": "ground"}]})");
  setEnvironment(scene, Image(8, 4, vec3(1.0f)));
  const Stats s =
      pixelStats(test::renderScene(std::move(scene), 256, SamplerKind::Independent, kSeed));
  EXPECT_GT(s.mean, 0.95 - 4 * s.standardError);
  EXPECT_LT(s.mean, 1.0 + 4 * s.standardError);
}

TEST(EnvironmentLighting, PlaneUnderAnElevationOnlyMapMatchesTheCosineIntegral) {
  // L = 1 + 3 cos^2 theta above the horizon, 0.2 below: L_plane = albedo / pi x 2 pi x
  // integral_0^1 (1 + 3 mu^2) mu dmu = 2 albedo (1/2 + 3/4) = 1.25 for albedo 0.5. Fine rows
  // make the map's own integral (which the quadrature gives) match that to 0.1%.
  constexpr int kW = 8, kH = 1024;
  Image map(kW, kH);
  for (int y = 0; y < kH; ++y) {
    const double mu = std::cos(kPiD * (y + 0.5) / kH);
    for (int x = 0; x < kW; ++x) map.at(x, y) = vec3(mu > 0 ? float(1 + 3 * mu * mu) : 0.2f);
  }
  Scene scene = planeScene();
  setEnvironment(scene, map);
  const EnvironmentLight light(scene.environment.map, 1.0f, 0.0f);
  const double expected = lambertianUpRadiance(light, 0.5);
  EXPECT_NEAR(expected, 1.25, 1.25e-3);
  const Stats s =
      pixelStats(test::renderScene(std::move(scene), 64, SamplerKind::LowDiscrepancy, kSeed));
  EXPECT_NEAR(s.mean, expected, 0.005 * expected);
}

TEST(EnvironmentLighting, SmallBrightSunIsImportanceSampled) {
  // A dim sky (0.05) and a sun of 2 x 2 texels (about 1.4 degrees across) at 60 degrees
  // elevation, giving about ten times the sky's irradiance. BSDF sampling alone finds a
  // solid angle of 2e-3 sr with probability under 1e-3 per sample: at 16 spp nearly every
  // pixel would miss the sun and read about a tenth of the answer, and the few that hit it
  // hundreds of times more: the pixels' spread over their mean would be about
  // 1 / sqrt(16 x 3.6e-4) = 13. Importance sampling sends 86% of the samples to the sun, whose
  // radiance over pdf varies within its texels (the bilinear lookup's edges): a sample's
  // relative deviation is about 0.7, so the pixels spread by about 0.7 / sqrt(16) = 0.18.
  constexpr int kW = 256, kH = 128;
  Image map(kW, kH, vec3(0.05f));
  const int sunRow = kH / 6;  // 30 degrees from the zenith
  for (int y = sunRow; y < sunRow + 2; ++y)
    for (int x = 100; x < 102; ++x) map.at(x, y) = vec3(3000.0f);
  Scene scene = planeScene();
  setEnvironment(scene, map);
  const EnvironmentLight light(scene.environment.map, 1.0f, 0.0f);
  const double expected = lambertianUpRadiance(light, 0.5);
  const double skyOnly = 0.5 * 0.05;
  ASSERT_GT(expected, 8 * skyOnly) << "the sun must dominate";
  for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::LowDiscrepancy}) {
    const Stats s = pixelStats(test::renderScene(scene, 16, sampler, kSeed));
    EXPECT_NEAR(s.mean, expected, std::max(4 * s.standardError, 0.005 * expected));
    EXPECT_LT(s.relativeSpread, 0.3) << "per-pixel noise at 16 spp";
  }
}

TEST(EnvironmentLighting, LowDiscrepancyLightPointsAreNoNoisierThanIndependentOnes) {
  // A studio-like map: a dim sky and four small bright panels at different places, each a few
  // texels across, so that the alias tables send a light point to a panel's texel or away from
  // it by the digits below a column. A low-discrepancy light point whose fine digits were the
  // same in every sample of a pixel (a digital shift) took the same branch of those tests in
  // all of them: its pixels spread further than independent ones at 64 spp (0.10 against 0.09).
  // Owen scrambling (Scrambling::Owen) gives each sample its own fine digits, and the points'
  // stratification then shows (0.06).
  constexpr int kW = 512, kH = 256;
  Image map(kW, kH, vec3(0.05f));
  const int panels[4][2] = {{60, 30}, {190, 52}, {300, 40}, {430, 70}};  // column, row
  for (const auto& panel : panels)
    for (int y = panel[1]; y < panel[1] + 3; ++y)
      for (int x = panel[0]; x < panel[0] + 5; ++x) map.at(x, y) = vec3(400.0f);
  Scene scene = planeScene();
  setEnvironment(scene, map);
  const EnvironmentLight light(scene.environment.map, 1.0f, 0.0f);
  const double expected = lambertianUpRadiance(light, 0.5);
  double spread[2] = {0, 0};
  for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::LowDiscrepancy}) {
    // Every pixel of the plane has the same expected value: their spread is the noise.
    const Stats s = pixelStats(test::renderScene(scene, 64, sampler, kSeed));
    EXPECT_NEAR(s.mean, expected, std::max(4 * s.standardError, 0.005 * expected));
    spread[sampler == SamplerKind::LowDiscrepancy] = s.relativeSpread;
  }
  EXPECT_LT(spread[1], 0.8 * spread[0])
      << "LD " << spread[1] << " against independent " << spread[0];
}

TEST(EnvironmentLighting, CameraRaysSeeTheMapTheBackdropOrNothing) {
  // An empty view (the camera looks away from the only object) sees the environment.
  Scene scene = sceneFrom(R"({
    "render": {"width": 4, "height": 4, "max_depth": 1},
    "camera": {"eye": [0, 0, 0], "look_at": [1, 0, 0], "fov": 1},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "objects": [{"shape": "sphere", "radius": 0.1, "material": "m",
                 "transform": {"translate": [0, 0, 5]}}]})");
  Image map(4, 2, vec3(0.0f));
  map.at(2, 0) = map.at(2, 1) = vec3(2.0f);  // the texels around +x
  setEnvironment(scene, map);
  const EnvironmentLight light(scene.environment.map, 1.0f, 0.0f);
  const double seen = luminance(light.radiance({1, 0, 0}));
  EXPECT_NEAR(pixelStats(test::renderScene(scene, 4, SamplerKind::LowDiscrepancy, kSeed)).mean,
              seen, 0.01 * seen);
  scene.background = vec3(0.25f);  // with a map, a background is only the backdrop
  EXPECT_NEAR(pixelStats(test::renderScene(scene, 4, SamplerKind::LowDiscrepancy, kSeed)).mean,
              0.25, 1e-5);
  scene.transparent = true;
  EXPECT_EQ(pixelStats(test::renderScene(scene, 4, SamplerKind::LowDiscrepancy, kSeed)).mean, 0.0);
}

TEST(EnvironmentLighting, BackgroundAloneLightsTheSceneByNextEventEstimation) {
  // A background without a map is a constant environment: a light the sampler chooses.
  Scene scene = planeScene();
  scene.background = vec3(1.0f);
  const auto prepared = prepareScene(scene);
  ASSERT_TRUE(prepared->lights.environment != nullptr);
  EXPECT_FLOAT_EQ(prepared->lights.environmentProbability, 1.0f);
  // L = albedo x background for a plane under a uniform sky.
  const Stats s =
      pixelStats(test::renderScene(std::move(scene), 16, SamplerKind::LowDiscrepancy, kSeed));
  EXPECT_NEAR(s.mean, 0.5, 0.01);
}

}  // namespace
}  // namespace penumbra
