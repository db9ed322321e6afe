// Tests for engine/scene/gltf_compression: Draco-compressed primitives and meshopt-compressed
// buffer views load as the same triangles as the uncompressed file, in .glb and .gltf files;
// corrupt compressed data is an error naming the file and the element.
#include "scene/gltf_compression.h"
#include "scene/gltf_io.h"
#include "tests/engine/scene/draco_encode.h"
#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

// A .glb of `json` with `bin` as its binary chunk.
std::string glb(const Json& json, const std::string& bin) {
  std::string text = json.dump();
  while (text.size() % 4 != 0) text += ' ';
  std::string body = bin;
  while (body.size() % 4 != 0) body += '\0';
  std::string out = "glTF";
  append<uint32_t>(out, {2u, uint32_t(12 + 8 + text.size() + 8 + body.size())});
  append<uint32_t>(out, {uint32_t(text.size()), 0x4E4F534Au});
  out += text;
  append<uint32_t>(out, {uint32_t(body.size()), 0x004E4942u});
  return out + body;
}

// The mesh's triangles as rounded (position, uv) corners, each triangle turned to start at its
// smallest corner (winding kept) and the triangles sorted: equal for the same triangles in any
// order and vertex numbering.
using GridCorner = std::array<long, 5>;
std::vector<std::array<GridCorner, 3>> triangles(const Mesh& mesh) {
  std::vector<std::array<GridCorner, 3>> out;
  auto round = [](float v) { return std::lround(double(v) * 1000.0); };
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    std::array<GridCorner, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = mesh.indices[3 * t + size_t(k)];
      const vec3 p = mesh.positions[i];
      const vec2 uv = mesh.uvs.empty() ? vec2(0.0f) : mesh.uvs[i];
      tri[size_t(k)] = {round(p.x), round(p.y), round(p.z), round(uv.x), round(uv.y)};
    }
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A 4 x 4 grid of quads in the xy plane (z = 0.25 x y), uv = (x, y) / 4, as 32 triangles.
struct Grid {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 2>> uvs;
  std::vector<uint32_t> indices;
};
Grid grid() {
  Grid g;
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 4; ++x) {
      g.positions.push_back({float(x), float(y), 0.25f * float(x * y)});
      g.uvs.push_back({float(x) / 4, float(y) / 4});
    }
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      const uint32_t a = y * 5 + x;
      g.indices.insert(g.indices.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
    }
  return g;
}

// The glTF JSON of one primitive drawing the grid with accessors 0 (positions), 1 (uvs) and 2
// (indices).
Json gridJson(size_t points, size_t indices) {
  return {{"asset", {{"version", "2.0"}}},
          {"scenes", {{{"nodes", {0}}}}},
          {"nodes", {{{"mesh", 0}}}},
          {"meshes",
           {{{"primitives",
              {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}}}}}}},
          {"accessors",
           {{{"componentType", 5126}, {"count", points}, {"type", "VEC3"}},
            {{"componentType", 5126}, {"count", points}, {"type", "VEC2"}},
            {{"componentType", 5125}, {"count", indices}, {"type", "SCALAR"}}}}};
}

