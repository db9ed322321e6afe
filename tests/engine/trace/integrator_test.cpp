// Integrator tests against values known in closed form: two white-furnace scenes and a
// diffuse plane under a disk light; plus NaN handling.
#include "trace/integrator.h"
#include "methods/render.h"
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

Scene sceneFrom(const std::string& json) { return parseSceneJson(json, "test.json", "."); }

// Mean and standard error of the per-pixel values (luminance) over the whole image.
struct ImageMean {
  double mean, standardError;
};
ImageMean imageMean(const RenderResult& r) {
  double sum = 0, var = 0;
  const double n = double(r.image.pixels.size());
  for (size_t i = 0; i < r.image.pixels.size(); ++i) {
    sum += luminance(r.image.pixels[i]);
    var += luminance(r.varianceOfMean.pixels[i]);
  }
  return {sum / n, std::sqrt(var) / n};
}

RenderResult renderScene(Scene scene, int spp, SamplerKind sampler = SamplerKind::Independent) {
  auto prepared = prepareScene(std::move(scene));
  RenderOptions options;
  options.spp = spp;
  options.sampler = sampler;
  options.seed = 11;
  return renderImage(*prepared, options);
}

TEST(Integrator, ClosedFurnaceConvergesToEmissionOverOneMinusAlbedo) {
  // Inside a closed emitter of radiance Le and albedo rho, L = Le + rho L = Le / (1 - rho).
  Scene scene = sceneFrom(R"({
    "render": {"width": 16, "height": 16, "max_depth": 1000},
    "camera": {"eye": [0, 0, 0], "look_at": [0, 0, -1], "fov": 90},
    "materials": {"wall": {"type": "diffuse", "albedo": 0.5, "emission": 0.5}},
    "objects": [{"shape": "sphere", "radius": 1, "material": "wall", "flip_normals": true,
                 "segments": 32, "rings": 16}]})");
  const RenderResult r = renderScene(std::move(scene), 64);
  const ImageMean m = imageMean(r);
  EXPECT_NEAR(m.mean, 1.0, std::max(4 * m.standardError, 1e-3))
      << "standard error " << m.standardError;
  EXPECT_LT(m.standardError, 0.01);
  EXPECT_EQ(r.nonFiniteSamples, 0u);
}

// Mean of a unit sphere of `material` under a uniform white sky (fov 16 shows all of it).
ImageMean sphereUnderWhiteSky(const std::string& material, int spp, int fovDegrees) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 64},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 4},
    "background": [1, 1, 1],
    "materials": {"ball": )" +
                          material + R"(},
    "objects": [{"shape": "sphere", "radius": 1, "material": "ball"}]})");
  return imageMean(renderScene(std::move(scene), spp));
}

TEST(Integrator, DiffuseSphereUnderUniformSkyReflectsItsAlbedo) {
  const ImageMean m = sphereUnderWhiteSky(R"({"type": "diffuse", "albedo": 0.8})", 256, 4);
  EXPECT_NEAR(m.mean, 0.8, std::max(4 * m.standardError, 2e-3));
}

TEST(Integrator, GlassSphereUnderUniformSkyIsInvisible) {
  // Smooth dielectric conserves energy, and the 1/eta^2 radiance scaling on entering is
  // undone on leaving: in a uniform environment the sphere has the sky's radiance.
  const ImageMean m = sphereUnderWhiteSky(R"({"type": "dielectric", "ior": 1.5})", 64, 16);
  EXPECT_NEAR(m.mean, 1.0, std::max(4 * m.standardError, 5e-3));
}

TEST(Integrator, PlaneUnderDiskLightMatchesTheFormFactor) {
  // A Lambertian plane point below a disk of radius R at height h: L = rho Le R^2 / (h^2 + R^2).
  const double rho = 0.5, le = 4.0, radius = 0.5, h = 2.0;
  for (int depth : {1, 4}) {
    Scene scene = sceneFrom(R"({
      "render": {"width": 8, "height": 8, "max_depth": 1},
      "camera": {"eye": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 1},
      "materials": {"ground": {"type": "diffuse", "albedo": 0.5},
                    "lamp": {"type": "emissive", "radiance": 4}},
      "objects": [
        {"shape": "rectangle", "size": [100, 100], "material": "ground"},
        {"shape": "disk", "radius": 0.5, "segments": 256, "material": "lamp",
         "transform": {"translate": [0, 2, 0], "rotate": [180, 1, 0, 0]}}]})");
    scene.settings.maxDepth = depth;
    const RenderResult r = renderScene(std::move(scene), 256, SamplerKind::LowDiscrepancy);
    const double expected = rho * le * radius * radius / (h * h + radius * radius);
    const ImageMean m = imageMean(r);
    EXPECT_NEAR(m.mean, expected, 0.01 * expected) << "max depth " << depth;
  }
}

TEST(Integrator, EmittersShineOnlyFromTheirCounterClockwiseSide) {
  // The disk faces up (+y); a camera below it sees its black back side.
  const char* json = R"({
    "render": {"width": 4, "height": 4, "max_depth": 0},
    "camera": {"eye": [0, EYE, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 5},
    "materials": {"lamp": {"type": "emissive", "radiance": 3}},
    "objects": [{"shape": "disk", "radius": 1, "material": "lamp"}]})";
  std::string above = json, below = json;
  above.replace(above.find("EYE"), 3, "2");
  below.replace(below.find("EYE"), 3, "-2");
  EXPECT_NEAR(imageMean(renderScene(sceneFrom(above), 4)).mean, 3.0, 1e-4);
  EXPECT_NEAR(imageMean(renderScene(sceneFrom(below), 4)).mean, 0.0, 1e-6);
}

TEST(Integrator, NonFiniteSamplesAreCountedAndKeptOutOfTheImage) {
  // A texture holding NaN (as a float EXR texture can) poisons every path that sees it.
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 3},
    "camera": {"eye": [0, 1, 3], "look_at": [0, 0, 0]},
    "background": 1,
    "materials": {"ground": {"type": "diffuse", "albedo": 0.5}},
    "objects": [{"shape": "rectangle", "size": [1, 1], "material": "ground"}]})");
  Image bad(2, 2, vec3(0.5f));
  bad.at(1, 1) = vec3(std::nanf(""));
  scene.images.push_back(bad);
  Texture texture;
  texture.kind = Texture::Kind::Image;
  texture.imageIndex = 0;
  scene.textures.push_back(texture);
  scene.materials[0].albedoTexture = 0;
  const RenderResult r = renderScene(std::move(scene), 16);
  EXPECT_GT(r.nonFiniteSamples, 0u);
  EXPECT_LT(r.nonFiniteSamples, r.samples) << "the background around the square stays valid";
  for (const vec3& p : r.image.pixels)
    EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

}  // namespace
}  // namespace penumbra
