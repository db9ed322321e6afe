// Integrator tests against values known in closed form: two white-furnace scenes and a
// diffuse plane under a disk light; plus NaN handling.
#include "trace/integrator.h"
#include "core/constants.h"
#include "methods/render.h"
#include "scene/lights.h"
#include "scene/scene_loader.h"
#include "scene/tangents.h"
#include "scene/textures.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {
namespace {

using test::renderScene;
using test::sceneFrom;

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

// A unit sphere of `material` at the origin, seen from distance 5 under a uniform white
// sky with a vertical field of view of `fovDegrees`: the whole sphere needs
// 2 asin(1/5) = 23.07 degrees, fov 4 shows only its middle (incidence below ~15 degrees).
RenderResult sphereUnderWhiteSky(const std::string& material, int spp, double fovDegrees,
                                 int size = 8, int maxDepth = 64) {
  Scene scene = sceneFrom(R"({
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
    "background": [1, 1, 1],
    "materials": {"ball": )" +
                          material + R"(},
    "objects": [{"shape": "sphere", "radius": 1, "material": "ball"}]})");
  scene.settings.width = scene.settings.height = size;
  scene.settings.maxDepth = maxDepth;
  scene.camera.vfovDegrees = float(fovDegrees);
  return renderScene(std::move(scene), spp);
}

TEST(Integrator, DiffuseSphereUnderUniformSkyReflectsItsAlbedo) {
  // fov 4: every pixel sees the sphere, so the image mean is the sphere's radiance.
  const ImageMean m =
      imageMean(sphereUnderWhiteSky(R"({"type": "diffuse", "albedo": 0.8})", 256, 4));
  EXPECT_NEAR(m.mean, 0.8, std::max(4 * m.standardError, 2e-3));
}

TEST(Integrator, AbsorbingGlassKeepsItsAttenuationColourPerAttenuationDistance) {
  // Index 1 bends and reflects nothing: a ray through the middle of a unit sphere travels 2
  // inside and keeps 0.5^(2 / 1) = 25 % of the white sky behind (the view, 0.5 degrees wide,
  // sees chords of 1.9995 and more). As glass and as glTF's transmission alike; a thin wall
  // (no distance) absorbs nothing.
  const std::string volume = R"("ior": 1, "attenuation_color": 0.5, "attenuation_distance": 1)";
  for (const std::string& material :
       {R"({"type": "dielectric", )" + volume + "}",
        R"({"type": "pbr", "albedo": 1, "transmission": 1, )" + volume + "}"}) {
    const ImageMean m = imageMean(sphereUnderWhiteSky(material, 64, 0.5));
    EXPECT_NEAR(m.mean, 0.25, 1e-3) << material;
  }
  const ImageMean clear = imageMean(sphereUnderWhiteSky(
      R"({"type": "dielectric", "ior": 1, "attenuation_color": 0.5})", 16, 0.5));
  EXPECT_NEAR(clear.mean, 1.0, 1e-4);
}

