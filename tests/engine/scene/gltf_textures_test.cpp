// glTF textures: images kept at their bit depth with their factors at lookup, normal maps,
// cut-out and blended coverage, emission textures, samplers' wrap modes, KHR_texture_transform,
// WebP images (EXT_texture_webp), images in formats that are not read (KTX2: left out, their
// fallbacks read) and images that are refused (not PNG, JPEG or WebP, damaged, missing).
#include "scene/gltf_io.h"

#include "scene/scene_loader.h"

#include "core/image_io.h"
#include "scene/texture_image.h"
#include "scene/textures.h"
#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>
#include <webp/encode.h>

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using namespace gltf_test;
using glm::vec2;
using test::expectSceneError;

// A 4 x 4 RGB image whose red byte names its texel: 16 (row * 4 + column) + 8, top row first,
// as a data: URI; and that red in linear units.
std::string labelledImageUri() {
  std::vector<uint8_t> texels;
  for (int i = 0; i < 16; ++i) texels.insert(texels.end(), {uint8_t(16 * i + 8), 0, 0});
  return pngUri(4, 4, 3, texels);
}
float red(int column, int row) { return srgb8ToLinear(uint8_t(16 * (row * 4 + column) + 8)); }

TEST(GltfTextures, BaseColourTextureIsSrgbBytesWithTheFactorAtLookup) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  // A 2x1 PNG: sRGB 255 and 128 in red.
  const std::vector<uint8_t> png = encodePng8(2, 1, 3, {255, 0, 0, 128, 0, 0});
  j["images"] = {{{"uri", "data:image/png;base64," + base64(std::string(png.begin(), png.end()))}}};
  j["textures"] = {{{"source", 0}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  const GltfData g = loadGltf(writeGltf("textured.gltf", j));
  ASSERT_GE(g.materials[0].albedoTexture, 0);
  const Texture& t = g.textures[size_t(g.materials[0].albedoTexture)];
  ASSERT_EQ(t.kind, Texture::Kind::Image);
  const TextureImage& image = g.images[size_t(t.imageIndex)];
  ASSERT_EQ(image.width(), 2);
  EXPECT_EQ(image.encoding, TexelEncoding::Srgb8) << "8 bits stay 8 bits";
  EXPECT_EQ(image.channels, 3);
  EXPECT_EQ((*image.bytes)[3], 128);
  EXPECT_EQ(textureTexel(image, 0, 1, 0).x, srgbToLinear(128.0f / 255.0f));
  EXPECT_NEAR(t.factor.x, 0.5f, 1e-6f);
  const Scene scene = [&] {
    Scene s;
    s.images = g.images;
    return s;
  }();
  // At the texels' centres (v = 0.5, u = 1/4 and 3/4): the factor times the linear values.
  EXPECT_NEAR(evalTexture(scene, t, {0.25f, 0.5f}).x, 0.5f, 1e-6f);               // 1.0 x 0.5
  EXPECT_NEAR(evalTexture(scene, t, {0.75f, 0.5f}).x, 0.5f * 0.2158605f, 1e-6f);  // sRGB 128
}

TEST(GltfTextures, NormalMapsCutoutsAndEmissionTexturesAreRead) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  // Image 0: RGBA, sRGB red 255 with alpha 51 and 255; image 1: a normal map texel.
  j["images"] = {{{"uri", pngUri(2, 1, 4, {255, 0, 0, 51, 255, 0, 0, 255})}},
                 {{"uri", pngUri(1, 1, 3, {128, 255, 128})}}};
  j["textures"] = {{{"source", 0}}, {{"source", 1}}};
  Json& paint = j["materials"][0];
  paint["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  paint["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 0.5};
  paint["alphaMode"] = "MASK";
  paint["alphaCutoff"] = 0.3;
  paint["normalTexture"] = {{"index", 1}, {"scale", 0.5}};
  paint["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
  j["materials"][2]["emissiveTexture"] = {{"index", 0}};
  const GltfData g = loadGltf(writeGltf("maps.gltf", j));
  const Material& m = g.materials[0];
  ASSERT_TRUE(m.hasCutouts());
  EXPECT_NEAR(m.alphaCutoff, 0.3f, 1e-6f);
  EXPECT_NEAR(m.alpha, 0.5f, 1e-6f);
  ASSERT_GE(m.alphaTexture, 0);
  const TextureImage& coverage = g.images[size_t(g.textures[size_t(m.alphaTexture)].imageIndex)];
  EXPECT_EQ(coverage.channels, 1) << "coverage keeps the alpha channel alone";
  EXPECT_EQ(coverage.levels.size(), 1u) << "coverage is tested at level 0 only";
  EXPECT_NEAR(textureTexel(coverage, 0, 0, 0).x, 0.2f, 1e-6f) << "alpha is linear, not sRGB";
  EXPECT_NEAR(textureTexel(coverage, 0, 1, 0).x, 1.0f, 1e-6f);
  ASSERT_GE(m.normalTexture, 0);
  EXPECT_NEAR(m.normalScale, 0.5f, 1e-6f);
  const TextureImage& normals = g.images[size_t(g.textures[size_t(m.normalTexture)].imageIndex)];
  EXPECT_EQ(normals.encoding, TexelEncoding::Linear8);
  EXPECT_NEAR(textureTexel(normals, 0, 0, 0).y, 1.0f, 1e-6f);
  EXPECT_NEAR(textureTexel(normals, 0, 0, 0).x, 128.0f / 255.0f, 1e-6f)
      << "normal maps are data, not sRGB";
  // The metallic-roughness texture is data too: the same image, converted once.
  EXPECT_EQ(m.metallicRoughnessTexture, m.normalTexture);
  // The emissive material shares the colour conversion of image 0 (factor 1): one image.
  const Material& lamp = g.materials[2];
  ASSERT_GE(lamp.emissionTexture, 0);
  EXPECT_EQ(lamp.emissionTexture, m.albedoTexture);
  EXPECT_EQ(g.images.size(), 3u);
}

TEST(GltfTextures, SamplerWrapModesAndTextureTransformsAreApplied) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", labelledImageUri()}}};
  j["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}}};
  j["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 0}}};
  j["extensionsUsed"].push_back("KHR_texture_transform");
  // The spec's example: the lower-left quadrant, turned 90 degrees.
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
      {"index", 1},
      {"extensions",
       {{"KHR_texture_transform",
         {{"offset", {0, 1}}, {"rotation", 1.57079632679}, {"scale", {0.5, 0.5}}}}}}};
  // Half the image, shifted right: the top-right quadrant; and the clamping sampler.
  j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = {
      {"index", 0},
      {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {0.5, 0.5}}}}}}};
  j["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 1.0};
  const GltfData g = loadGltf(writeGltf("transform.gltf", j));
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
  EXPECT_EQ(g.images.size(), 1u) << "one image, however it is mapped";
  Scene scene;
  scene.images = g.images;
  // glTF's uv (s, t) runs down the image; ours is (s, 1 - t).
  auto at = [&](const Texture& t, float s, float tt) {
    return evalTexture(scene, t, vec2(s, 1.0f - tt)).x;
  };
  const Texture& turned = g.textures[size_t(g.materials[0].albedoTexture)];
  EXPECT_TRUE(turned.wrap.repeats());
  EXPECT_TRUE(turned.uvTransformed);
  // (s, t) -> (t / 2, 1 - s / 2): rows 2 and 3, columns 0 and 1.
  const float paint = 0.5f;  // the material's base colour factor
  EXPECT_NEAR(at(turned, 0.75f, 0.25f), paint * red(0, 2), 1e-5f);
  EXPECT_NEAR(at(turned, 0.25f, 0.25f), paint * red(0, 3), 1e-5f);
  EXPECT_NEAR(at(turned, 0.25f, 0.75f), paint * red(1, 3), 1e-5f);
  EXPECT_NEAR(at(turned, 0.75f, 0.75f), paint * red(1, 2), 1e-5f);
  const Texture& shifted = g.textures[size_t(g.materials[1].albedoTexture)];
  EXPECT_EQ(shifted.wrap.u, TextureWrap::ClampToEdge);
  EXPECT_EQ(shifted.wrap.v, TextureWrap::MirroredRepeat);
  // (s, t) -> (s / 2 + 1/2, t / 2): columns 2 and 3, rows 0 and 1.
  EXPECT_NEAR(at(shifted, 0.25f, 0.25f), red(2, 0), 1e-5f);
  EXPECT_NEAR(at(shifted, 0.75f, 0.75f), red(3, 1), 1e-5f);
  // Past the right edge the clamp holds column 3; past t = 2 the mirror reads rows backwards.
  EXPECT_NEAR(at(shifted, 2.5f, 0.25f), red(3, 0), 1e-5f);
  // (t = 3.75 is t' = 1.875: mirrored, row 0; repeating or clamping would read row 3.)
  EXPECT_NEAR(at(shifted, 0.25f, 3.75f), red(2, 0), 1e-5f);
  // The footprint goes through the transform: two texels wide in the surface's uv is one
  // texel after the scale of 1/2, so level 0 is read, not level 1.
  const vec3 sharp = evalTexture(scene, shifted, vec2(0.25f, 0.75f), {vec2(0.5f, 0), vec2(0)});
  EXPECT_NEAR(sharp.x, red(2, 0), 1e-5f);
}

