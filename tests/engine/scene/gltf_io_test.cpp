// glTF 2.0 scenes: small files written here (buffers as data: URIs, a .glb container, a
// relative .bin) through loadGltf and loadScene: geometry placed by the node hierarchy,
// quantised attributes, sparse accessors and vertex colours, the material mapping, cameras,
// animation, warnings for what is not rendered, and clear errors for damaged files and for URIs
// that name a network location. The textures are gltf_textures_test.cpp's.
#include "scene/gltf_io.h"

#include "core/image_io.h"
#include "scene/scene_loader.h"
#include "scene/textures.h"
#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

TEST(Gltf, NodeHierarchyPlacesTheMeshes) {
  const std::string buffer = quadBuffer();
  const GltfData g = loadGltf(writeGltf("quad.gltf", quadGltf(dataUri(buffer), buffer.size())));
  ASSERT_EQ(g.mesh.vertexCount, 8u);
  ASSERT_EQ(g.mesh.triangleCount(), 4u);
  // The child: scaled by 2, turned +90 degrees about y (x -> -z), then moved by (10, 0, 0).
  expectNear(g.mesh.positions[1], vec3(10, 0, -2));
  expectNear(g.mesh.positions[2], vec3(10, 2, -2));
  // Its normal +z turns to +x; the second instance has no normals of its own and gets its
  // faces' normal.
  expectNear(g.mesh.normals[0], vec3(1, 0, 0));
  expectNear(g.mesh.normals[4], vec3(0, 0, 1));
  // uv (0, 1) in glTF (v down) is (0, 0) in penumbra (v up).
  EXPECT_NEAR(g.mesh.uvs[0].y, 0.0f, 1e-6f);
  EXPECT_NEAR(g.mesh.uvs[2].y, 1.0f, 1e-6f);
  expectNear(g.mesh.positions[6], vec3(1, 1, 0));
  EXPECT_EQ(g.mesh.materialIds, (std::vector<uint32_t>{0, 0, 3, 3}));
  // Winding kept: the child's first triangle faces its normal.
  const vec3 a = g.mesh.positions[g.mesh.indices[0]], b = g.mesh.positions[g.mesh.indices[1]],
             c = g.mesh.positions[g.mesh.indices[2]];
  EXPECT_GT(glm::dot(glm::cross(b - a, c - a), vec3(1, 0, 0)), 0.0f);
}

TEST(Gltf, MaterialsMapOntoOurs) {
  const std::string buffer = quadBuffer();
  const GltfData g = loadGltf(writeGltf("quad.gltf", quadGltf(dataUri(buffer), buffer.size())));
  ASSERT_EQ(g.materials.size(), 4u);
  for (const Material& m : g.materials) EXPECT_EQ(m.type, Material::Type::Pbr) << m.name;
  expectNear(g.materials[0].albedo, vec3(0.5f, 0.25f, 1.0f));
  EXPECT_EQ(g.materials[0].metallic, 0.0f);
  expectNear(g.materials[1].albedo, vec3(1.0f, 0.8f, 0.3f));
  EXPECT_EQ(g.materials[1].metallic, 1.0f);
  EXPECT_NEAR(g.materials[1].roughness, 0.3f, 1e-6f);
  expectNear(g.materials[2].emission, vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(g.materials[2].metallic, 1.0f) << "glTF's default metallic factor is 1";
  EXPECT_EQ(g.materials[3].transmission, 1.0f);
  EXPECT_NEAR(g.materials[3].ior, 1.33f, 1e-6f);
  for (const Material& m : g.materials) EXPECT_FALSE(m.hasCutouts()) << m.name;
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
}

TEST(Gltf, CamerasFirstByNameOrFramed) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  const std::string path = writeGltf("quad.gltf", j);
  const Scene first = loadScene(path);
  expectNear(first.camera.eye, vec3(0, 1, 5));
  expectNear(first.camera.lookAt, vec3(0, 1, 4));
  EXPECT_NEAR(first.camera.vfovDegrees, 0.5f * 180.0f / 3.14159265f, 1e-3f);
  SceneLoadOptions byName;
  byName.camera = "lens";  // the camera's own name works as well as its node's
  expectNear(loadScene(path, byName).camera.eye, vec3(0, 1, 5));
  byName.camera = "nope";
  expectSceneError([&] { loadScene(path, byName); },
                   {"quad.gltf", "no camera named 'nope'", "there are: shot"});
  // An orthographic camera: its view is 2 ymag tall.
  j["cameras"][0] = {
      {"type", "orthographic"},
      {"orthographic", {{"xmag", 3.0}, {"ymag", 1.5}, {"znear", 0.1}, {"zfar", 50}}}};
  const Scene ortho = loadScene(writeGltf("ortho.gltf", j));
  EXPECT_FLOAT_EQ(ortho.camera.orthographicHeight, 3.0f);
  expectNear(ortho.camera.eye, vec3(0, 1, 5));
  j["cameras"][0]["orthographic"]["ymag"] = 0.0;
  const GltfData flat = loadGltf(writeGltf("flat.gltf", j));
  EXPECT_FALSE(flat.hasCamera);
  EXPECT_NE(allWarnings(flat).find("cameras[0]: an orthographic camera's ymag"), std::string::npos);

  j["nodes"][3].erase("camera");
  const Scene framed = loadScene(writeGltf("no_camera.gltf", j));
  EXPECT_GT(glm::length(framed.camera.eye - framed.camera.lookAt), 1.0f);
}