TEST(Integrator, GlassSphereUnderUniformSkyIsInvisible) {
  // A smooth dielectric only redirects light: each reflection has weight 1, and the
  // 1/eta^2 radiance scaling on entering is undone by the eta^2 on leaving. So in a
  // uniform environment every path that escapes carries exactly the sky's radiance, and
  // every pixel, near-normal, grazing and silhouette alike, has expected value 1. The fov
  // (26 > 23.07 degrees) shows the whole sphere and a margin of sky, so the grazing
  // incidences, where Fresnel reflectance goes to 1 and paths bounce many times inside,
  // are in view.
  //
  // Depth truncation: a ray entering at incidence theta with reflectance F = F(theta)
  // meets the inside of a sphere always at its refraction angle (below the critical
  // angle), so it leaves at each inner hit with probability 1 - F; it is still inside
  // after vertex D - 1, and is cut off by max depth D, with probability (1 - F) F^(D-1)
  // <= (1/D)(1 - 1/D)^(D-1) < 1/(e (D-1)). With D = 1024 that darkens any pixel by at
  // most 3.6e-4, which the tolerances below allow for explicitly (one-sided). Russian
  // roulette keeps the paths short anyway: it is unbiased, so it only adds variance.
  constexpr int kSize = 24, kSpp = 512, kMaxDepth = 1024;
  constexpr double kFov = 26;
  const double truncation = (1.0 / kMaxDepth) * std::pow(1.0 - 1.0 / kMaxDepth, kMaxDepth - 1);
  const RenderResult r =
      sphereUnderWhiteSky(R"({"type": "dielectric", "ior": 1.5})", kSpp, kFov, kSize, kMaxDepth);
  EXPECT_EQ(r.nonFiniteSamples, 0u);

  // Classify pixels by the distance d of their rays from the sphere's centre (the eye is
  // 5 away, so a ray at angle a off the axis passes at d = 5 sin a; inside the sphere d is
  // the sine of the incidence angle). The mesh is inscribed in the unit sphere, so a pixel
  // whose whole footprint has d > 1 sees only sky.
  const double tanHalf = std::tan(0.5 * kFov * M_PI / 180.0);
  const auto distance = [&](double rasterX, double rasterY) {
    const double sx = (2.0 * rasterX / kSize - 1.0) * tanHalf;
    const double sy = (2.0 * rasterY / kSize - 1.0) * tanHalf;
    return 5.0 * std::sin(std::atan(std::hypot(sx, sy)));
  };
  struct Band {
    Band(const char* name, double lo, double hi) : name(name), lo(lo), hi(hi) {}
    const char* name;
    double lo, hi;  // d of the pixel centre; the silhouette band instead holds every
                    // pixel whose footprint straddles d = 1
    double sum = 0, varianceSum = 0;
    std::vector<std::pair<int, int>> pixels;
  };
  std::vector<Band> bands = {{"incidence below 30 deg", 0.0, 0.5},
                             {"30 to 53 deg", 0.5, 0.8},
                             {"53 to 64 deg", 0.8, 0.9},
                             {"above 64 deg, up to the silhouette", 0.9, 1.0},
                             {"silhouette", 1.0, 1.0}};
  Band& silhouette = bands.back();
  int skyPixels = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      // Nearest and farthest points of the pixel's footprint from the image centre.
      const double cx = std::clamp(kSize / 2.0, double(x), x + 1.0);
      const double cy = std::clamp(kSize / 2.0, double(y), y + 1.0);
      const double fx = std::abs(x - kSize / 2.0) > std::abs(x + 1 - kSize / 2.0) ? x : x + 1;
      const double fy = std::abs(y - kSize / 2.0) > std::abs(y + 1 - kSize / 2.0) ? y : y + 1;
      const double dMin = distance(cx, cy), dMax = distance(fx, fy);
      const double value = luminance(r.image.at(x, y));
      if (dMin > 1.0) {
        ++skyPixels;
        EXPECT_NEAR(value, 1.0, 1e-6) << "sky pixel " << x << "," << y;
        continue;
      }
      Band* band = &silhouette;
      if (dMax < 1.0) {
        const double d = distance(x + 0.5, y + 0.5);
        for (Band& b : bands)
          if (d >= b.lo && d < b.hi) band = &b;
      }
      band->sum += value;
      band->varianceSum += luminance(r.varianceOfMean.at(x, y));
      band->pixels.push_back({x, y});
    }
  }
  EXPECT_GT(skyPixels, 0) << "the fov must show the sky all around the sphere";

  for (const Band& band : bands) {
    // Every band is in view (fov 4 would show the first alone) with enough samples for
    // the central limit theorem on the band mean: over 16000 paths, among them dozens to
    // hundreds of the rare ones (Russian roulette kills, long internal chains) that carry
    // the variance.
    ASSERT_GE(band.pixels.size(), 16u) << band.name;
    const double n = double(band.pixels.size());
    const double mean = band.sum / n, standardError = std::sqrt(band.varianceSum) / n;
    // 5 standard errors: a false alarm below 1e-6 for each of the five bands.
    EXPECT_GT(mean, 1.0 - truncation - 5 * standardError) << band.name;
    EXPECT_LT(mean, 1.0 + 5 * standardError) << band.name;

    // Each pixel on its own, with the band's pooled variance (a pixel's own sample
    // variance is unreliable where the rare events are few). Frequent small deviations
    // (a roulette survival: x 1/0.95) make a Gaussian part, allowed 6 sigma. But some
    // deviations are rare and large: a roulette kill (-1) or a chain that survived the
    // roulette inside the sphere and left with weight ~2.5 (+1.5) move a pixel by up to
    // ~1.5/spp each, and near the middle of the sphere a pixel sees only a few of them:
    // their number is Poisson with a small mean m, whose tail beyond m + 6 sqrt(m) is
    // far heavier than a Gaussian's. Allowing 6 more such events on top of the 6 sigma
    // keeps P(Poisson(m) >= m + 6 sqrt(m) + 6) at most about 1e-9 whatever m, a false
    // alarm below 1e-6 over the few hundred pixels.
    const double sigma = std::sqrt(band.varianceSum / n);  // of one pixel's mean
    const double tolerance = 6 * sigma + 6 * 1.5 / kSpp;
    for (auto [x, y] : band.pixels) {
      const double value = luminance(r.image.at(x, y));
      EXPECT_GT(value, 1.0 - truncation - tolerance) << band.name << ": pixel " << x << "," << y;
      EXPECT_LT(value, 1.0 + tolerance) << band.name << ": pixel " << x << "," << y;
    }
  }
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

// A Lambertian plane (albedo 0.5) seen straight down through a 0.5-degree field of view, lit by
// `light` alone (a JSON light) with direct lighting only.
double planeUnderPunctualLight(const std::string& light) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 4, "height": 4, "max_depth": 1},
    "camera": {"eye": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 0.5},
    "materials": {"ground": {"type": "diffuse", "albedo": 0.5}},
    "objects": [{"shape": "rectangle", "size": [100, 100], "material": "ground"}],
    "lights": [)" + light +
                          "]}");
  return imageMean(renderScene(std::move(scene), 16)).mean;
}