// magFilter NEAREST: a magnified lookup reads one texel (pixel art stays blocky), under every
// wrap mode; a minified one is trilinear as ever; LINEAR (or none) blends.
TEST(GltfTextures, NearestMagnificationReadsOneTexel) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", labelledImageUri()}}};
  j["samplers"] = {{{"magFilter", 9728}},
                   {{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}},
                   {{"magFilter", 9729}}};
  j["textures"] = {{{"source", 0}, {"sampler", 0}},
                   {{"source", 0}, {"sampler", 1}},
                   {{"source", 0}, {"sampler", 2}}};
  for (int m = 0; m < 3; ++m) {
    j["materials"][m]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", m}};
    j["materials"][m]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 1.0};
  }
  const GltfData g = loadGltf(writeGltf("nearest.gltf", j));
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
  Scene scene;
  scene.images = g.images;
  auto texture = [&](int m) -> const Texture& {
    return g.textures[size_t(g.materials[size_t(m)].albedoTexture)];
  };
  auto at = [&](int m, float s, float t) {
    return evalTexture(scene, texture(m), vec2(s, 1 - t)).x;
  };
  EXPECT_TRUE(texture(0).wrap.nearest);
  EXPECT_FALSE(texture(2).wrap.nearest);
  // (0.3, 0.1) is texel (1, 0), 0.2 of a texel left of its centre: one texel, not a blend.
  EXPECT_NEAR(at(0, 0.3f, 0.1f), red(1, 0), 1e-6f);
  EXPECT_NEAR(at(0, 0.49f, 0.9f), red(1, 3), 1e-6f);
  // Repeating past the edge: texel (0, 0) again; near u = 0 from the left, the last column.
  EXPECT_NEAR(at(0, 1.1f, 0.1f), red(0, 0), 1e-6f);
  EXPECT_NEAR(at(0, -0.05f, 0.1f), red(3, 0), 1e-6f);
  // Clamped along s, mirrored along t (t = 1.1 reads row 3, the mirror's first).
  EXPECT_NEAR(at(1, 1.7f, 0.1f), red(3, 0), 1e-6f);
  EXPECT_NEAR(at(1, 0.1f, 1.1f), red(0, 3), 1e-6f);
  // LINEAR blends the two columns' red.
  EXPECT_NEAR(at(2, 0.25f, 0.125f), 0.5f * (red(0, 0) + red(1, 0)), 1e-5f);
  // Minified (a footprint of two texels): level 1, as the linear sampler reads it.
  const UvFootprint wide{vec2(0.5f, 0), vec2(0)};
  const vec3 minifiedNearest = evalTexture(scene, texture(0), vec2(0.3f, 0.7f), wide);
  const vec3 minifiedLinear = evalTexture(scene, texture(2), vec2(0.3f, 0.7f), wide);
  EXPECT_NEAR(minifiedNearest.x, minifiedLinear.x, 1e-6f);
}

