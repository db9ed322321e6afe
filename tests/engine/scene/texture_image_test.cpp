// Tests for engine/scene/texture_image and the image lookups of engine/scene/textures: 8-bit
// storage and its size, the sRGB table, level 0 against the old float decode with the factor
// baked in, the mip pyramid (means kept, level choice, trilinear blend) and footprints from
// ray differentials.
#include "scene/texture_image.h"

#include "scene/textures.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace penumbra {
namespace {

using glm::vec2;

TEST(TextureImage, EightBitRgbTakesAtMostFourBytesATexelWithItsMips) {
  const int size = 2048;
  std::vector<uint8_t> texels(size_t(size) * size * 3);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = uint8_t(i * 7 % 251);
  const TextureImage image =
      makeTextureImage8(size, size, 3, std::move(texels), TexelEncoding::Srgb8);
  ASSERT_EQ(image.levels.size(), 12u);  // 2048, 1024, ..., 1
  EXPECT_EQ(image.levels.back().width, 1);
  EXPECT_EQ(image.levels.back().height, 1);
  EXPECT_LE(double(image.byteSize()) / (double(size) * size), 4.0);
  EXPECT_EQ(textureValueCount(size, size, 3), image.bytes->size());
  EXPECT_EQ(textureValueCount(size, size, 3, false), size_t(size) * size * 3);
  // The float texture it replaces took 12 bytes a texel without mips.
  EXPECT_GE(double(image.byteSize()) / (double(size) * size), 3.0);
  EXPECT_FALSE(image.floats);
}

TEST(TextureImage, SrgbTableIsTheTransferFunction) {
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(srgb8ToLinear(uint8_t(i)), srgbToLinear(float(i) / 255.0f)) << i;
    EXPECT_EQ(linearToSrgb8(srgb8ToLinear(uint8_t(i))), i) << "round trip of " << i;
  }
  EXPECT_NEAR(srgb8ToLinear(128), 0.2158605f, 1e-6f);
  EXPECT_EQ(srgb8ToLinear(255), 1.0f);
  EXPECT_EQ(linearToSrgb8(-1.0f), 0);
  EXPECT_EQ(linearToSrgb8(2.0f), 255);
}

// The lookup every texture had before textures kept their bit depth: bilinear, repeating, over
// float texels decoded from sRGB with the factor baked in.
vec3 oldBilinear(const Image& image, vec2 uv) {
  const float x = (uv.x - std::floor(uv.x)) * image.width - 0.5f;
  const float y = (1.0f - (uv.y - std::floor(uv.y))) * image.height - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  auto texel = [&](int ix, int iy) {
    ix = ((ix % image.width) + image.width) % image.width;
    iy = ((iy % image.height) + image.height) % image.height;
    return image.at(ix, iy);
  };
  const int ix = int(fx), iy = int(fy);
  return (1 - ty) * ((1 - tx) * texel(ix, iy) + tx * texel(ix + 1, iy)) +
         ty * ((1 - tx) * texel(ix, iy + 1) + tx * texel(ix + 1, iy + 1));
}

TEST(TextureImage, LevelZeroWithTheFactorAtLookupIsTheOldBakedFloatDecode) {
  const int w = 7, h = 5;
  std::mt19937 random(3);
  std::vector<uint8_t> bytes(size_t(w) * h * 3);
  for (uint8_t& b : bytes) b = uint8_t(random() & 255);
  const vec3 factor(0.8f, 0.5f, 0.25f);
  Image baked(w, h);
  for (size_t p = 0; p < baked.pixels.size(); ++p)
    baked.pixels[p] = factor * vec3(srgbToLinear(float(bytes[3 * p]) / 255.0f),
                                    srgbToLinear(float(bytes[3 * p + 1]) / 255.0f),
                                    srgbToLinear(float(bytes[3 * p + 2]) / 255.0f));
  Scene scene;
  scene.images.push_back(makeTextureImage8(w, h, 3, bytes, TexelEncoding::Srgb8));
  Texture texture;
  texture.kind = Texture::Kind::Image;
  texture.imageIndex = 0;
  texture.factor = factor;
  for (int i = 0; i < 200; ++i) {
    const vec2 uv(float(random() % 10000) / 3000.0f - 1.0f, float(random() % 10000) / 3000.0f);
    const vec3 expected = oldBilinear(baked, uv);
    const vec3 got = evalTexture(scene, texture, uv);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], expected[k], 1e-6f * std::max(1.0f, expected[k])) << uv.x << "," << uv.y;
  }
  // Linear data reads v / 255, grey images (one channel) read the same in all three.
  const TextureImage grey = makeTextureImage8(2, 1, 1, {51, 255}, TexelEncoding::Linear8);
  EXPECT_EQ(textureTexel(grey, 0, 0, 0), vec3(51.0f / 255.0f));
  EXPECT_EQ(textureTexel(grey, 0, 1, 0), vec3(1.0f));
  EXPECT_EQ(grey.byteSize(), 3u) << "2 texels, then 1 of level 1";
}