TEST(Integrator, PunctualLightsFollowTheInverseSquareLawAndTheirCones) {
  // L = rho / pi * E, with E = I / h^2 below a point light, E cos(theta) for a directional one.
  const double rho = 0.5, pi = 3.14159265358979;
  EXPECT_NEAR(
      planeUnderPunctualLight(R"({"type": "point", "position": [0, 2, 0], "intensity": 8})"),
      rho / pi * 8.0 / 4.0, 1e-3 * rho / pi * 2.0);
  EXPECT_NEAR(
      planeUnderPunctualLight(
          R"({"type": "point", "position": [0, 2, 0], "intensity": 2, "color": [1, 2, 3]})"),
      rho / pi * 2.0 / 4.0 * luminance(vec3(1, 2, 3)), 2e-3);
  EXPECT_NEAR(planeUnderPunctualLight(
                  R"({"type": "directional", "direction": [0, -1, -1], "intensity": 3})"),
              rho / pi * 3.0 * std::sqrt(0.5), 1e-3);
  // A spot aimed at the plane lights it fully inside its inner cone, and not at all when turned
  // away by more than its outer angle; half way between, glTF's squared ramp gives 1/4.
  const std::string spot =
      R"({"type": "spot", "position": [0, 2, 0], "intensity": 8, "inner_angle": 10, "outer_angle": 30, "direction": )";
  EXPECT_NEAR(planeUnderPunctualLight(spot + "[0, -1, 0]}"), rho / pi * 2.0, 1e-3);
  const double turned40 = std::tan(40.0 * pi / 180.0);
  EXPECT_EQ(planeUnderPunctualLight(spot + "[" + std::to_string(turned40) + ", -1, 0]}"), 0.0);
  const double cosHalf = (std::cos(10 * pi / 180) + std::cos(30 * pi / 180)) / 2;
  const double turnedHalf = std::tan(std::acos(cosHalf));
  EXPECT_NEAR(planeUnderPunctualLight(spot + "[" + std::to_string(turnedHalf) + ", -1, 0]}"),
              rho / pi * 2.0 * 0.25, 2e-3);
  // A point light behind the plane does not shine through it.
  EXPECT_EQ(planeUnderPunctualLight(R"({"type": "point", "position": [0, -2, 0], "intensity": 8})"),
            0.0);
}

// glTF's range windows the inverse square by clamp(1 - (d / range)^4, 0, 1): at 2 from the light
// a range of 4 keeps 15/16 of it, a range of 2^(5/4) half, and a range of 2 or less nothing.
TEST(Integrator, APunctualLightsRangeWindowsItsInverseSquare) {
  const double full = 0.5 / 3.14159265358979 * 8.0 / 4.0;
  const auto lit = [](const std::string& range) {
    return planeUnderPunctualLight(R"({"type": "point", "position": [0, 2, 0], "intensity": 8,
                                       "range": )" +
                                   range + "}");
  };
  EXPECT_NEAR(lit("0"), full, 1e-3 * full);  // none
  EXPECT_NEAR(lit("4"), full * 15.0 / 16.0, 1e-3 * full);
  EXPECT_NEAR(lit(std::to_string(std::pow(2.0, 1.25))), full * 0.5, 1e-3 * full);
  EXPECT_EQ(lit("2"), 0.0);
  EXPECT_EQ(lit("1.5"), 0.0);
  EXPECT_NEAR(rangeWindow(4.0f, 4.0f), 15.0f / 16.0f, 1e-7f);
  // A spot's range too.
  EXPECT_NEAR(planeUnderPunctualLight(R"({"type": "spot", "position": [0, 2, 0], "intensity": 8,
                                          "outer_angle": 30, "range": 4})"),
              full * 15.0 / 16.0, 1e-3 * full);
}

// A plane of `material` seen at 45 degrees under a disk light straight above the point seen,
// direct light only: a diffuse plane reflects the light, a smooth metal mirrors the dark sky.
ImageMean planeUnderDisk(const std::string& material,
                         const std::function<void(Scene&)>& change = nullptr) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8, "max_depth": 1},
    "camera": {"eye": [0, 1, 1], "look_at": [0, 0, 0], "fov": 1},
    "materials": {"ground": )" +
                          material + R"(,
                  "lamp": {"type": "emissive", "radiance": 4}},
    "objects": [
      {"shape": "rectangle", "size": [100, 100], "material": "ground"},
      {"shape": "disk", "radius": 0.5, "segments": 256, "material": "lamp",
       "transform": {"translate": [0, 2, 0], "rotate": [180, 1, 0, 0]}}]})");
  if (change) change(scene);
  return imageMean(renderScene(std::move(scene), 1024));
}