TEST(GltfTextures, BadSamplersAndTransformsNameTheElement) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", pngUri(1, 1, 3, {9, 9, 9})}}};
  j["samplers"] = {{{"wrapS", 10497}, {"wrapT", 1234}}};
  j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  expectSceneError([&] { loadGltf(writeGltf("wrap.gltf", j)); },
                   {"wrap.gltf", "samplers[0].wrapT", "1234"});
  j["samplers"] = {{{"wrapS", 33071}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
      {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1, "two"}}}}}}};
  expectSceneError([&] { loadGltf(writeGltf("transform.gltf", j)); },
                   {"transform.gltf", "KHR_texture_transform.scale", "two numbers"});
}

TEST(GltfTextures, BlendedMaterialsStopRaysAsOftenAsTheirCoverage) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", pngUri(2, 1, 4, {255, 0, 0, 51, 255, 0, 0, 255})}}};
  j["textures"] = {{{"source", 0}}};
  j["materials"][0]["alphaMode"] = "BLEND";
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1.0, 1.0, 1.0, 0.5};
  j["materials"][1]["alphaMode"] = "BLEND";  // covered everywhere: stays opaque
  const GltfData g = loadGltf(writeGltf("blend.gltf", j));
  const Material& m = g.materials[0];
  EXPECT_TRUE(m.alphaBlend);
  EXPECT_TRUE(m.hasCutouts());
  EXPECT_LT(m.alphaCutoff, 0.0f);
  EXPECT_NEAR(m.alpha, 0.5f, 1e-6f);
  ASSERT_GE(m.alphaTexture, 0);
  EXPECT_NEAR(
      textureTexel(g.images[size_t(g.textures[size_t(m.alphaTexture)].imageIndex)], 0, 0, 0).x,
      0.2f, 1e-6f);
  EXPECT_FALSE(g.materials[1].hasCutouts());
  for (const std::string& w : g.warnings) EXPECT_EQ(w.find("BLEND"), std::string::npos) << w;
}