TEST(TextureImage, MipLevelsKeepTheMeanForAnySize) {
  // 5 x 3: the levels are 2 x 1 and 1 x 1; boxes weighted by overlap keep the mean.
  std::vector<float> values;
  double sum = 0;
  for (int i = 0; i < 15; ++i) {
    values.push_back(float(i * i % 11));
    sum += values.back();
  }
  const TextureImage image = makeTextureImageFloat(5, 3, 1, values);
  ASSERT_EQ(image.levels.size(), 3u);
  EXPECT_EQ(image.levels[1].width, 2);
  EXPECT_EQ(image.levels[1].height, 1);
  EXPECT_NEAR(textureTexel(image, 2, 0, 0).x, sum / 15.0, 1e-5);
  const float level1Mean = 0.5f * (textureTexel(image, 1, 0, 0).x + textureTexel(image, 1, 1, 0).x);
  EXPECT_NEAR(level1Mean, sum / 15.0, 1e-5);
  // A 4 x 4 level is the 2 x 2 box average of the one above it.
  std::vector<float> ramp(16);
  for (int i = 0; i < 16; ++i) ramp[size_t(i)] = float(i);
  const TextureImage boxes = makeTextureImageFloat(4, 4, 1, ramp);
  EXPECT_FLOAT_EQ(textureTexel(boxes, 1, 0, 0).x, (0 + 1 + 4 + 5) / 4.0f);
  EXPECT_FLOAT_EQ(textureTexel(boxes, 1, 1, 1).x, (10 + 11 + 14 + 15) / 4.0f);
}

TEST(TextureImage, ColourMipsAverageLinearValuesNotSrgbBytes) {
  // Black and white texels average to linear 0.5, which is sRGB 188, not byte 128.
  const TextureImage image = makeTextureImage8(2, 1, 1, {0, 255}, TexelEncoding::Srgb8);
  ASSERT_EQ(image.levels.size(), 2u);
  EXPECT_EQ((*image.bytes)[2], linearToSrgb8(0.5f));
  EXPECT_NEAR(textureTexel(image, 1, 0, 0).x, 0.5f, 0.005f);
}

TEST(TextureImage, LevelIsTheLog2OfTheFootprintInTexels) {
  const TextureImage image = makeTextureImageFloat(256, 128, 1, std::vector<float>(256 * 128));
  ASSERT_EQ(image.levels.size(), 9u);
  EXPECT_EQ(textureMipLevel(image, vec2(0.0f), vec2(0.0f)), 0.0f);
  EXPECT_EQ(textureMipLevel(image, vec2(0.5f / 256, 0), vec2(0, 0.5f / 128)), 0.0f);
  EXPECT_FLOAT_EQ(textureMipLevel(image, vec2(4.0f / 256, 0), vec2(0, 1.0f / 128)), 2.0f);
  // The longer side decides, in texels of its own axis: 8 texels down v.
  EXPECT_FLOAT_EQ(textureMipLevel(image, vec2(1.0f / 256, 0), vec2(0, 8.0f / 128)), 3.0f);
  // A diagonal footprint counts its length.
  EXPECT_FLOAT_EQ(textureMipLevel(image, vec2(3.0f / 256, 4.0f / 128), vec2(0.0f)),
                  std::log2(5.0f));
  EXPECT_EQ(textureMipLevel(image, vec2(1e6f, 0), vec2(0.0f)), 8.0f) << "clamped to 1x1";
  EXPECT_EQ(textureMipLevel(image, vec2(std::nanf(""), 0), vec2(0.0f)), 0.0f);
}