TEST(Integrator, PbrMaterialIsTheWeightedMixOfItsParts) {
  // The dielectric base alone (metallic 0: diffuse under a specular layer) and the metal.
  const ImageMean diffuse =
      planeUnderDisk(R"({"type": "pbr", "albedo": 0.6, "roughness": 0.3, "metallic": 0})");
  const ImageMean metal =
      planeUnderDisk(R"({"type": "conductor", "color": 0.6, "roughness": 0.3})");
  EXPECT_GT(diffuse.mean - metal.mean, 0.05) << "the parts must differ for this test";
  for (const float metallic : {0.25f, 0.5f}) {
    const ImageMean mix =
        planeUnderDisk(R"({"type": "pbr", "albedo": 0.6, "roughness": 0.3, "metallic": )" +
                       std::to_string(metallic) + "}");
    const double expected = (1 - metallic) * diffuse.mean + metallic * metal.mean;
    const double error = std::sqrt(mix.standardError * mix.standardError +
                                   diffuse.standardError * diffuse.standardError +
                                   metal.standardError * metal.standardError);
    EXPECT_NEAR(mix.mean, expected, std::max(4 * error, 1e-3)) << "metallic " << metallic;
  }
  // glTF's metallic-roughness texture scales the factors per texel: blue 0 takes the metal
  // away, leaving the dielectric base; blue 1 keeps it.
  for (const float blue : {0.0f, 1.0f}) {
    const ImageMean textured = planeUnderDisk(
        R"({"type": "pbr", "albedo": 0.6, "roughness": 0.3, "metallic": 1})", [&](Scene& scene) {
          Image texel(1, 1);
          texel.pixels[0] = vec3(0.0f, 1.0f, blue);
          scene.images.push_back(makeTextureImage(texel));
          Texture t;
          t.kind = Texture::Kind::Image;
          t.imageIndex = int(scene.images.size() - 1);
          scene.textures.push_back(t);
          scene.materials[0].metallicRoughnessTexture = int(scene.textures.size() - 1);
        });
    const ImageMean& expected = blue == 0.0f ? diffuse : metal;
    EXPECT_NEAR(textured.mean, expected.mean,
                std::max(4 * std::hypot(textured.standardError, expected.standardError), 1e-3))
        << "blue " << blue;
  }
  // Full transmission is glass: invisible under a uniform sky.
  const ImageMean glass = imageMean(sphereUnderWhiteSky(
      R"({"type": "pbr", "albedo": 1, "transmission": 1, "ior": 1.5})", 256, 4));
  EXPECT_NEAR(glass.mean, 1.0, std::max(4 * glass.standardError, 2e-3));
}

// A 2 x 2 quad facing +z (u along +x, v along +y) with one image texture; `material` set up
// by the caller.
Scene texturedQuad(const std::string& materialJson, std::vector<vec3> texels, int width) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 16, "height": 16, "max_depth": 0},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 22.6},
    "materials": {"m": )" +
                          materialJson + R"(},
    "objects": [{"shape": "rectangle", "size": [2, 2], "material": "m",
                 "transform": {"rotate": [90, 1, 0, 0]}}]})");
  Image image(width, int(texels.size()) / width);
  image.pixels.assign(texels.begin(), texels.end());
  scene.images.push_back(makeTextureImage(image));
  Texture texture;
  texture.kind = Texture::Kind::Image;
  texture.imageIndex = 0;
  scene.textures.push_back(texture);
  return scene;
}

TEST(Integrator, NormalMapsTiltTheShadingNormalInTheTangentFrame) {
  const float s = std::sin(0.5f), c = std::cos(0.5f);
  // Tangent-space (sin, 0, cos) tilts towards +u (+x); (0, sin, cos) towards +v (+y, up the image).
  for (const vec3 tangentSpace : {vec3(s, 0, c), vec3(0, s, c)}) {
    Scene scene = texturedQuad(R"({"type": "diffuse"})", {0.5f * tangentSpace + vec3(0.5f)}, 1);
    scene.materials[0].normalTexture = 0;
    const auto prepared = prepareScene(std::move(scene));
    Hit hit;
    ASSERT_TRUE(
        prepared->accel->intersect(Ray{vec3(0.3f, 0.2f, 5), vec3(0, 0, -1), 0}, 0, 100, hit));
    const SurfaceHit surface = surfaceAt(prepared->scene, hit, 0.0f);
    EXPECT_NEAR(surface.shadingNormal.x, tangentSpace.x, 1e-2f);
    EXPECT_NEAR(surface.shadingNormal.y, tangentSpace.y, 1e-2f);
    EXPECT_NEAR(surface.shadingNormal.z, c, 1e-2f);
    EXPECT_NEAR(surface.geometricNormal.z, 1.0f, 1e-6f) << "the geometry does not change";
  }
}

TEST(Integrator, TheCoatTakesItsOwnNormalMapAndNotTheBases) {
  // One texel tilting by 0.5 rad towards +u, two textures reading it: the base's normal map, the
  // coat's (scaled by -1: towards -u), or both.
  const float s = std::sin(0.5f), c = std::cos(0.5f);
  const auto normals = [&](bool baseMapped, bool coatMapped) {
    Scene scene = texturedQuad(R"({"type": "pbr"})", {0.5f * vec3(s, 0, c) + vec3(0.5f)}, 1);
    Material& m = scene.materials[0];
    m.clearcoat = 1.0f;
    if (baseMapped) m.normalTexture = 0;
    if (coatMapped) m.clearcoatNormalTexture = 0, m.clearcoatNormalScale = -1.0f;
    const auto prepared = prepareScene(std::move(scene));
    Hit hit;
    EXPECT_TRUE(
        prepared->accel->intersect(Ray{vec3(0.3f, 0.2f, 5), vec3(0, 0, -1), 0}, 0, 100, hit));
    return surfaceAt(prepared->scene, hit, 0.0f);
  };
  // Under a mapped base, a coat without its own map keeps the interpolated normal (glTF).
  SurfaceHit hit = normals(true, false);
  EXPECT_NEAR(hit.shadingNormal.x, s, 1e-2f);
  test::expectNear(hit.coatNormal, vec3(0, 0, 1), 1e-6f);
  // Its own map tilts it, whatever the base does.
  for (const bool base : {false, true}) {
    hit = normals(base, true);
    test::expectNear(hit.coatNormal, glm::normalize(vec3(-s, 0, c)), 1e-2f);
    EXPECT_NEAR(hit.shadingNormal.x, base ? s : 0.0f, 1e-2f);
  }
  // Neither mapped: the coat lies in the shading frame, and no normal of its own is kept.
  EXPECT_EQ(normals(false, false).coatNormal, vec3(0.0f));
}