// A lossless WebP of w x h RGB texels, as a data: URI.
std::string webpUri(int w, int h, const std::vector<uint8_t>& rgb) {
  uint8_t* out = nullptr;
  const size_t size = WebPEncodeLosslessRGB(rgb.data(), w, h, 3 * w, &out);
  const std::string bytes(reinterpret_cast<const char*>(out), size);
  WebPFree(out);
  EXPECT_GT(size, 0u);
  return "data:image/webp;base64," + base64(bytes);
}

TEST(GltfTextures, WebpImagesAreReadAndKtx2OnesLeftOutWithTheirFallbacksRead) {
  const std::string buffer = quadBuffer();
  const std::string png = pngUri(1, 1, 3, {255, 0, 0});
  const std::string webp = webpUri(2, 1, {0, 255, 0, 0, 0, 255});  // green, blue
  // Contents whose magic is KTX2's (a data: URI's type is not what decides).
  const std::string ktx2 =
      "data:image/png;base64," + base64(std::string("\xabKTX 20\xbb\r\n\x1a\n\0\0\0\0", 16));
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", webp}}, {{"uri", png}}, {{"uri", ktx2}}};
  j["textures"] = {// WebP with a PNG fallback: the WebP is read.
                   {{"source", 1}, {"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}},
                   // KTX2 only, through the extension: left out.
                   {{"extensions", {{"KHR_texture_basisu", {{"source", 2}}}}}},
                   // A WebP image as the texture's own source: read too.
                   {{"source", 0}}};
  j["extensionsUsed"].push_back("EXT_texture_webp");
  j["extensionsUsed"].push_back("KHR_texture_basisu");
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 1}};
  j["materials"][3]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 2}};
  const GltfData g = loadGltf(writeGltf("formats.gltf", j));
  for (size_t m : {0u, 3u}) {
    ASSERT_GE(g.materials[m].albedoTexture, 0) << m;
    const TextureImage& image =
        g.images[size_t(g.textures[size_t(g.materials[m].albedoTexture)].imageIndex)];
    EXPECT_EQ(image.width(), 2) << m;
    EXPECT_EQ(textureTexel(image, 0, 0, 0), vec3(0, 1, 0)) << m;
    EXPECT_EQ(textureTexel(image, 0, 1, 0), vec3(0, 0, 1)) << m;
  }
  EXPECT_EQ(g.materials[1].albedoTexture, -1);
  const std::string all = allWarnings(g);
  EXPECT_NE(all.find("textures[1]: its image is only in KHR_texture_basisu's format"),
            std::string::npos)
      << all;
  EXPECT_EQ(all.find("textures[0]"), std::string::npos) << all;
  EXPECT_EQ(all.find("textures[2]"), std::string::npos) << all;
  EXPECT_EQ(all.find("EXT_texture_webp"), std::string::npos) << all;

  // A damaged WebP, and an extension naming an image that does not exist: errors naming them.
  j["images"][0]["uri"] =
      "data:image/png;base64," + base64(std::string("RIFF\x10\0\0\0WEBPVP8 ", 16));
  expectSceneError([&] { loadGltf(writeGltf("damaged.gltf", j)); },
                   {"damaged.gltf", "images[0]", "WebP"});
  j["images"][0]["uri"] = webp;
  j["textures"][0]["extensions"]["EXT_texture_webp"]["source"] = 7;
  expectSceneError([&] { loadGltf(writeGltf("missing.gltf", j)); },
                   {"missing.gltf", "textures[0].extensions.EXT_texture_webp.source", "image 7"});
}