TEST(TextureImage, TrilinearBlendsTheTwoLevelsAroundTheFootprint) {
  std::vector<float> values(64);
  for (int i = 0; i < 64; ++i) values[size_t(i)] = float((i % 8) * (i / 8) % 5);
  const TextureImage image = makeTextureImageFloat(8, 8, 1, values);
  const vec2 uv(0.3f, 0.6f);
  const vec2 dx(std::exp2(1.25f) / 8.0f, 0.0f);  // level 1.25
  const float expected =
      0.75f * sampleTextureLevel(image, 1, uv).x + 0.25f * sampleTextureLevel(image, 2, uv).x;
  EXPECT_NEAR(sampleTexture(image, uv, dx, vec2(0.0f)).x, expected, 1e-5f);
  EXPECT_EQ(sampleTexture(image, uv, vec2(0.0f), vec2(0.0f)), sampleTextureLevel(image, 0, uv));
}

TEST(TextureImage, AFarAwayCheckerAveragesToItsMean) {
  // A 64 x 64 checker of single texels, black and white, seen with a footprint of the whole
  // texture: its mean, 0.5 (to one step of the 8-bit levels) wherever it is looked up.
  std::vector<uint8_t> bytes(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) bytes[size_t(y * 64 + x)] = (x + y) % 2 ? 255 : 0;
  for (const TexelEncoding encoding : {TexelEncoding::Linear8, TexelEncoding::Srgb8}) {
    const TextureImage image = makeTextureImage8(64, 64, 1, bytes, encoding);
    for (const vec2 uv : {vec2(0.1f, 0.2f), vec2(0.77f, 0.31f), vec2(0.5f, 0.9f)}) {
      EXPECT_NEAR(sampleTexture(image, uv, vec2(1.0f, 0.0f), vec2(0.0f, 1.0f)).x, 0.5f, 0.005f);
      // Up close (a quarter of a texel a pixel) it is the checker itself.
      const float close = sampleTexture(image, uv, vec2(0.25f / 64, 0), vec2(0, 0.25f / 64)).x;
      EXPECT_EQ(close, sampleTextureLevel(image, 0, uv).x);
    }
  }
}

TEST(TextureImage, ClampToEdgeExtendsTheEdgeTexels) {
  // 4 x 1 texels 0, 1, 2, 3 (float, so the values are exact).
  const TextureImage image = makeTextureImageFloat(4, 1, 1, {0, 1, 2, 3});
  const TextureWrapModes clamp{TextureWrap::ClampToEdge, TextureWrap::ClampToEdge};
  auto at = [&](float u, TextureWrapModes wrap) {
    return sampleTextureLevel(image, 0, vec2(u, 0.5f), wrap).x;
  };
  // Inside, away from the edges, the modes agree.
  for (const float u : {0.125f, 0.3f, 0.625f, 0.875f}) EXPECT_EQ(at(u, clamp), at(u, {})) << u;
  // At the left edge repeat blends the last texel in; clamp keeps the first.
  EXPECT_FLOAT_EQ(at(0.0f, {}), 1.5f);
  EXPECT_FLOAT_EQ(at(0.0f, clamp), 0.0f);
  EXPECT_FLOAT_EQ(at(1.0f, clamp), 3.0f);
  for (const float u : {-0.5f, -3.25f, -1000.875f, -1e30f}) EXPECT_EQ(at(u, clamp), 0.0f) << u;
  for (const float u : {1.5f, 7.0f, 1e30f}) EXPECT_EQ(at(u, clamp), 3.0f) << u;
}