TEST(Integrator, NormalMapsFollowTheVertexTangentsAcrossEdges) {
  // Two triangles sharing the edge x + y = 1, whose dp/du differ by 18 degrees (the second's
  // uvs are sheared); a map tilting every normal by 0.5 rad towards +u.
  const float s = std::sin(0.5f), c = std::cos(0.5f);
  Scene scene = texturedQuad(R"({"type": "diffuse"})", {0.5f * vec3(s, 0, c) + vec3(0.5f)}, 1);
  scene.materials[0].normalTexture = 0;
  Mesh& mesh = scene.meshes[0];
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.normals.assign(4, vec3(0, 0, 1));
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1.5f}};
  mesh.vertexCount = 4;
  mesh.indices = {0, 1, 2, 1, 3, 2};
  mesh.materialIds = {0, 0};
  // The shading normal just either side of the edge's middle.
  const auto normalsAcross = [](const Scene& scene) {
    const auto prepared = prepareScene(scene);
    std::vector<vec3> normals;
    for (const float d : {-1e-3f, 1e-3f}) {
      Hit hit;
      EXPECT_TRUE(prepared->accel->intersect(Ray{vec3(0.5f + d, 0.5f + d, 5), vec3(0, 0, -1), 0}, 0,
                                             100, hit));
      normals.push_back(surfaceAt(prepared->scene, hit, 0.0f).shadingNormal);
    }
    return normals;
  };
  // Each triangle's own frame: the normal jumps at the edge.
  const std::vector<vec3> own = normalsAcross(scene);
  EXPECT_GT(glm::length(own[0] - own[1]), 0.1f);
  // The vertices' frames: continuous, tilted towards the mean of the two tangents.
  generateTangents(scene);
  const std::vector<vec3> shared = normalsAcross(scene);
  EXPECT_LT(glm::length(shared[0] - shared[1]), 5e-3f);
  const vec3 t = glm::normalize(vec3(1, 0, 0) + glm::normalize(vec3(1, -1.0f / 3.0f, 0)));
  for (const vec3& n : shared) test::expectNear(n, s * t + c * vec3(0, 0, 1), 1e-2f);
}

// A 2 x 2 diffuse quad of `albedo` facing the camera, which sees only its middle, under a
// uniform white sky that is also the backdrop.
Scene quadUnderWhiteSky(float albedo) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 8, "height": 8},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 10},
    "background": [1, 1, 1],
    "materials": {"m": {"type": "diffuse"}},
    "objects": [{"shape": "rectangle", "size": [2, 2], "material": "m",
                 "transform": {"rotate": [90, 1, 0, 0]}}]})");
  scene.materials[0].albedo = vec3(albedo);
  return scene;
}

TEST(Integrator, UnlitSurfacesShowTheirColourWhateverLightsThem) {
  // Under a sky of 3 a diffuse quad returns 3 times its albedo; unlit, its albedo itself (times
  // its vertex colour), even with no bounce allowed.
  Scene scene = quadUnderWhiteSky(0.5f);
  scene.background = vec3(3.0f);
  scene.materials[0].unlit = true;
  for (int depth : {0, 5}) {
    scene.settings.maxDepth = depth;
    const ImageMean m = imageMean(renderScene(scene, 4));
    EXPECT_NEAR(m.mean, 0.5, 1e-5) << depth;
  }
  scene.meshes[0].colors.assign(scene.meshes[0].vertexCount, vec3(0.5f));
  EXPECT_NEAR(imageMean(renderScene(scene, 4)).mean, 0.25, 1e-5);
}