TEST(Gltf, BinaryContainerAndRelativeBuffer) {
  const std::string buffer = quadBuffer();
  // .glb: header, the JSON chunk (padded to 4 bytes), the BIN chunk.
  Json j = quadGltf("", buffer.size());
  j["buffers"][0].erase("uri");
  std::string json = j.dump();
  while (json.size() % 4) json += ' ';
  std::string glb = "glTF";
  append<uint32_t>(glb, {2, uint32_t(12 + 8 + json.size() + 8 + buffer.size())});
  append<uint32_t>(glb, {uint32_t(json.size()), 0x4E4F534Au});
  glb += json;
  append<uint32_t>(glb, {uint32_t(buffer.size()), 0x004E4942u});
  glb += buffer;
  EXPECT_EQ(loadGltf(writeFile("quad.glb", glb)).mesh.triangleCount(), 4u);

  writeFile("sub/quad.bin", buffer);
  EXPECT_EQ(loadGltf(writeGltf("sub/quad.gltf", quadGltf("quad.bin", buffer.size())))
                .mesh.triangleCount(),
            4u);
  // A file name with a space, percent-encoded in the URI as exporters write it: read, and the
  // file listed (for live reload) by its own name.
  const std::string spaced = writeFile("sub/my quad.bin", buffer);
  const GltfData g =
      loadGltf(writeGltf("sub/spaced.gltf", quadGltf("my%20quad.bin", buffer.size())));
  EXPECT_EQ(g.mesh.triangleCount(), 4u);
  ASSERT_EQ(g.files.size(), 1u);
  EXPECT_EQ(std::filesystem::path(g.files[0]), std::filesystem::path(spaced).lexically_normal());
}

TEST(Gltf, NetworkAndAbsoluteUrisAreRefused) {
  const std::string buffer = quadBuffer();
  expectSceneError(
      [&] { loadGltf(writeGltf("net.gltf", quadGltf("https://example.com/quad.bin", 140))); },
      {"net.gltf", "buffers[0].uri", "network location"});
  expectSceneError([&] { loadGltf(writeGltf("abs.gltf", quadGltf("/etc/quad.bin", 140))); },
                   {"abs.gltf", "buffers[0].uri", "absolute path"});
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", "ftp://example.com/a.png"}}};
  expectSceneError([&] { loadGltf(writeGltf("net_image.gltf", j)); },
                   {"images[0].uri", "network location"});
}

TEST(Gltf, DamagedFilesNameTheElement) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["accessors"][0]["count"] = 40;  // runs past its 48-byte view
  expectSceneError([&] { loadGltf(writeGltf("long.gltf", j)); },
                   {"long.gltf", "meshes[0].primitives[0].POSITION", "past the end"});
  j = quadGltf(dataUri(buffer), buffer.size());
  j["nodes"][1]["children"] = {0};  // a cycle
  expectSceneError([&] { loadGltf(writeGltf("cycle.gltf", j)); }, {"is its own ancestor"});
  j = quadGltf(dataUri(buffer), buffer.size());
  j["meshes"][0]["primitives"][0]["material"] = 9;
  expectSceneError([&] { loadGltf(writeGltf("material.gltf", j)); },
                   {"meshes[0].primitives[0].material", "material 9 does not exist"});
  j = quadGltf(dataUri(buffer), buffer.size());
  j["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 1;  // the normals: VEC3
  expectSceneError([&] { loadGltf(writeGltf("tangent.gltf", j)); },
                   {"meshes[0].primitives[0].TANGENT", "expected 4 VEC4 values"});
  // Every node lists the next one twice: 2^30 instances of the last from 31 nodes.
  j = quadGltf(dataUri(buffer), buffer.size());
  j["scenes"][0]["nodes"] = {4};
  for (int n = 4; n < 34; ++n) j["nodes"][size_t(n)] = {{"children", {n + 1, n + 1}}};
  j["nodes"][34] = {{"mesh", 0}};
  expectSceneError([&] { loadGltf(writeGltf("instances.gltf", j)); },
                   {"instances.gltf", "more than 1048576 node instances"});
  expectSceneError([&] { loadGltf(writeFile("junk.gltf", "{\"asset\": ")); }, {"junk.gltf"});
  expectSceneError([&] { loadGltf(writeFile("junk.glb", "glTF\x02")); },
                   {"junk.glb", "not a binary glTF file"});
}