TEST(TextureImage, RepeatReadsTheSameTexelsInEveryPeriod) {
  const TextureImage image = makeTextureImageFloat(4, 1, 1, {0, 1, 2, 3});
  auto at = [&](float u) { return sampleTextureLevel(image, 0, vec2(u, 0.5f)).x; };
  // Texel centres at 0.125 + 0.25 i; between them a blend, across the seam of the last and first.
  EXPECT_FLOAT_EQ(at(0.25f), 0.5f);
  EXPECT_FLOAT_EQ(at(0.0f), 1.5f);
  EXPECT_FLOAT_EQ(at(0.0625f), 0.75f) << "three quarters of the way from texel 3 to texel 0";
  EXPECT_FLOAT_EQ(at(0.9375f), 2.25f) << "a quarter of the way from texel 3 to texel 0";
  for (const float period : {1.0f, -1.0f, 5.0f, -7.0f, 64.0f, -1000.0f})
    for (const float u : {0.0f, 0.0625f, 0.3f, 0.5f, 0.9375f})
      EXPECT_NEAR(at(u + period), at(u), 2e-3f) << u << " + " << period;
  // Along v too (v = 0 is the bottom row).
  const TextureImage column = makeTextureImageFloat(1, 4, 1, {3, 2, 1, 0});
  for (const float v : {0.3f, -0.7f, 4.3f})
    EXPECT_NEAR(sampleTextureLevel(column, 0, vec2(0.5f, v)).x, 0.7f, 1e-3f) << v;
}