TEST(GltfTextures, ImagesThatAreNotPngOrJpegAreAnErrorNamingThem) {
  // A 16-bit PGM (stb's PNM reader once handed the 16-bit path an 8-bit buffer), a GIF, and
  // a PNG whose chunk claims more bytes than there are.
  const std::string buffer = quadBuffer();
  std::vector<uint8_t> damaged = encodePng8(1, 1, 3, {1, 2, 3});
  damaged[8] = 0x7f;  // the IHDR chunk's length
  for (const std::string& contents :
       {std::string("P5\n2 2\n65535\n") + std::string(8, '\x7f'), std::string("GIF89a\0\0"),
        std::string(damaged.begin(), damaged.end())}) {
    Json j = quadGltf(dataUri(buffer), buffer.size());
    j["images"] = {{{"uri", "data:image/png;base64," + base64(contents)}}};
    j["textures"] = {{{"source", 0}}};
    j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    expectSceneError([&] { loadGltf(writeGltf("bad_image.gltf", j)); },
                     {"bad_image.gltf", "images[0]"});
  }
}

TEST(GltfTextures, AMissingImageFileIsAnErrorNamingIt) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["textures"] = {{{"source", 0}}};
  j["images"] = {{{"uri", "missing.png"}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  expectSceneError([&] { loadGltf(writeGltf("missing_image.gltf", j)); },
                   {"missing_image.gltf", "missing.png"});
}

TEST(GltfTextures, TexturesOverTheBudgetAreHalvedWithAWarning) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", pngUri(64, 64, 3, std::vector<uint8_t>(64 * 64 * 3, 200))}}};
  j["textures"] = {{{"source", 0}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  const std::string path = writeGltf("budget.gltf", j);
  const Scene full = loadScene(path);
  ASSERT_EQ(full.images.size(), 1u);
  EXPECT_EQ(full.images[0].width(), 64);
  for (const std::string& w : full.warnings) EXPECT_EQ(w.find("budget"), std::string::npos) << w;
  SceneLoadOptions options;
  // The image takes 16383 bytes with its mips; at 32 x 32, 4095.
  options.textureBudgetBytes = 5000;
  const Scene halved = loadScene(path, options);
  EXPECT_EQ(halved.images[0].width(), 32);
  EXPECT_LE(halved.images[0].byteSize(), 5000u);
  ASSERT_FALSE(halved.warnings.empty());
  EXPECT_NE(halved.warnings.back().find(
                "textures take 0.02 MB, over the texture budget of 0.01 MB: the largest were "
                "halved once (a mip level each), leaving 0.00 MB"),
            std::string::npos)
      << halved.warnings.back();
  options.textureBudgetBytes = 0;  // no limit
  EXPECT_EQ(loadScene(path, options).images[0].width(), 64);
}

}  // namespace
}  // namespace penumbra