// The unit quad quantised as KHR_mesh_quantization has it (gltfpack's output): positions as
// unsigned 16-bit integers, not normalised, scaled back by the node; normals as normalised
// bytes; uvs as normalised unsigned shorts; vertex colours as normalised RGBA bytes. Every
// attribute starts on a 4-byte boundary: positions (8-byte stride, 32 bytes), normals (16),
// uvs (16), colours (16), 16-bit indices (12).
std::string quantisedQuadBuffer() {
  std::string b;
  for (const uint16_t v : {0, 0, 0, 100, 0, 0, 100, 100, 0, 0, 100, 0}) {
    append<uint16_t>(b, {v});
    if (b.size() % 8 == 6) append<uint16_t>(b, {0});
  }
  for (int v = 0; v < 4; ++v) append<int8_t>(b, {0, 0, 127, 0});
  append<uint16_t>(b, {0, 65535, 65535, 65535, 65535, 0, 0, 0});
  append<uint8_t>(b, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128, 51, 102, 255, 0});
  append<uint16_t>(b, {0, 1, 2, 0, 2, 3});
  return b;
}

Json quantisedQuadGltf(const std::string& buffer) {
  Json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"scale", {0.01, 0.01, 0.01}}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}, {"COLOR_0", 3}}},
            {"indices", 4}},
           {{"attributes", {{"POSITION", 0}}}, {"indices", 4}}}}}}},
      {"buffers", {{{"uri", dataUri(buffer)}, {"byteLength", buffer.size()}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 32}, {"byteStride", 8}},
        {{"buffer", 0}, {"byteOffset", 32}, {"byteLength", 16}, {"byteStride", 4}},
        {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 16}},
        {{"buffer", 0}, {"byteOffset", 64}, {"byteLength", 16}},
        {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5123},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {100, 100, 0}}},
        {{"bufferView", 1},
         {"componentType", 5120},
         {"normalized", true},
         {"count", 4},
         {"type", "VEC3"}},
        {{"bufferView", 2},
         {"componentType", 5123},
         {"normalized", true},
         {"count", 4},
         {"type", "VEC2"}},
        {{"bufferView", 3},
         {"componentType", 5121},
         {"normalized", true},
         {"count", 4},
         {"type", "VEC4"}},
        {{"bufferView", 4}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
      {"extensionsUsed", {"KHR_mesh_quantization"}},
      {"extensionsRequired", {"KHR_mesh_quantization"}}};
  return j;
}

TEST(Gltf, QuantisedAttributesAndVertexColoursAreRead) {
  const std::string buffer = quantisedQuadBuffer();
  ASSERT_EQ(buffer.size(), 92u);
  const GltfData g = loadGltf(writeGltf("quantised.gltf", quantisedQuadGltf(buffer)));
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
  ASSERT_EQ(g.mesh.vertexCount, 8u);
  expectNear(g.mesh.positions[1], vec3(1, 0, 0));
  expectNear(g.mesh.positions[2], vec3(1, 1, 0));
  expectNear(g.mesh.positions[6], vec3(1, 1, 0));
  expectNear(g.mesh.normals[0], vec3(0, 0, 1));
  EXPECT_NEAR(g.mesh.uvs[0].y, 0.0f, 1e-6f);  // glTF's (0, 1): ours (0, 0)
  EXPECT_NEAR(g.mesh.uvs[1].x, 1.0f, 1e-6f);
  EXPECT_NEAR(g.mesh.uvs[2].y, 1.0f, 1e-6f);
  // Colours are linear (no sRGB decode); their alpha is not read. The second primitive has
  // none: white.
  ASSERT_EQ(g.mesh.colors.size(), 8u);
  expectNear(g.mesh.colors[0], vec3(1, 0, 0));
  expectNear(g.mesh.colors[2], vec3(0, 0, 1));
  expectNear(g.mesh.colors[3], vec3(0.2f, 0.4f, 1.0f));
  for (size_t v = 4; v < 8; ++v) expectNear(g.mesh.colors[v], vec3(1.0f));
  // A mesh without colours keeps none (white, at no cost).
  const std::string plain = quadBuffer();
  EXPECT_TRUE(loadGltf(writeGltf("plain.gltf", quadGltf(dataUri(plain), plain.size())))
                  .mesh.colors.empty());
  // COLOR_0 must be VEC3 or VEC4.
  Json j = quantisedQuadGltf(buffer);
  j["accessors"][3]["type"] = "VEC2";
  j["accessors"][3]["count"] = 4;
  expectSceneError([&] { loadGltf(writeGltf("colour.gltf", j)); },
                   {"colour.gltf", "COLOR_0", "VEC3 or VEC4"});
}