TEST(TextureImage, MirroredRepeatReadsEveryOtherPeriodBackwards) {
  const TextureImage image = makeTextureImageFloat(4, 1, 1, {0, 1, 2, 3});
  const TextureWrapModes mirror{TextureWrap::MirroredRepeat, TextureWrap::Repeat};
  auto at = [&](float u) { return sampleTextureLevel(image, 0, vec2(u, 0.5f), mirror).x; };
  // Texel centres: u = 0.125 + 0.25 i in [0, 1); mirrored in [1, 2) and [-1, 0).
  EXPECT_FLOAT_EQ(at(0.375f), 1.0f);
  EXPECT_FLOAT_EQ(at(1.125f), 3.0f);
  EXPECT_FLOAT_EQ(at(1.375f), 2.0f);
  EXPECT_FLOAT_EQ(at(1.875f), 0.0f);
  EXPECT_FLOAT_EQ(at(2.125f), 0.0f) << "the period is two images";
  EXPECT_FLOAT_EQ(at(-0.125f), 0.0f);
  EXPECT_FLOAT_EQ(at(-0.375f), 1.0f);
  // At the seams the mirror meets itself: the edge texel, not a blend across the image.
  EXPECT_FLOAT_EQ(at(1.0f), 3.0f);
  EXPECT_FLOAT_EQ(at(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(at(2.0f), 0.0f);
}

TEST(TextureImage, WrapModesActPerAxis) {
  // 2 x 2: top row 0, 1; bottom row 2, 3. v = 0 is the bottom.
  const TextureImage image = makeTextureImageFloat(2, 2, 1, {0, 1, 2, 3});
  const TextureWrapModes repeatUClampV{TextureWrap::Repeat, TextureWrap::ClampToEdge};
  EXPECT_FLOAT_EQ(sampleTextureLevel(image, 0, vec2(1.25f, -0.5f), repeatUClampV).x, 2.0f);
  EXPECT_FLOAT_EQ(sampleTextureLevel(image, 0, vec2(1.75f, 7.0f), repeatUClampV).x, 1.0f);
  const TextureWrapModes clampUMirrorV{TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat};
  EXPECT_FLOAT_EQ(sampleTextureLevel(image, 0, vec2(-2.0f, 1.25f), clampUMirrorV).x, 0.0f);
  EXPECT_FLOAT_EQ(sampleTextureLevel(image, 0, vec2(-2.0f, 1.75f), clampUMirrorV).x, 2.0f);
  // Trilinear lookups pass the modes to both levels.
  EXPECT_FLOAT_EQ(sampleTexture(image, vec2(1.25f, -0.5f), vec2(0.0f), vec2(0.0f), repeatUClampV).x,
                  2.0f);
  // 8-bit images wrap the same way.
  const TextureImage bytes = makeTextureImage8(2, 1, 1, {0, 255}, TexelEncoding::Linear8);
  const TextureWrapModes clamp{TextureWrap::ClampToEdge, TextureWrap::ClampToEdge};
  EXPECT_FLOAT_EQ(sampleTextureLevel(bytes, 0, vec2(0.0f, 0.5f), clamp).x, 0.0f);
  EXPECT_FLOAT_EQ(sampleTextureLevel(bytes, 0, vec2(0.0f, 0.5f)).x, 0.5f);
}

TEST(TextureImage, WithoutTheFinestLevelTheCoarserLevelsAreUnchanged) {
  std::vector<uint8_t> bytes(8 * 4 * 3);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(i * 37 % 251);
  const TextureImage image = makeTextureImage8(8, 4, 3, bytes, TexelEncoding::Srgb8);
  const TextureImage half = withoutFinestLevel(image);
  ASSERT_EQ(half.levels.size(), image.levels.size() - 1);
  EXPECT_EQ(half.width(), 4);
  EXPECT_EQ(half.height(), 2);
  EXPECT_EQ(half.encoding, TexelEncoding::Srgb8);
  EXPECT_EQ(half.byteSize(), image.byteSize() - 8 * 4 * 3);
  for (size_t level = 0; level < half.levels.size(); ++level)
    for (int y = 0; y < half.levels[level].height; ++y)
      for (int x = 0; x < half.levels[level].width; ++x)
        EXPECT_EQ(textureTexel(half, int(level), x, y), textureTexel(image, int(level) + 1, x, y));
  // A lookup with a footprint of two texels of the old level 0 reads the same level as before.
  const vec2 uv(0.3f, 0.6f), dx(2.0f / 8, 0), dy(0, 2.0f / 4);
  EXPECT_EQ(sampleTexture(half, uv, dx, dy), sampleTexture(image, uv, dx, dy));
  // Floats too; and a single level has nothing to fall back to.
  const TextureImage floats = makeTextureImageFloat(2, 2, 1, {1, 2, 3, 4});
  EXPECT_FLOAT_EQ(textureTexel(withoutFinestLevel(floats), 0, 0, 0).x, 2.5f);
  EXPECT_THROW(withoutFinestLevel(makeTextureImageFloat(2, 2, 1, {1, 2, 3, 4}, false)),
               std::invalid_argument);
}

TEST(TextureImage, ABudgetHalvesTheLargestImagesFirstUntilTheyFit) {
  auto grey = [](int size) {
    return makeTextureImage8(size, size, 1, std::vector<uint8_t>(size_t(size) * size, 7),
                             TexelEncoding::Linear8);
  };
  // 64 x 64 and 16 x 16 with their mips: 5461 and 341 bytes.
  std::vector<TextureImage> images = {grey(16), grey(64)};
  ASSERT_EQ(images[1].byteSize(), 5461u);
  EXPECT_EQ(fitTexturesToBudget(images, 10000), 0);
  EXPECT_EQ(images[1].width(), 64);
  // 2000 bytes: the 64 x 64 one drops to 32 x 32 (1365), which with 341 fits.
  EXPECT_EQ(fitTexturesToBudget(images, 2000), 1);
  EXPECT_EQ(images[1].width(), 32);
  EXPECT_EQ(images[0].width(), 16);
  // 500 bytes: the larger first (32 -> 16: 341 + 341), then, of two the same size, the first
  // (16 -> 8: 85 + 341 = 426).
  EXPECT_EQ(fitTexturesToBudget(images, 500), 2);
  EXPECT_LE(images[0].byteSize() + images[1].byteSize(), 500u);
  EXPECT_EQ(images[0].width(), 8);
  EXPECT_EQ(images[1].width(), 16);
  // Nothing left to drop: it stops at 1 x 1.
  fitTexturesToBudget(images, 0);
  EXPECT_EQ(images[0].width(), 1);
  EXPECT_EQ(images[1].width(), 1);
}

TEST(TextureImage, BadSizesAreRefused) {
  EXPECT_THROW(makeTextureImage8(2, 2, 3, std::vector<uint8_t>(11), TexelEncoding::Srgb8),
               std::invalid_argument);
  EXPECT_THROW(makeTextureImage8(2, 2, 2, std::vector<uint8_t>(8), TexelEncoding::Linear8),
               std::invalid_argument);
  EXPECT_THROW(makeTextureImageFloat(0, 2, 1, {}), std::invalid_argument);
}

// ---- footprints from ray differentials --------------------------------------------------------

TEST(TextureFootprint, PinholeDifferentialsOnAPlaneFacingTheCameraAreOnePixel) {
  // A 200 x 100 image with a 60 degree vertical field of view, looking down -z at a plane 10
  // away: one pixel there is 2 * 10 * tan(30 degrees) / 100 wide, in x and in y alike.
  Camera camera;
  camera.eye = vec3(0, 0, 10);
  camera.lookAt = vec3(0, 0, 0);
  camera.vfovDegrees = 60;
  const CameraFrame frame = makeCameraFrame(camera, 200, 100);
  const float pixel = 2.0f * 10.0f * std::tan(3.14159265f / 6.0f) / 100.0f;
  const CameraSample sample{100.0f, 50.0f, 0.5f, 0.5f, 0.0f};  // the image's centre
  const Ray ray = generateRay(frame, sample);
  const RayDifferentials rays = cameraRayDifferentials(frame, sample);
  const vec3 point = ray.origin + 10.0f * ray.direction;
  vec3 dpdx, dpdy;
  ASSERT_TRUE(differentialOffsets(rays, point, vec3(0, 0, 1), dpdx, dpdy));
  EXPECT_NEAR(dpdx.x, pixel, 1e-5f);
  EXPECT_NEAR(dpdx.y, 0.0f, 1e-6f);
  EXPECT_NEAR(dpdy.x, 0.0f, 1e-6f);
  EXPECT_NEAR(dpdy.y, -pixel, 1e-5f) << "image y runs down";
  EXPECT_NEAR(dpdx.z, 0.0f, 1e-6f);
  // On a plane with u = x / 4 and v = y / 2 (dp/du = (4,0,0), dp/dv = (0,2,0)).
  const UvFootprint fp = uvFootprint(dpdx, dpdy, vec3(4, 0, 0), vec3(0, 2, 0));
  EXPECT_NEAR(fp.dx.x, pixel / 4, 1e-6f);
  EXPECT_NEAR(fp.dx.y, 0.0f, 1e-7f);
  EXPECT_NEAR(fp.dy.y, -pixel / 2, 1e-6f);
  // A thin lens keeps the lens point: at the focus distance the footprint is the same.
  camera.lensRadius = 0.5f;
  const CameraFrame lens = makeCameraFrame(camera, 200, 100);
  const CameraSample offLens{100.0f, 50.0f, 0.9f, 0.2f, 0.0f};
  const Ray lensRay = generateRay(lens, offLens);
  const float t = (0.0f - lensRay.origin.z) / lensRay.direction.z;
  ASSERT_TRUE(differentialOffsets(cameraRayDifferentials(lens, offLens),
                                  lensRay.origin + t * lensRay.direction, vec3(0, 0, 1), dpdx,
                                  dpdy));
  EXPECT_NEAR(glm::length(dpdx), pixel, 1e-4f);
  EXPECT_NEAR(glm::length(dpdy), pixel, 1e-4f);
}

TEST(TextureFootprint, ParallelRaysAndFlatParameterisationsGiveNoFootprint) {
  RayDifferentials rays;
  rays.xOrigin = rays.yOrigin = vec3(0, 0, 1);
  rays.xDirection = rays.yDirection = vec3(1, 0, 0);  // along the plane z = 0
  vec3 dpdx, dpdy;
  EXPECT_FALSE(differentialOffsets(rays, vec3(0.0f), vec3(0, 0, 1), dpdx, dpdy));
  const UvFootprint fp = uvFootprint(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0.0f), vec3(0.0f));
  EXPECT_EQ(fp.dx, vec2(0.0f));
  EXPECT_EQ(fp.dy, vec2(0.0f));
}

}  // namespace
}  // namespace penumbra
