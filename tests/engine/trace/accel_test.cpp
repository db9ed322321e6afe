// Ray query tests on Embree, including motion blur (a moving sphere is hit where it is at the
// ray's time) and cut-outs (rays pass through the holes of an alpha mask).
#include "trace/accel.h"
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(Accel, MovingSphereIsHitWhereItIsAtTheRaysTime) {
  const Scene scene = parseSceneJson(R"({
    "materials": {"m": {"type": "diffuse"}},
    "objects": [{"shape": "sphere", "radius": 0.5, "material": "m",
                 "motion": {"translate": [3, 0, 0]}}]})",
                                     "moving.json", ".");
  Accel accel(scene);
  Hit hit;
  // A ray down the z axis through x = 0 meets the sphere at t=0 only; through x = 1.5,
  // only half way through the shutter; through x = 3, at the end.
  auto hits = [&](float x, float time) {
    return accel.intersect(Ray{vec3(x, 0, 5), vec3(0, 0, -1), time}, 0.0f, 100.0f, hit);
  };
  EXPECT_TRUE(hits(0, 0));
  EXPECT_NEAR(hit.t, 4.5f, 1e-2f);
  EXPECT_FALSE(hits(0, 1));
  EXPECT_TRUE(hits(1.5f, 0.5f));
  EXPECT_FALSE(hits(1.5f, 0.0f));
  EXPECT_TRUE(hits(3, 1));
  EXPECT_TRUE(accel.occluded(Ray{vec3(0, 0, 5), vec3(0, 0, -1), 0.0f}, 0.0f, 100.0f));
  EXPECT_FALSE(accel.occluded(Ray{vec3(0, 0, 5), vec3(0, 0, -1), 0.0f}, 0.0f, 4.0f));
}

TEST(Accel, RaysPassThroughTheHolesOfACutout) {
  // A 2 x 2 quad in the xy plane whose coverage texture is 0 on its left half (u < 0.5) and 1 on
  // its right; a ray down -z hits only the right half, for intersections and shadow rays alike.
  Scene scene = parseSceneJson(R"({
    "materials": {"leaf": {"type": "diffuse"}},
    "objects": [{"shape": "rectangle", "size": [2, 2], "material": "leaf",
                 "transform": {"rotate": [90, 1, 0, 0]}}]})",
                               "cutout.json", ".");
  Image coverage(2, 1);
  coverage.pixels = {vec3(0.0f), vec3(1.0f)};
  scene.images.push_back(makeTextureImage(coverage));
  Texture texture;
  texture.kind = Texture::Kind::Image;
  texture.imageIndex = 0;
  scene.textures.push_back(texture);
  auto ray = [](float x) { return Ray{vec3(x, 0, 5), vec3(0, 0, -1), 0.0f}; };
  Hit hit;
  {
    Accel opaque(scene);  // no cut-off yet: opaque everywhere
    EXPECT_TRUE(opaque.intersect(ray(-0.6f), 0.0f, 100.0f, hit));
  }
  scene.materials[0].alphaTexture = 0;
  scene.materials[0].alphaCutoff = 0.5f;
  const Accel accel(scene);
  EXPECT_FALSE(accel.intersect(ray(-0.6f), 0.0f, 100.0f, hit));
  EXPECT_FALSE(accel.occluded(ray(-0.6f), 0.0f, 100.0f));
  ASSERT_TRUE(accel.intersect(ray(0.6f), 0.0f, 100.0f, hit));
  EXPECT_NEAR(hit.t, 5.0f, 1e-4f);
  EXPECT_TRUE(accel.occluded(ray(0.6f), 0.0f, 100.0f));
  // The texture's uv transform (glTF's KHR_texture_transform) reaches the coverage test: u
  // mirrored, u' = 1 - u, puts the hole on the right.
  scene.textures[0].uvTransformed = true;
  scene.textures[0].uvLinear = glm::mat2(glm::vec2(-1, 0), glm::vec2(0, 1));
  scene.textures[0].uvOffset = vec2(1, 0);
  {
    const Accel mirrored(scene);
    EXPECT_TRUE(mirrored.intersect(ray(-0.6f), 0.0f, 100.0f, hit));
    EXPECT_FALSE(mirrored.occluded(ray(0.6f), 0.0f, 100.0f));
  }
  // And its wrap modes: u' = u + 0.25 runs past the image's right edge near the quad's right
  // side (x = 0.9: u' = 1.2), where clamping holds the covered texel but repeating wraps round
  // to the hole.
  scene.textures[0].uvLinear = glm::mat2(1.0f);
  scene.textures[0].uvOffset = vec2(0.25f, 0);
  EXPECT_FALSE(Accel(scene).intersect(ray(0.9f), 0.0f, 100.0f, hit));
  scene.textures[0].wrap = {TextureWrap::ClampToEdge, TextureWrap::ClampToEdge};
  EXPECT_TRUE(Accel(scene).intersect(ray(0.9f), 0.0f, 100.0f, hit));
  // The factor alone: coverage 0.4 under a cut-off of 0.5 is a hole everywhere.
  scene.materials[0].alphaTexture = -1;
  scene.materials[0].alpha = 0.4f;
  EXPECT_FALSE(Accel(scene).intersect(ray(0.6f), 0.0f, 100.0f, hit));
}

TEST(Accel, BlendedSurfacesStopRaysWithTheChanceOfTheirCoverage) {
  // The quad of the test above, blended with coverage 0.3: of many rays, about 0.3 stop; each
  // ray's intersection and occlusion query agree, and it meets the quad the same way again.
  Scene scene = parseSceneJson(R"({
    "materials": {"glass": {"type": "diffuse"}},
    "objects": [{"shape": "rectangle", "size": [2, 2], "material": "glass",
                 "transform": {"rotate": [90, 1, 0, 0]}}]})",
                               "blend.json", ".");
  scene.materials[0].alphaBlend = true;
  scene.materials[0].alpha = 0.3f;
  const Accel accel(scene);
  const int rays = 4000;
  int stopped = 0;
  Hit hit;
  for (int i = 0; i < rays; ++i) {
    const Ray ray{
        vec3(-0.9f + 1.8f * float(i % 64) / 64.0f, -0.9f + 1.8f * float(i / 64) / 64.0f, 5),
        vec3(0, 0, -1), 0.0f};
    const bool stops = accel.intersect(ray, 0.0f, 100.0f, hit);
    stopped += stops;
    EXPECT_EQ(accel.occluded(ray, 0.0f, 100.0f), stops) << i;
    EXPECT_EQ(accel.intersect(ray, 0.0f, 100.0f, hit), stops) << i;
  }
  // Binomial: standard deviation sqrt(0.3 * 0.7 / 4000) = 0.0072.
  EXPECT_NEAR(double(stopped) / rays, 0.3, 0.03);
  // Coverage 1 stops every ray, 0 none.
  scene.materials[0].alpha = 1.0f;
  EXPECT_TRUE(Accel(scene).intersect(Ray{vec3(0.1f, 0.2f, 5), vec3(0, 0, -1), 0}, 0, 100, hit));
  scene.materials[0].alpha = 0.0f;
  EXPECT_FALSE(Accel(scene).intersect(Ray{vec3(0.1f, 0.2f, 5), vec3(0, 0, -1), 0}, 0, 100, hit));
}

}  // namespace
}  // namespace penumbra