// The grid uncompressed, as a .glb.
std::string plainGridGlb() {
  const Grid g = grid();
  std::string bin;
  for (const auto& p : g.positions) append<float>(bin, {p[0], p[1], p[2]});
  for (const auto& uv : g.uvs) append<float>(bin, {uv[0], uv[1]});
  for (uint32_t i : g.indices) append<uint32_t>(bin, {i});
  Json j = gridJson(g.positions.size(), g.indices.size());
  const size_t p = g.positions.size() * 12, u = g.uvs.size() * 8, n = g.indices.size() * 4;
  j["buffers"] = {{{"byteLength", bin.size()}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", p}},
                      {{"buffer", 0}, {"byteOffset", p}, {"byteLength", u}},
                      {{"buffer", 0}, {"byteOffset", p + u}, {"byteLength", n}}};
  for (int a = 0; a < 3; ++a) j["accessors"][size_t(a)]["bufferView"] = a;
  return glb(j, bin);
}

using DracoGrid = test::DracoEncoded;
DracoGrid dracoGrid() {
  const Grid g = grid();
  DracoGrid d = test::encodeDraco(g.positions, g.uvs, g.indices);
  EXPECT_FALSE(d.bytes.empty());
  EXPECT_EQ(d.faces, 32u);
  return d;
}

Json dracoGridJson(const DracoGrid& d) {
  Json j = gridJson(d.points, d.faces * 3);
  j["buffers"] = {{{"byteLength", d.bytes.size()}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", d.bytes.size()}}};
  j["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression",
       {{"bufferView", 0}, {"attributes", {{"POSITION", d.positionId}, {"TEXCOORD_0", d.uvId}}}}}};
  j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return j;
}

TEST(GltfCompression, DracoPrimitivesLoadAsTheSameTriangles) {
  const GltfData plain = loadGltf(writeFile("plain.glb", plainGridGlb()));
  ASSERT_EQ(plain.mesh.triangleCount(), 32u);
  const DracoGrid d = dracoGrid();
  const Json j = dracoGridJson(d);
  const GltfData fromGlb = loadGltf(writeFile("draco.glb", glb(j, d.bytes)));
  EXPECT_EQ(triangles(fromGlb.mesh), triangles(plain.mesh));
  EXPECT_TRUE(fromGlb.warnings.empty()) << fromGlb.warnings.front();
  // The same in a .gltf whose buffer is a data: URI.
  Json text = j;
  text["buffers"][0]["uri"] = dataUri(d.bytes);
  EXPECT_EQ(triangles(loadGltf(writeGltf("draco.gltf", text)).mesh), triangles(plain.mesh));
}

TEST(GltfCompression, CorruptDracoDataIsAnErrorNamingThePrimitive) {
  DracoGrid d = dracoGrid();
  Json j = dracoGridJson(d);
  std::string broken = d.bytes;
  for (size_t i = broken.size() / 3; i < broken.size(); ++i) broken[i] = char(0x5a ^ i);
  expectSceneError([&] { loadGltf(writeFile("broken.glb", glb(j, broken))); },
                   {"broken.glb", "meshes[0].primitives[0]", "KHR_draco_mesh_compression"});
  // Accessors that do not count what the Draco mesh holds.
  j["accessors"][0]["count"] = d.points + 1;
  expectSceneError([&] { loadGltf(writeFile("count.glb", glb(j, d.bytes))); },
                   {"count.glb", "meshes[0].primitives[0]", "POSITION", "points"});
}

// The quad of gltf_test_files.h with every buffer view meshopt-compressed: the compressed
// streams in buffer 0 (`data`), the views in fallback buffer 1, which has no data.
Json meshoptQuad(std::string& data) {
  const std::string plain = quadBuffer();
  Json j = quadGltf("", plain.size());
  struct View {
    size_t offset, count, stride;
    const char* mode;
  };
  const View views[] = {{0, 4, 12, "ATTRIBUTES"},
                        {48, 4, 12, "ATTRIBUTES"},
                        {96, 4, 8, "ATTRIBUTES"},
                        {128, 6, 2, "TRIANGLES"}};
  data.clear();
  for (size_t v = 0; v < 4; ++v) {
    const View& view = views[v];
    std::vector<unsigned char> out;
    if (std::string(view.mode) == "TRIANGLES") {
      std::vector<unsigned int> indices(view.count);
      for (size_t i = 0; i < view.count; ++i)
        indices[i] = uint16_t(uint8_t(plain[view.offset + 2 * i]) |
                              uint8_t(plain[view.offset + 2 * i + 1]) << 8);
      out.resize(meshopt_encodeIndexBufferBound(view.count, 4));
      out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), view.count));
    } else {
      out.resize(meshopt_encodeVertexBufferBound(view.count, view.stride));
      out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), plain.data() + view.offset,
                                            view.count, view.stride));
    }
    j["bufferViews"][v]["buffer"] = 1;
    j["bufferViews"][v]["extensions"] = {{"EXT_meshopt_compression",
                                          {{"buffer", 0},
                                           {"byteOffset", data.size()},
                                           {"byteLength", out.size()},
                                           {"byteStride", view.stride},
                                           {"count", view.count},
                                           {"mode", view.mode}}}};
    data.append(out.begin(), out.end());
    while (data.size() % 4 != 0) data += '\0';
  }
  j["buffers"] = {{{"byteLength", data.size()}},
                  {{"byteLength", plain.size()},
                   {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  j["extensionsUsed"].push_back("EXT_meshopt_compression");
  j["extensionsRequired"] = {"EXT_meshopt_compression"};
  return j;
}

TEST(GltfCompression, MeshoptBufferViewsLoadAsTheSameTriangles) {
  const std::string plain = quadBuffer();
  const GltfData expected =
      loadGltf(writeGltf("plain.gltf", quadGltf(dataUri(plain), plain.size())));
  std::string data;
  Json j = meshoptQuad(data);
  const GltfData fromGlb = loadGltf(writeFile("meshopt.glb", glb(j, data)));
  EXPECT_EQ(fromGlb.mesh.positions, expected.mesh.positions);
  EXPECT_EQ(fromGlb.mesh.normals, expected.mesh.normals);
  EXPECT_EQ(fromGlb.mesh.uvs, expected.mesh.uvs);
  EXPECT_EQ(fromGlb.mesh.indices, expected.mesh.indices);
  EXPECT_EQ(fromGlb.mesh.triangleCount(), 4u);
  // In a .gltf the compressed streams are a data: URI and the fallback has none either.
  j["buffers"][0]["uri"] = dataUri(data);
  const GltfData fromText = loadGltf(writeGltf("meshopt.gltf", j));
  EXPECT_EQ(fromText.mesh.positions, expected.mesh.positions);
  EXPECT_EQ(fromText.mesh.indices, expected.mesh.indices);
}

TEST(GltfCompression, CorruptMeshoptDataIsAnErrorNamingTheBufferView) {
  std::string data;
  Json j = meshoptQuad(data);
  const size_t at = j["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["byteOffset"];
  data[at] = char(0x7f);  // not the vertex stream's header byte
  expectSceneError([&] { loadGltf(writeFile("broken.glb", glb(j, data))); },
                   {"broken.glb", "bufferViews[2]", "do not decode"});
  j["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["mode"] = "POINTS";
  expectSceneError([&] { loadGltf(writeFile("mode.glb", glb(j, data))); },
                   {"mode.glb", "bufferViews[1]", "unknown mode 'POINTS'"});
}

TEST(GltfCompression, ACompressionOnlyUsedReadsTheUncompressedData) {
  // A file that names the extensions but compresses nothing (or keeps its uncompressed data)
  // loads as it is, without a warning.
  const std::string plain = quadBuffer();
  Json j = quadGltf(dataUri(plain), plain.size());
  for (const char* e : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    j["extensionsUsed"].push_back(e);
    j["extensionsRequired"].push_back(e);
  }
  const GltfData g = loadGltf(writeGltf("used.gltf", j));
  EXPECT_EQ(g.mesh.triangleCount(), 4u);
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
}

}  // namespace
}  // namespace penumbra
