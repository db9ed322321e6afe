// glTF's material extensions through loadGltf, on the quad of gltf_test_files.h: the
// dielectric base's specular layer, the clear coat, sheen, transmission's texture, anisotropy,
// volume, unlit and the archived specular-glossiness model, with their textures read as
// colour, data or alpha, and errors naming the
// malformed field. How they shade is tests/engine/scene/materials_test.cpp's and the
// environment lighting tests'.
#include "scene/gltf_io.h"
#include "scene/textures.h"

#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>

#include <string>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

// The quad's glTF with material `material` carrying the extension `name` (listed in
// extensionsUsed) and one texture per image of `imageUris`, in order.
Json quadWithExtension(int material, const char* name, Json extension,
                       const std::vector<std::string>& imageUris) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["materials"][material]["extensions"][name] = std::move(extension);
  j["images"] = Json::array();
  j["textures"] = Json::array();
  for (size_t i = 0; i < imageUris.size(); ++i) {
    j["images"].push_back({{"uri", imageUris[i]}});
    j["textures"].push_back({{"source", i}});
  }
  j["extensionsUsed"].push_back(name);
  return j;
}

// The image that texture `texture` of `g` reads.
const TextureImage& imageOf(const GltfData& g, int texture) {
  return g.images[size_t(g.textures[size_t(texture)].imageIndex)];
}