TEST(Integrator, VertexColoursScaleTheBaseColour) {
  // A diffuse quad of albedo 0.8 facing the camera under a uniform white sky reflects its
  // albedo times its colour; the colours vary linearly across it, so the interpolated colour at
  // any point is that linear function there, and the image (centred on the quad) averages to
  // its value at the centre.
  Scene scene = quadUnderWhiteSky(0.8f);
  ASSERT_EQ(scene.meshes.size(), 1u);
  Mesh& mesh = scene.meshes[0];
  auto colour = [](vec3 p) { return vec3(0.25f + 0.25f * p.x, 0.5f, 0.75f - 0.25f * p.y); };
  for (const vec3& p : mesh.positions) mesh.colors.push_back(colour(p));
  const auto prepared = prepareScene(scene);
  Hit hit;
  ASSERT_TRUE(
      prepared->accel->intersect(Ray{vec3(0.3f, -0.6f, 5), vec3(0, 0, -1), 0}, 0, 100, hit));
  const SurfaceHit surface = surfaceAt(prepared->scene, hit, 0.0f);
  EXPECT_TRUE(surface.vertexColored);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(surface.vertexColor[c], colour(vec3(0.3f, -0.6f, 0))[c], 1e-5f) << c;
  const RenderResult r = renderScene(scene, 64);
  vec3 mean(0.0f);
  for (const vec3& v : r.image.pixels) mean += v / float(r.image.pixels.size());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], 0.8f * colour(vec3(0.0f))[c], 0.01f) << c;
  // Without colours the quad is grey.
  scene.meshes[0].colors.clear();
  const RenderResult grey = renderScene(scene, 64);
  vec3 greyMean(0.0f);
  for (const vec3& v : grey.image.pixels) greyMean += v / float(grey.image.pixels.size());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(greyMean[c], 0.8f, 0.01f) << c;
}

TEST(Integrator, ABlendedSurfaceMixesItselfWithWhatIsBehindByItsCoverage) {
  // A diffuse quad of albedo 0.5 and coverage 0.4 fills the view under a white sky, which is
  // also the backdrop: 0.4 of the camera rays see the lit quad (0.5), 0.6 the backdrop (1).
  // Light reaching the quad is not blocked by anything: 0.4 x 0.5 + 0.6 x 1 = 0.8.
  Scene scene = quadUnderWhiteSky(0.5f);
  scene.materials[0].alphaBlend = true;
  scene.materials[0].alpha = 0.4f;
  const ImageMean m = imageMean(renderScene(scene, 256));
  EXPECT_NEAR(m.mean, 0.8, std::max(4 * m.standardError, 5e-3)) << m.standardError;
}