// Sparse accessors: the listed elements replace the base's, or zeros where the accessor has no
// buffer view; damaged ones are errors naming the accessor.
TEST(Gltf, TangentsAreReadMovedByTheNodesAndGeneratedWhereMissing) {
  std::string buffer = quadBuffer();
  const size_t offset = buffer.size();
  append<float>(buffer, {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, -1});
  Json j = quadGltf("", 0);
  j["buffers"][0] = {{"uri", dataUri(buffer)}, {"byteLength", buffer.size()}};
  j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", 64}});
  j["accessors"].push_back(
      {{"bufferView", 4}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
  j["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 4;
  // A third instance, mirrored in x.
  j["nodes"].push_back({{"name", "mirror"}, {"mesh", 0}, {"scale", {-1, 1, 1}}});
  j["scenes"][0]["nodes"].push_back(4);
  const GltfData g = loadGltf(writeGltf("tangents.gltf", j));
  ASSERT_EQ(g.mesh.tangents.size(), 12u);
  // The child is turned +90 degrees about y (x -> -z) and scaled by 2: the tangent turns, stays
  // a unit vector and keeps its side.
  expectNear(vec3(g.mesh.tangents[0]), vec3(0, 0, -1));
  EXPECT_EQ(g.mesh.tangents[0].w, 1.0f);
  expectNear(vec3(g.mesh.tangents[3]), vec3(0, 1, 0));
  EXPECT_EQ(g.mesh.tangents[3].w, -1.0f);
  // The plain instance has none in the file.
  EXPECT_EQ(g.mesh.tangents[4], glm::vec4(0.0f));
  // The mirror turns x around and the side with it.
  EXPECT_EQ(g.mesh.tangents[8], glm::vec4(-1, 0, 0, -1));
  EXPECT_EQ(g.mesh.tangents[11], glm::vec4(0, 1, 0, 1));

  // Normal-mapped, the plain instance (with uvs now) gets generated tangents: +u runs along
  // +x, +v (up the image) along +y. The file's stay as they are.
  j["images"] = {{{"uri", pngUri(1, 1, 3, {128, 128, 255})}}};
  j["textures"] = {{{"source", 0}}};
  j["materials"][0]["normalTexture"] = {{"index", 0}};
  j["meshes"][1]["primitives"][0]["material"] = 0;
  j["meshes"][1]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
  const Scene scene = loadScene(writeGltf("mapped.gltf", j));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.tangents[0], g.mesh.tangents[0]);
  for (uint32_t v = 4; v < 8; ++v) {
    expectNear(vec3(mesh.tangents[v]), vec3(1, 0, 0));
    EXPECT_EQ(mesh.tangents[v].w, 1.0f) << v;
  }
}

TEST(Gltf, SparseAccessorsReplaceTheListedElements) {
  std::string buffer = quadBuffer();          // 140 bytes
  append<uint8_t>(buffer, {2, 0, 0, 0});      // 140: one index, padded
  append<float>(buffer, {0.25f, 0.75f});      // 144: its uv
  append<uint16_t>(buffer, {1, 3});           // 152: two indices
  append<float>(buffer, {0.5f, 0.5f, 1, 0});  // 156: their uvs
  append<uint16_t>(buffer, {3, 1});           // 172: two indices out of order
  ASSERT_EQ(buffer.size(), 176u);
  Json j = quadGltf(dataUri(buffer), buffer.size());
  for (auto [offset, length] : {std::pair{140, 1}, {144, 8}, {152, 4}, {156, 16}, {172, 4}})
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
  j["accessors"][2]["sparse"] = {{"count", 1},
                                 {"indices", {{"bufferView", 4}, {"componentType", 5121}}},
                                 {"values", {{"bufferView", 5}}}};
  const GltfData g = loadGltf(writeGltf("sparse.gltf", j));
  ASSERT_GE(g.mesh.uvs.size(), 4u);
  // glTF's v runs down: ours is 1 - v.
  EXPECT_NEAR(g.mesh.uvs[1].x, 1.0f, 1e-6f);  // the base's
  EXPECT_NEAR(g.mesh.uvs[2].x, 0.25f, 1e-6f);
  EXPECT_NEAR(g.mesh.uvs[2].y, 0.25f, 1e-6f);
  EXPECT_NEAR(g.mesh.uvs[3].y, 1.0f, 1e-6f);  // the base's (0, 0)

  // No buffer view: zeros but for the listed elements.
  Json zeros = j;
  zeros["accessors"][2].erase("bufferView");
  zeros["accessors"][2]["sparse"] = {{"count", 2},
                                     {"indices", {{"bufferView", 6}, {"componentType", 5123}}},
                                     {"values", {{"bufferView", 7}}}};
  const GltfData z = loadGltf(writeGltf("zeros.gltf", zeros));
  ASSERT_GE(z.mesh.uvs.size(), 4u);
  EXPECT_NEAR(z.mesh.uvs[0].x, 0.0f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[0].y, 1.0f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[1].x, 0.5f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[1].y, 0.5f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[2].x, 0.0f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[3].x, 1.0f, 1e-6f);
  EXPECT_NEAR(z.mesh.uvs[3].y, 1.0f, 1e-6f);

  // Damaged: an index past the count, indices out of order, too many, values past their view,
  // a signed index type.
  auto damaged = [&](const std::string& name, const std::function<void(Json&)>& edit,
                     std::initializer_list<std::string> parts) {
    Json d = zeros;
    edit(d);
    expectSceneError([&] { loadGltf(writeGltf(name, d)); }, parts);
  };
  damaged("past.gltf", [](Json& d) { d["accessors"][2]["count"] = 3; },
          {"past.gltf", "accessors[2]", "sparse index 3"});
  damaged("order.gltf", [](Json& d) { d["accessors"][2]["sparse"]["indices"]["bufferView"] = 8; },
          {"order.gltf", "accessors[2]", "strictly increasing"});
  damaged("many.gltf", [](Json& d) { d["accessors"][2]["sparse"]["count"] = 5; },
          {"many.gltf", "accessors[2]", "sparse count 5"});
  damaged("values.gltf", [](Json& d) { d["bufferViews"][7]["byteLength"] = 12; },
          {"values.gltf", "accessors[2]", "sparse values run past"});
  damaged("type.gltf",
          [](Json& d) { d["accessors"][2]["sparse"]["indices"]["componentType"] = 5122; },
          {"type.gltf", "accessors[2]", "unsigned"});
}

TEST(Gltf, PunctualLightsArePlacedByTheirNodes) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  const double s = std::sqrt(0.5);
  j["nodes"].push_back({{"name", "bulb"},
                        {"translation", {1, 2, 3}},
                        {"scale", {2, 2, 2}},  // moves nothing, and leaves the range as it is
                        {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // Turned -90 degrees about x: its -z (where a spot shines) points down, -y.
  j["nodes"].push_back({{"translation", {0, 4, 0}},
                        {"rotation", {-s, 0, 0, s}},
                        {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  j["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  j["scenes"][0]["nodes"] = {0, 2, 3, 4, 5, 6};
  j["extensionsUsed"].push_back("KHR_lights_punctual");
  j["extensions"] = {
      {"KHR_lights_punctual",
       {{"lights",
         {{{"type", "point"}, {"intensity", 10.0}, {"color", {1.0, 0.5, 0.25}}, {"range", 4.0}},
          {{"type", "spot"},
           {"intensity", 2.0},
           {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
          {{"type", "directional"}, {"intensity", 3.0}, {"range", 5.0}}}}}}};
  const GltfData g = loadGltf(writeGltf("lights.gltf", j));
  ASSERT_EQ(g.lights.size(), 3u);
  EXPECT_EQ(g.lights[0].kind, PunctualLight::Kind::Point);
  expectNear(g.lights[0].position, vec3(1, 2, 3));
  expectNear(g.lights[0].intensity, vec3(10, 5, 2.5));
  EXPECT_EQ(g.lights[1].kind, PunctualLight::Kind::Spot);
  expectNear(g.lights[1].position, vec3(0, 4, 0));
  expectNear(g.lights[1].direction, vec3(0, -1, 0));
  EXPECT_NEAR(g.lights[1].cosInner, std::cos(0.2f), 1e-6f);
  EXPECT_NEAR(g.lights[1].cosOuter, std::cos(0.4f), 1e-6f);
  EXPECT_EQ(g.lights[2].kind, PunctualLight::Kind::Directional);
  expectNear(g.lights[2].direction, vec3(0, 0, -1));
  // The point light's range is read; the spot has none, and a directional light's means nothing.
  EXPECT_EQ(g.lights[0].range, 4.0f);
  EXPECT_EQ(g.lights[1].range, 0.0f);
  EXPECT_EQ(g.lights[2].range, 0.0f);
  EXPECT_TRUE(g.warnings.empty()) << g.warnings[0];
  // They reach the scene, and a light that does not exist is an error naming the node.
  EXPECT_EQ(loadScene(writeGltf("lights_scene.gltf", j)).lights.size(), 3u);
  j["nodes"][6]["extensions"]["KHR_lights_punctual"]["light"] = 7;
  expectSceneError([&] { loadGltf(writeGltf("bad_light.gltf", j)); },
                   {"bad_light.gltf", "nodes[6]", "light 7 does not exist"});
}

// The quad file with one animation on node "plain" (node 2): keyframe times and values of a
// translation and/or a rotation channel.
Json animatedQuad(const std::string& buffer, const std::vector<float>& times,
                  const std::vector<float>& translations, const std::vector<float>& rotations,
                  const std::string& interpolation = "LINEAR") {
  std::string animationBytes;
  for (float t : times) append<float>(animationBytes, {t});
  const size_t timesBytes = animationBytes.size();
  for (float v : translations) append<float>(animationBytes, {v});
  const size_t translationBytes = animationBytes.size() - timesBytes;
  for (float v : rotations) append<float>(animationBytes, {v});
  const size_t rotationBytes = animationBytes.size() - timesBytes - translationBytes;
  const std::string all = buffer + animationBytes;
  Json j = quadGltf(dataUri(all), all.size());
  const size_t at = buffer.size();
  const size_t keys = times.size();
  j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", timesBytes}});
  j["accessors"].push_back({{"bufferView", 4},
                            {"componentType", 5126},
                            {"count", keys},
                            {"type", "SCALAR"},
                            {"min", {times.front()}},
                            {"max", {times.back()}}});
  Json animation = {{"name", "move"}, {"channels", Json::array()}, {"samplers", Json::array()}};
  if (translationBytes) {
    j["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", at + timesBytes}, {"byteLength", translationBytes}});
    j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1},
                              {"componentType", 5126},
                              {"count", translations.size() / 3},
                              {"type", "VEC3"}});
    animation["samplers"].push_back(
        {{"input", 4}, {"output", j["accessors"].size() - 1}, {"interpolation", interpolation}});
    animation["channels"].push_back({{"sampler", animation["samplers"].size() - 1},
                                     {"target", {{"node", 2}, {"path", "translation"}}}});
  }
  if (rotationBytes) {
    j["bufferViews"].push_back({{"buffer", 0},
                                {"byteOffset", at + timesBytes + translationBytes},
                                {"byteLength", rotationBytes}});
    j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1},
                              {"componentType", 5126},
                              {"count", rotations.size() / 4},
                              {"type", "VEC4"}});
    animation["samplers"].push_back(
        {{"input", 4}, {"output", j["accessors"].size() - 1}, {"interpolation", interpolation}});
    animation["channels"].push_back({{"sampler", animation["samplers"].size() - 1},
                                     {"target", {{"node", 2}, {"path", "rotation"}}}});
  }
  j["animations"] = {animation};
  return j;
}

TEST(Gltf, AnimationBecomesMotionBlurOverTheShutter) {
  const std::string buffer = quadBuffer();
  // A straight move from x = 0 at t = 1 s to x = 4 at t = 3 s: two time steps.
  Json j = animatedQuad(buffer, {1, 3}, {0, 0, 0, 4, 0, 0}, {});
  GltfOptions options;
  options.shutterSeconds = 0.5;
  GltfData g = loadGltf(writeGltf("move.gltf", j), options);
  EXPECT_EQ(g.frameTime, 1.0) << "the frame time defaults to the animation's start";
  EXPECT_EQ(g.mesh.vertexCount, 4u) << "the still instance stays in the static mesh";
  ASSERT_EQ(g.animatedMeshes.size(), 1u);
  const Mesh& moving = g.animatedMeshes[0];
  ASSERT_EQ(moving.timeSteps, 2);
  ASSERT_EQ(moving.vertexCount, 4u);
  // Vertex 1 is (1, 0, 0) in the quad: at 1 s it is there, at 1.5 s moved by 1.
  expectNear(moving.positions[1], vec3(1, 0, 0));
  expectNear(moving.positions[4 + 1], vec3(2, 0, 0));
  // A later frame time, and the shutter closed: the node where it is then, not moving.
  options.frameTime = 2.0;
  options.shutterSeconds = 0.0;
  g = loadGltf(writeGltf("move.gltf", j), options);
  EXPECT_TRUE(g.animatedMeshes.empty());
  expectNear(g.mesh.positions[4 + 1], vec3(3, 0, 0));
  // Included in a JSON scene (no animation): at its start, with a warning.
  options = GltfOptions();
  options.animate = false;
  g = loadGltf(writeGltf("move.gltf", j), options);
  EXPECT_TRUE(g.animatedMeshes.empty());
  ASSERT_EQ(g.warnings.size(), 1u);
  EXPECT_NE(g.warnings[0].find("without motion blur"), std::string::npos) << g.warnings[0];

  // A full turn about z during the shutter needs many steps; a step channel holds its value.
  const double s = std::sqrt(0.5);
  const std::vector<float> turn = {0, 0, 0, 1, 0,        0,         float(s), float(s), 0, 0,
                                   1, 0, 0, 0, float(s), -float(s), 0,        0,        0, -1};
  j = animatedQuad(buffer, {0, 1, 2, 3, 4}, {}, turn);
  options = GltfOptions();
  options.shutterSeconds = 4.0;
  g = loadGltf(writeGltf("turn.gltf", j), options);
  ASSERT_EQ(g.animatedMeshes.size(), 1u);
  EXPECT_GE(g.animatedMeshes[0].timeSteps, 65) << "a turn is followed closely";
  const Mesh& turning = g.animatedMeshes[0];
  const size_t half = size_t(turning.timeSteps - 1) / 2 * turning.vertexCount;
  expectNear(turning.positions[half + 1], vec3(-1, 0, 0));  // half a turn at 2 s
  j = animatedQuad(buffer, {0, 1}, {0, 0, 0, 4, 0, 0}, {}, "STEP");
  options.shutterSeconds = 0.5;
  g = loadGltf(writeGltf("step.gltf", j), options);
  EXPECT_TRUE(g.animatedMeshes.empty()) << "a step channel does not move between its keys";

  // Scenes loaded with options: the moving quad is a mesh of its own.
  SceneLoadOptions load;
  load.shutterSeconds = 0.5;
  const Scene scene = loadScene(
      writeGltf("move_scene.gltf", animatedQuad(buffer, {1, 3}, {0, 0, 0, 4, 0, 0}, {})), load);
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[1].timeSteps, 2);
}

TEST(Gltf, DamagedAnimationsNameTheElement) {
  const std::string buffer = quadBuffer();
  expectSceneError(
      [&] {
        loadGltf(writeGltf("back.gltf", animatedQuad(buffer, {2, 1}, {0, 0, 0, 4, 0, 0}, {})));
      },
      {"back.gltf", "animations[0].channels[0].input", "not finite and after the one before"});
  Json j = animatedQuad(buffer, {0, 1}, {0, 0, 0, 4, 0, 0}, {});
  j["animations"][0]["channels"][0]["target"]["node"] = 12;
  expectSceneError([&] { loadGltf(writeGltf("node.gltf", j)); },
                   {"animations[0].channels[0].target.node", "node 12 does not exist"});
  j = animatedQuad(buffer, {0, 1}, {0, 0, 0, 4, 0, 0}, {});
  j["accessors"][5]["count"] = 1;
  expectSceneError([&] { loadGltf(writeGltf("count.gltf", j)); },
                   {"animations[0].channels[0].output", "expected 2 VEC3 values"});
}

TEST(Gltf, FeaturesNotRenderedAreNamedInWarnings) {
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["images"] = {{{"uri", pngUri(1, 1, 3, {128, 128, 255})}}};
  j["textures"] = {{{"source", 0}}};
  j["materials"][0]["occlusionTexture"] = {{"index", 0}};
  j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  j["materials"][1]["normalTexture"] = {{"index", 0}, {"texCoord", 1}};
  j["extensionsUsed"].push_back("KHR_materials_dispersion");
  const GltfData g = loadGltf(writeGltf("features.gltf", j));
  const std::string all = allWarnings(g);
  for (const char* part : {"materials[0]: occlusionTexture is ignored",
                           "materials[1].normalTexture: uv set 1 is not read; uv set 0 is "
                           "used (materials[1].baseColorTexture's",
                           "extension KHR_materials_dispersion is not supported"})
    EXPECT_NE(all.find(part), std::string::npos) << "'" << part << "' not in:\n" << all;
}

TEST(Gltf, AMaterialsTexturesAreReadInTheUvSetTheyName) {
  // The quad's TEXCOORD_1 reads the normals' floats as pairs: (0, 0), (1, 0), (0, 1), (0, 0).
  const std::string buffer = quadBuffer();
  Json j = quadGltf(dataUri(buffer), buffer.size());
  j["accessors"].push_back(
      {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 4;
  j["images"] = {{{"uri", pngUri(1, 1, 3, {128, 128, 255})}}};
  j["textures"] = {{{"source", 0}}};
  const auto uvsOf = [&](const Json& file) {
    const GltfData g = loadGltf(writeGltf("uvs.gltf", file));
    EXPECT_EQ(allWarnings(g).find("uv set"), std::string::npos) << allWarnings(g);
    return std::vector<vec2>(g.mesh.uvs.begin(), g.mesh.uvs.begin() + 4);
  };
  // Without textures, and with textures on set 0: TEXCOORD_0, v flipped.
  const std::vector<vec2> first{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_EQ(uvsOf(j), first);
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  EXPECT_EQ(uvsOf(j), first);
  // Every texture on set 1 (the reference's texCoord or its transform's): TEXCOORD_1.
  const std::vector<vec2> second{{0, 1}, {1, 1}, {0, 0}, {0, 1}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
  j["materials"][0]["normalTexture"] = {{"index", 0}, {"texCoord", 1}};
  EXPECT_EQ(uvsOf(j), second);
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
      {"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}};
  j["extensionsUsed"].push_back("KHR_texture_transform");
  EXPECT_EQ(uvsOf(j), second);
}

TEST(Gltf, JsonScenesIncludeGltfFilesWithATransformAndAMaterial) {
  const std::string buffer = quadBuffer();
  writeGltf("include/quad.gltf", quadGltf(dataUri(buffer), buffer.size()));
  const std::string scenePath = writeFile("include/scene.json",
                                          R"({"camera": {"eye": [0, 0, 10], "look_at": [0, 0, 0]},
          "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
          "objects": [
            {"shape": "mesh", "file": "quad.gltf", "transform": {"translate": [0, 5, 0]}},
            {"shape": "mesh", "file": "quad.gltf", "material": "white"}]})");
  const Scene scene = loadScene(scenePath);
  ASSERT_EQ(scene.meshes.size(), 2u);
  // The file's own materials come along with the first; the second uses "white" throughout.
  EXPECT_EQ(scene.materials.size(), 1u + 4u);
  expectNear(scene.meshes[0].positions[4], vec3(0, 5, 0));
  for (uint32_t id : scene.meshes[1].materialIds) EXPECT_EQ(scene.materials[id].name, "white");
}

TEST(Gltf, IncludedFilesMaterialsCanBeOverriddenOneByOne) {
  const std::string buffer = quadBuffer();
  writeGltf("quad.gltf", quadGltf(dataUri(buffer), buffer.size()));
  const std::string scenePath = writeFile("scene.json", R"({
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "objects": [{"shape": "mesh", "file": "quad.gltf",
                   "material_overrides": {"paint": "white"}}]})");
  const Scene scene = loadScene(scenePath);
  // The child's triangles used "paint" and now use "white"; the plain instance keeps "glass".
  ASSERT_EQ(scene.meshes[0].materialIds.size(), 4u);
  EXPECT_EQ(scene.materials[scene.meshes[0].materialIds[0]].name, "white");
  EXPECT_EQ(scene.materials[scene.meshes[0].materialIds[2]].name, "glass");

  const std::string bad = writeFile("bad.json", R"({
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "objects": [{"shape": "mesh", "file": "quad.gltf",
                   "material_overrides": {"varnish": "white"}}]})");
  expectSceneError([&] { loadScene(bad); },
                   {"bad.json", "objects[0].material_overrides.varnish",
                    "the file has no material 'varnish' (it has: paint, gold, lamp, glass"});
  const std::string both = writeFile("both.json", R"({
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "objects": [{"shape": "mesh", "file": "quad.gltf", "material": "white",
                   "material_overrides": {"paint": "white"}}]})");
  expectSceneError([&] { loadScene(both); }, {"objects[0].material_overrides", "not both"});
}

}  // namespace
}  // namespace penumbra