TEST(Gltf, SpecularExtensionScalesTheDielectricLayer) {
  // Image 0: the weight in its alpha (128); image 1: an sRGB colour.
  Json j = quadWithExtension(0, "KHR_materials_specular",
                             {{"specularFactor", 0.5},
                              {"specularColorFactor", {1.0, 0.5, 0.25}},
                              {"specularTexture", {{"index", 0}}},
                              {"specularColorTexture", {{"index", 1}}}},
                             {pngUri(1, 1, 4, {0, 0, 0, 128}), pngUri(1, 1, 3, {255, 188, 0})});
  const GltfData g = loadGltf(writeGltf("specular.gltf", j));
  const Material& m = g.materials[0];
  EXPECT_FLOAT_EQ(m.specular, 0.5f);
  EXPECT_EQ(m.specularColor, vec3(1.0f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(g.materials[1].specular, 1.0f) << "without the extension";
  EXPECT_EQ(g.materials[0].clearcoat, 0.0f);
  ASSERT_GE(m.specularTexture, 0);
  const TextureImage& weight = imageOf(g, m.specularTexture);
  EXPECT_EQ(weight.channels, 1) << "the alpha channel alone";
  EXPECT_NEAR(textureTexel(weight, 0, 0, 0).x, 128.0f / 255.0f, 1e-6f);
  ASSERT_GE(m.specularColorTexture, 0);
  const TextureImage& colour = imageOf(g, m.specularColorTexture);
  EXPECT_EQ(colour.encoding, TexelEncoding::Srgb8);
  EXPECT_NEAR(textureTexel(colour, 0, 0, 0).y, 0.5f, 0.01f) << "sRGB 188 is about 0.5 linear";
  const std::string all = allWarnings(g);
  EXPECT_EQ(all.find("is not read"), std::string::npos) << all;
  EXPECT_EQ(all.find("KHR_materials_specular is not supported"), std::string::npos) << all;
  j["materials"][0]["extensions"]["KHR_materials_specular"]["specularTexture"] = {{"texCoord", 0}};
  expectSceneError(
      [&] { loadGltf(writeGltf("reference.gltf", j)); },
      {"materials[0].extensions.KHR_materials_specular.specularTexture", "with an index"});
  j["materials"][0]["extensions"]["KHR_materials_specular"]["specularTexture"] = {{"index", 0}};
  j["materials"][0]["extensions"]["KHR_materials_specular"]["specularColorFactor"] = {1.0, -1.0,
                                                                                      0.0};
  expectSceneError(
      [&] { loadGltf(writeGltf("bad.gltf", j)); },
      {"bad.gltf", "materials[0].extensions.KHR_materials_specular.specularColorFactor"});
}

TEST(Gltf, ClearcoatExtensionGivesTheCoatsWeightAndRoughness) {
  // The weight in red, the roughness in green: linear data.
  Json j = quadWithExtension(1, "KHR_materials_clearcoat",
                             {{"clearcoatFactor", 0.8},
                              {"clearcoatRoughnessFactor", 0.2},
                              {"clearcoatTexture", {{"index", 0}}},
                              {"clearcoatRoughnessTexture", {{"index", 0}}},
                              {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}},
                             {pngUri(1, 1, 3, {51, 102, 0})});
  const GltfData g = loadGltf(writeGltf("coat.gltf", j));
  const Material& m = g.materials[1];
  EXPECT_FLOAT_EQ(m.clearcoat, 0.8f);
  EXPECT_FLOAT_EQ(m.clearcoatRoughness, 0.2f);
  EXPECT_EQ(g.materials[0].clearcoat, 0.0f);
  ASSERT_GE(m.clearcoatTexture, 0);
  EXPECT_EQ(m.clearcoatRoughnessTexture, m.clearcoatTexture) << "one image read one way";
  const TextureImage& coat = imageOf(g, m.clearcoatTexture);
  EXPECT_EQ(coat.encoding, TexelEncoding::Linear8);
  EXPECT_NEAR(textureTexel(coat, 0, 0, 0).x, 0.2f, 1e-6f);
  EXPECT_NEAR(textureTexel(coat, 0, 0, 0).y, 0.4f, 1e-6f);
  const std::string all = allWarnings(g);
  EXPECT_EQ(m.clearcoatNormalTexture, m.clearcoatTexture) << "one image read as data";
  EXPECT_FLOAT_EQ(m.clearcoatNormalScale, 0.5f);
  EXPECT_TRUE(m.coatHasOwnNormal());
  EXPECT_EQ(all.find("is not read"), std::string::npos) << all;
  EXPECT_EQ(all.find("KHR_materials_clearcoat is not supported"), std::string::npos) << all;
}

// KHR_materials_iridescence: the factor, the film's index and thickness range, the factor's
// texture (red) and the thickness texture (green), both linear; a negative thickness is an error.
TEST(Gltf, IridescenceExtensionIsRead) {
  Json j = quadWithExtension(2, "KHR_materials_iridescence",
                             {{"iridescenceFactor", 0.75},
                              {"iridescenceIor", 1.8},
                              {"iridescenceThicknessMinimum", 200.0},
                              {"iridescenceThicknessMaximum", 600.0},
                              {"iridescenceTexture", {{"index", 0}}},
                              {"iridescenceThicknessTexture", {{"index", 0}}}},
                             {pngUri(1, 1, 3, {51, 102, 0})});
  const GltfData g = loadGltf(writeGltf("iridescence.gltf", j));
  const Material& m = g.materials[2];
  EXPECT_FLOAT_EQ(m.iridescence, 0.75f);
  EXPECT_FLOAT_EQ(m.iridescenceIor, 1.8f);
  EXPECT_FLOAT_EQ(m.iridescenceThicknessMin, 200.0f);
  EXPECT_FLOAT_EQ(m.iridescenceThicknessMax, 600.0f);
  EXPECT_EQ(g.materials[0].iridescence, 0.0f) << "without the extension";
  ASSERT_GE(m.iridescenceTexture, 0);
  ASSERT_GE(m.iridescenceThicknessTexture, 0);
  const TextureImage& t = imageOf(g, m.iridescenceTexture);
  EXPECT_EQ(t.encoding, TexelEncoding::Linear8);
  EXPECT_NEAR(textureTexel(t, 0, 0, 0).y, 0.4f, 1e-6f);
  const std::string all = allWarnings(g);
  EXPECT_EQ(all.find("KHR_materials_iridescence"), std::string::npos) << all;
  // The defaults: index 1.3, 100 to 400 nm.
  j["materials"][2]["extensions"]["KHR_materials_iridescence"] = {{"iridescenceFactor", 1.0}};
  const Material d = loadGltf(writeGltf("defaults.gltf", j)).materials[2];
  EXPECT_FLOAT_EQ(d.iridescenceIor, 1.3f);
  EXPECT_FLOAT_EQ(d.iridescenceThicknessMin, 100.0f);
  EXPECT_FLOAT_EQ(d.iridescenceThicknessMax, 400.0f);
  j["materials"][2]["extensions"]["KHR_materials_iridescence"]["iridescenceThicknessMaximum"] =
      -5.0;
  expectSceneError(
      [&] { loadGltf(writeGltf("bad.gltf", j)); },
      {"bad.gltf", "materials[2].extensions.KHR_materials_iridescence.iridescenceThicknessMaximum",
       "at least 0"});
}

TEST(Gltf, SheenExtensionAndTheTransmissionTextureAreRead) {
  // Image 0: the roughness in its alpha (64); image 1: an sRGB colour; image 2: the
  // transmission in red, linear.
  Json j = quadWithExtension(2, "KHR_materials_sheen",
                             {{"sheenColorFactor", {1.0, 0.5, 0.25}},
                              {"sheenRoughnessFactor", 0.6},
                              {"sheenColorTexture", {{"index", 1}}},
                              {"sheenRoughnessTexture", {{"index", 0}}}},
                             {pngUri(1, 1, 4, {0, 0, 0, 64}), pngUri(1, 1, 3, {255, 188, 0}),
                              pngUri(1, 1, 3, {51, 0, 0})});
  j["materials"][3]["extensions"]["KHR_materials_transmission"] = {
      {"transmissionFactor", 1.0}, {"transmissionTexture", {{"index", 2}}}};
  j["extensionsUsed"].push_back("KHR_materials_transmission");
  const GltfData g = loadGltf(writeGltf("sheen.gltf", j));
  const Material& m = g.materials[2];
  EXPECT_EQ(m.sheenColor, vec3(1.0f, 0.5f, 0.25f));
  EXPECT_FLOAT_EQ(m.sheenRoughness, 0.6f);
  EXPECT_EQ(g.materials[0].sheenColor, vec3(0.0f)) << "without the extension";
  ASSERT_GE(m.sheenColorTexture, 0);
  const TextureImage& colour = imageOf(g, m.sheenColorTexture);
  EXPECT_EQ(colour.encoding, TexelEncoding::Srgb8);
  EXPECT_NEAR(textureTexel(colour, 0, 0, 0).y, 0.5f, 0.01f) << "sRGB 188 is about 0.5 linear";
  ASSERT_GE(m.sheenRoughnessTexture, 0);
  const TextureImage& roughness = imageOf(g, m.sheenRoughnessTexture);
  EXPECT_EQ(roughness.channels, 1) << "the alpha channel alone";
  EXPECT_NEAR(textureTexel(roughness, 0, 0, 0).x, 64.0f / 255.0f, 1e-6f);
  const Material& glass = g.materials[3];
  EXPECT_FLOAT_EQ(glass.transmission, 1.0f);
  ASSERT_GE(glass.transmissionTexture, 0);
  const TextureImage& share = imageOf(g, glass.transmissionTexture);
  EXPECT_EQ(share.encoding, TexelEncoding::Linear8);
  EXPECT_NEAR(textureTexel(share, 0, 0, 0).x, 0.2f, 1e-6f);
  const std::string all = allWarnings(g);
  EXPECT_EQ(all.find("is not read"), std::string::npos) << all;
  EXPECT_EQ(all.find("KHR_materials_sheen is not supported"), std::string::npos) << all;
  j["materials"][2]["extensions"]["KHR_materials_sheen"]["sheenColorFactor"] = {1.0, 2.0, 0.0};
  expectSceneError(
      [&] { loadGltf(writeGltf("bad.gltf", j)); },
      {"bad.gltf", "materials[2].extensions.KHR_materials_sheen.sheenColorFactor", "at most 1"});
}

TEST(Gltf, AnisotropyExtensionIsRead) {
  // The direction in red and green, the strength in blue: linear data.
  Json j = quadWithExtension(1, "KHR_materials_anisotropy",
                             {{"anisotropyStrength", 0.6},
                              {"anisotropyRotation", 1.25},
                              {"anisotropyTexture", {{"index", 0}}}},
                             {pngUri(1, 1, 3, {255, 128, 51})});
  const GltfData g = loadGltf(writeGltf("anisotropy.gltf", j));
  const Material& m = g.materials[1];
  EXPECT_FLOAT_EQ(m.anisotropyStrength, 0.6f);
  EXPECT_FLOAT_EQ(m.anisotropyRotation, 1.25f);
  EXPECT_TRUE(m.needsTangents());
  EXPECT_EQ(g.materials[0].anisotropyStrength, 0.0f) << "without the extension";
  ASSERT_GE(m.anisotropyTexture, 0);
  const TextureImage& t = imageOf(g, m.anisotropyTexture);
  EXPECT_EQ(t.encoding, TexelEncoding::Linear8);
  EXPECT_NEAR(textureTexel(t, 0, 0, 0).z, 0.2f, 1e-6f);
  EXPECT_EQ(allWarnings(g).find("KHR_materials_anisotropy"), std::string::npos) << allWarnings(g);
  j["materials"][1]["extensions"]["KHR_materials_anisotropy"]["anisotropyRotation"] = "left";
  expectSceneError(
      [&] { loadGltf(writeGltf("bad.gltf", j)); },
      {"bad.gltf", "materials[1].extensions.KHR_materials_anisotropy.anisotropyRotation"});
}

TEST(Gltf, VolumeAndUnlitExtensionsAreRead) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["materials"][3]["extensions"]["KHR_materials_volume"] = {{"thicknessFactor", 0.2},
                                                             {"attenuationDistance", 0.5},
                                                             {"attenuationColor", {0.9, 0.5, 0.1}}};
  // A thin wall (thickness 0, the default) has no volume.
  j["materials"][0]["extensions"]["KHR_materials_volume"] = {{"attenuationDistance", 0.5},
                                                             {"attenuationColor", {0.5, 0.5, 0.5}}};
  j["extensionsUsed"].push_back("KHR_materials_volume");
  const GltfData g = loadGltf(writeGltf("volume.gltf", j));
  EXPECT_TRUE(g.materials[3].absorbs());
  EXPECT_EQ(g.materials[3].attenuationColor, vec3(0.9f, 0.5f, 0.1f));
  EXPECT_FLOAT_EQ(g.materials[3].attenuationDistance, 0.5f);
  EXPECT_FALSE(g.materials[0].absorbs());
  EXPECT_FALSE(g.materials[0].unlit);
  EXPECT_EQ(allWarnings(g).find("KHR_materials_volume"), std::string::npos) << allWarnings(g);
  j["materials"][1]["extensions"]["KHR_materials_unlit"] = Json::object();
  j["extensionsUsed"].push_back("KHR_materials_unlit");
  const GltfData unlit = loadGltf(writeGltf("unlit.gltf", j));
  EXPECT_TRUE(unlit.materials[1].unlit);
  EXPECT_EQ(allWarnings(unlit).find("KHR_materials_unlit"), std::string::npos)
      << allWarnings(unlit);
  j["materials"][3]["extensions"]["KHR_materials_volume"]["attenuationColor"] = {2, 0, 0};
  expectSceneError([&] { loadGltf(writeGltf("colour.gltf", j)); },
                   {"materials[3].extensions.KHR_materials_volume.attenuationColor", "at most 1"});
  j["materials"][3]["extensions"]["KHR_materials_volume"]["attenuationColor"] = {1, 1, 1};
  j["materials"][3]["extensions"]["KHR_materials_volume"]["attenuationDistance"] = 0;
  expectSceneError([&] { loadGltf(writeGltf("distance.gltf", j)); },
                   {"KHR_materials_volume.attenuationDistance", "above 0"});
}

TEST(Gltf, SpecularGlossinessBecomesMetallicRoughnessWithASpecularLayer) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["materials"][0] = {{"name", "old"},
                       {"extensions",
                        {{"KHR_materials_pbrSpecularGlossiness",
                          {{"diffuseFactor", {0.8, 0.4, 0.2, 1.0}},
                           {"specularFactor", {0.2, 0.1, 0.05}},
                           {"glossinessFactor", 0.7}}}}}};
  j["materials"][1] = {{"name", "textured"},
                       {"alphaMode", "BLEND"},
                       {"extensions",
                        {{"KHR_materials_pbrSpecularGlossiness",
                          {{"diffuseFactor", {1.0, 1.0, 1.0, 0.5}},
                           {"diffuseTexture", {{"index", 0}}},
                           {"glossinessFactor", 0.8},
                           {"specularGlossinessTexture", {{"index", 1}}}}}}}};
  // Image 1: the specular colour (sRGB) and the glossiness in alpha (204 = 0.8).
  j["images"] = {{{"uri", pngUri(1, 1, 4, {255, 255, 255, 255})}},
                 {{"uri", pngUri(1, 1, 4, {255, 188, 0, 204})}}};
  j["textures"] = {{{"source", 0}}, {{"source", 1}}};
  j["extensionsUsed"].push_back("KHR_materials_pbrSpecularGlossiness");
  const GltfData g = loadGltf(writeGltf("specgloss.gltf", j));
  // The diffuse colour keeps 1 - max(specular) = 0.8 of itself under the specular layer, whose
  // f0 (0.04 x specularColor at ior 1.5) is the specular factor.
  const Material& old = g.materials[0];
  EXPECT_EQ(old.type, Material::Type::Pbr);
  EXPECT_NEAR(old.albedo.x, 0.64f, 1e-6f);
  EXPECT_NEAR(old.albedo.z, 0.16f, 1e-6f);
  EXPECT_EQ(old.metallic, 0.0f);
  EXPECT_NEAR(old.roughness, 0.3f, 1e-6f);
  EXPECT_FLOAT_EQ(old.specular, 1.0f);
  EXPECT_NEAR(0.04f * old.specularColor.x, 0.2f, 1e-6f);
  EXPECT_NEAR(0.04f * old.specularColor.z, 0.05f, 1e-6f);
  EXPECT_LT(old.metallicRoughnessTexture, 0);
  // Textured: the diffuse texture is the base colour's, the specular colour the layer's
  // texture (sRGB), and roughness reads 1 - 0.8 x the alpha.
  const Material& textured = g.materials[1];
  EXPECT_EQ(textured.albedo, vec3(1.0f)) << "the specular texture varies: c_diff takes it whole";
  EXPECT_TRUE(textured.alphaBlend);
  EXPECT_FLOAT_EQ(textured.alpha, 0.5f);
  ASSERT_GE(textured.albedoTexture, 0);
  ASSERT_GE(textured.specularColorTexture, 0);
  const Texture& colour = g.textures[size_t(textured.specularColorTexture)];
  EXPECT_EQ(g.images[size_t(colour.imageIndex)].encoding, TexelEncoding::Srgb8);
  Scene scene;
  scene.images = g.images;
  EXPECT_NEAR(evalTexture(scene, colour, vec2(0.5f), {}).y, 0.5f, 0.01f);
  ASSERT_GE(textured.metallicRoughnessTexture, 0);
  EXPECT_FLOAT_EQ(textured.roughness, 1.0f);
  const vec3 rough =
      evalTexture(scene, g.textures[size_t(textured.metallicRoughnessTexture)], vec2(0.5f), {});
  EXPECT_NEAR(rough.y, 1.0f - 0.8f * 0.8f, 1e-6f);
  const std::string all = allWarnings(g);
  EXPECT_EQ(all.find("pbrSpecularGlossiness"), std::string::npos) << all;
  j["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]["diffuseFactor"] = {1.0,
                                                                                             2.0};
  expectSceneError(
      [&] { loadGltf(writeGltf("bad.gltf", j)); },
      {"bad.gltf", "materials[0].extensions.KHR_materials_pbrSpecularGlossiness.diffuseFactor"});
}

}  // namespace
}  // namespace penumbra