TEST(Integrator, EmissionTexturesModulateEmittersSeenAndSampled) {
  // Emission 3 times a texture dark on the left half of the quad and white on the right.
  std::vector<vec3> texels(8, vec3(0.0f));
  for (int x = 4; x < 8; ++x) texels[size_t(x)] = vec3(1.0f);
  Scene scene = texturedQuad(R"({"type": "emissive", "radiance": 3})", texels, 8);
  scene.materials[0].emissionTexture = 0;
  const auto prepared = prepareScene(scene);
  // Seen: the camera frames the quad exactly; columns 2-5 are dark, 10-13 bright.
  const RenderResult r = renderScene(scene, 4);
  for (int y = 2; y < 14; ++y) {
    for (int x : {2, 5}) EXPECT_NEAR(luminance(r.image.at(x, y)), 0.0f, 1e-5f) << x << "," << y;
    for (int x : {10, 13}) EXPECT_NEAR(luminance(r.image.at(x, y)), 3.0f, 1e-4f) << x << "," << y;
  }
  // Sampled: a light sample carries the texture's value where it lands.
  int checked = 0;
  for (int i = 0; i < 64; ++i) {
    LightSample ls;
    const glm::vec2 u((float(i % 8) + 0.5f) / 8.0f, (float(i / 8) + 0.5f) / 8.0f);
    if (!sampleLight(prepared->scene, prepared->lights, vec3(0, 0, 3), 0.0f, 0.5f, u, ls)) continue;
    const float texU = 0.5f * (ls.point.x + 1.0f);
    if (texU > 0.1f && texU < 0.4f) {
      EXPECT_NEAR(ls.radiance.x, 0.0f, 1e-5f);
      ++checked;
    }
    if (texU > 0.6f && texU < 0.9f) {
      EXPECT_NEAR(ls.radiance.x, 3.0f, 1e-4f);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(Integrator, TexturedEmittersAreSampledWhereTheirTextureGlows) {
  // The quad as a strip of 8 columns of 2 triangles each, u = (x + 1) / 2, under a texture
  // of 64 columns that glows (1) only in columns 40-47: the sixth strip column (u 0.625 to
  // 0.75). Light sampling must choose that column's triangles, the others only at the floor.
  std::vector<vec3> texels(64 * 4, vec3(0.0f));
  for (int y = 0; y < 4; ++y)
    for (int x = 40; x < 48; ++x) texels[size_t(y * 64 + x)] = vec3(1.0f);
  Scene scene = texturedQuad(R"({"type": "emissive", "radiance": 3})", texels, 64);
  scene.materials[0].emissionTexture = 0;
  Mesh strip;
  const int columns = 8;
  for (int i = 0; i <= columns; ++i)
    for (int j = 0; j <= 1; ++j) {
      const float u = float(i) / float(columns), v = float(j);
      strip.positions.push_back(vec3(2.0f * u - 1.0f, 2.0f * v - 1.0f, 0.0f));
      strip.uvs.push_back(vec2(u, v));
    }
  strip.vertexCount = uint32_t(strip.positions.size());
  for (uint32_t i = 0; i < uint32_t(columns); ++i) {
    const uint32_t a = 2 * i, b = 2 * i + 2, c = 2 * i + 3, d = 2 * i + 1;
    strip.indices.insert(strip.indices.end(), {a, b, c, a, c, d});
    strip.materialIds.insert(strip.materialIds.end(), {0u, 0u});
  }
  scene.meshes.assign(1, strip);
  const auto prepared = prepareScene(scene);
  const std::vector<float>& probability = prepared->lights.triangleProbability[0];
  ASSERT_EQ(probability.size(), size_t(2 * columns));
  double glowing = 0, dark = 0;
  for (int t = 0; t < 2 * columns; ++t) (t / 2 == 5 ? glowing : dark) += probability[size_t(t)];
  EXPECT_NEAR(glowing + dark, 1.0, 1e-5);
  // The estimate reads the texture blurred over half a triangle, so the columns beside the
  // glowing one get a little; the texture's mean alone would give the column 1/8.
  EXPECT_GT(glowing, 0.85);
  for (int t = 0; t < 2 * columns; ++t) {
    // Every triangle keeps a share, so that a detail the estimate missed is still
    // light-sampled; the columns two away from the glow keep only that floor.
    EXPECT_GT(probability[size_t(t)], 0.0f) << t;
    if (std::abs(t / 2 - 5) >= 2) {
      EXPECT_LT(probability[size_t(t)], 1e-3f) << t;
    }
  }
  // Sampled points land in the glowing column and carry its radiance.
  int inColumn = 0;
  for (int i = 0; i < 64; ++i) {
    LightSample ls;
    const glm::vec2 u((float(i % 8) + 0.5f) / 8.0f, (float(i / 8) + 0.5f) / 8.0f);
    const float choose = (float(i) + 0.5f) / 64.0f;
    ASSERT_TRUE(sampleLight(prepared->scene, prepared->lights, vec3(0, 0, 3), 0.0f, choose, u, ls));
    const float texU = 0.5f * (ls.point.x + 1.0f);
    inColumn += texU > 0.625f && texU < 0.75f;
    // Between the column's outer texel centres the bilinear lookup reads glowing texels only.
    if (texU > 40.5f / 64 && texU < 47.5f / 64) {
      EXPECT_NEAR(ls.radiance.x, 3.0f, 1e-4f);
    }
  }
  EXPECT_GT(inColumn, 52) << "of 64";
}

// A 64 x 64 checker of single texels, black and white (float, so every mip level of it is
// exactly 0.5).
std::vector<vec3> checkerTexels() {
  std::vector<vec3> texels(64 * 64);
  for (int i = 0; i < 64 * 64; ++i) texels[size_t(i)] = vec3(float((i % 64 + i / 64) % 2));
  return texels;
}

TEST(Integrator, CameraRaysFirstHitsTakeTheFootprintOfOnePixel) {
  // The quad (1 in uv across its 2 units) seen head on: one pixel of the 16 x 16 image spans
  // 2 d tan(fov / 2) / 16 units at distance d, which is 4 texels of the 64 x 64 texture at
  // d = 5 (level 2) and 16 at d = 20 (level 4).
  Scene scene = texturedQuad(R"({"type": "diffuse"})", checkerTexels(), 64);
  scene.materials[0].albedoTexture = 0;
  for (const float distance : {5.0f, 20.0f}) {
    scene.camera.eye = vec3(0, 0, distance);
    const auto prepared = prepareScene(scene);
    const CameraSample sample{8.3f, 7.6f, 0.5f, 0.5f, 0.5f};
    const Ray ray = generateRay(prepared->camera, sample);
    Hit hit;
    ASSERT_TRUE(prepared->accel->intersect(ray, 0, 100, hit));
    const RayDifferentials rays = cameraRayDifferentials(prepared->camera, sample);
    const SurfaceHit first = surfaceAt(prepared->scene, hit, ray.time, &rays);
    const float pixelUv = distance * std::tan(0.5f * 22.6f * 3.14159265f / 180.0f) / 16.0f;
    EXPECT_NEAR(first.footprint.dx.x, pixelUv, 1e-3f * pixelUv);
    EXPECT_NEAR(first.footprint.dy.y, -pixelUv, 1e-3f * pixelUv) << "image y runs down v";
    EXPECT_NEAR(textureMipLevel(prepared->scene.images[0], first.footprint.dx, first.footprint.dy),
                std::log2(64 * pixelUv), 1e-3f);
    // A hit without differentials or a camera reads level 0.
    const SurfaceHit bare = surfaceAt(prepared->scene, hit, ray.time);
    EXPECT_EQ(bare.footprint.dx, vec2(0.0f));
    EXPECT_EQ(bare.footprint.dy, vec2(0.0f));
    // A bounce's hit takes the footprint the camera would give it: here, seen head on, the
    // camera ray's own.
    const SurfaceHit later = surfaceAt(prepared->scene, hit, ray.time, nullptr, &prepared->camera);
    EXPECT_NEAR(later.footprint.dx.x, pixelUv, 1e-3f * pixelUv);
    EXPECT_NEAR(later.footprint.dy.y, -pixelUv, 1e-3f * pixelUv);
  }
}

TEST(Integrator, AFarAwayCheckerTextureIsSeenAsItsMean) {
  // The emissive checker quad 40 away covers the 2 x 2 pixels in the image's middle, each
  // pixel 32 x 32 texels: every camera sample reads the coarse levels, 0.5 times radiance 3,
  // where point sampling would give 0 or 3 at random.
  Scene scene = texturedQuad(R"({"type": "emissive", "radiance": 3})", checkerTexels(), 64);
  scene.materials[0].emissionTexture = 0;
  scene.camera.eye = vec3(0, 0, 40);
  const RenderResult r = renderScene(scene, 8);
  for (int y = 7; y <= 8; ++y)
    for (int x = 7; x <= 8; ++x) EXPECT_NEAR(luminance(r.image.at(x, y)), 1.5f, 1e-4f);
  // Close up (distance 5, 4 texels a pixel: level 2, where 4 x 4 boxes of the checker are
  // 0.5 too) the same; at distance 1.25 (one texel a pixel, level 0) the checker shows.
  scene.camera.eye = vec3(0, 0, 1.25f);
  const RenderResult close = renderScene(scene, 8);
  double spread = 0;
  for (int x = 1; x < 15; ++x)
    spread += std::abs(luminance(close.image.at(x, 8)) - luminance(close.image.at(x - 1, 8)));
  EXPECT_GT(spread / 14, 0.3) << "neighbouring pixels differ where the texels show";
}

// The highlight of a point light next to the camera on an anisotropic metal plane seen from
// above: its spread along the image's x over its spread along y (second moments of the
// picture). The plane's uv runs along x and z, so its tangent is +x.
double highlightAspect(float strength, float rotation) {
  Scene scene = sceneFrom(R"({
    "render": {"width": 64, "height": 64, "max_depth": 1},
    "camera": {"eye": [0, 6, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40},
    "materials": {"metal": {"type": "pbr", "albedo": 1, "metallic": 1, "roughness": 0.3}},
    "lights": [{"type": "point", "position": [0, 6, 0], "intensity": 40}],
    "objects": [{"shape": "rectangle", "size": [8, 8], "material": "metal"}]})");
  scene.materials[0].anisotropyStrength = strength;
  scene.materials[0].anisotropyRotation = rotation;
  generateTangents(scene);
  const Image image = renderScene(std::move(scene), 16).image;
  double sum = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double v = luminance(image.at(x, y));
      sum += v, sx += v * x, sy += v * y, sxx += v * x * x, syy += v * y * y;
    }
  const double mx = sx / sum, my = sy / sum;
  return (sxx / sum - mx * mx) / (syy / sum - my * my);
}

TEST(Integrator, AnisotropicHighlightsStretchAlongTheTangentTurnedByTheRotation) {
  // glTF's anisotropy: the lobe is rough along the direction (the tangent, +x here, turned by
  // the rotation) and smooth across it, so a point light's highlight stretches along it.
  EXPECT_NEAR(highlightAspect(0.0f, 0.0f), 1.0, 0.1);
  EXPECT_GT(highlightAspect(0.8f, 0.0f), 2.0);
  EXPECT_LT(highlightAspect(0.8f, float(kPiD) / 2), 0.5);
}

TEST(Integrator, AnOrthographicCameraSeesObjectsAtTheirSizeAtAnyDistance) {
  // A glowing unit sphere in a view 4 tall and wide covers pi / 16 of the image, seen from 3 or
  // from 30 away; a perspective camera sees it shrink.
  const auto covered = [](float distance, float orthographicHeight) {
    Scene scene = sceneFrom(R"({
      "render": {"width": 64, "height": 64, "max_depth": 0},
      "camera": {"eye": [0, 0, )" +
                            std::to_string(distance) + R"(], "look_at": [0, 0, 0], "fov": 40},
      "materials": {"glow": {"type": "diffuse", "albedo": 0, "emission": 1}},
      "objects": [{"shape": "sphere", "radius": 1, "material": "glow"}]})");
    scene.camera.orthographicHeight = orthographicHeight;
    const Image image = renderScene(std::move(scene), 16).image;
    double sum = 0;
    for (const vec3& p : image.pixels) sum += p.x;
    return sum / double(image.pixels.size());
  };
  EXPECT_NEAR(covered(3.0f, 4.0f), kPiD / 16, 5e-3);
  EXPECT_NEAR(covered(30.0f, 4.0f), kPiD / 16, 5e-3);
  EXPECT_GT(covered(3.0f, 0.0f), 10 * covered(30.0f, 0.0f));
}

TEST(Integrator, EmittersShineOnlyFromTheirCounterClockwiseSide) {
  // The disk faces up (+y); a camera below it sees its black back side.
  // (Built by concatenation: g++ 12 gives a false -Wrestrict warning for string::replace.)
  const auto diskSeenFrom = [](const std::string& eyeY) {
    return sceneFrom(R"({
    "render": {"width": 4, "height": 4, "max_depth": 0},
    "camera": {"eye": [0, )" +
                     eyeY + R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 5},
    "materials": {"lamp": {"type": "emissive", "radiance": 3}},
    "objects": [{"shape": "disk", "radius": 1, "material": "lamp"}]})");
  };
  EXPECT_NEAR(imageMean(renderScene(diskSeenFrom("2"), 4)).mean, 3.0, 1e-4);
  EXPECT_NEAR(imageMean(renderScene(diskSeenFrom("-2"), 4)).mean, 0.0, 1e-6);
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
  scene.images.push_back(makeTextureImage(bad));
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
