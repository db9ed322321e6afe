// Small glTF files for the glTF reader's tests (gltf_io_test.cpp, gltf_textures_test.cpp):
// base64 and data: URIs, a unit quad's buffer and JSON, a PNG as a data: URI, and files written
// under a folder of the running test's own.
#pragma once

#include "core/image_io.h"
#include "tests/base64.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

namespace penumbra::gltf_test {

using Json = nlohmann::json;

using test::base64;

template <typename T>
inline void append(std::string& bytes, std::initializer_list<T> values) {
  for (T v : values) bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// A unit quad in the xy plane (normal +z), two triangles, uvs, 16-bit indices: the buffer
// holds positions (48 bytes), normals (48), uvs (32), indices (12).
inline std::string quadBuffer() {
  std::string b;
  append<float>(b, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  append<float>(b, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  append<float>(b, {0, 1, 1, 1, 1, 0, 0, 0});
  append<uint16_t>(b, {0, 1, 2, 0, 2, 3});
  return b;
}

// The glTF JSON of the quad, drawn twice: a parent node (translated by (10, 0, 0)) holding a
// child turned 90 degrees about +y and scaled by 2, and a second, untransformed instance; a
// camera node; four materials. `bufferUri` is where the buffer lives.
inline Json quadGltf(const std::string& bufferUri, size_t bufferBytes) {
  const double s = std::sqrt(0.5);
  Json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 2, 3}}}}},
      {"nodes",
       {{{"name", "parent"}, {"translation", {10, 0, 0}}, {"children", {1}}},
        {{"name", "child"}, {"mesh", 0}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}},
        {{"name", "plain"}, {"mesh", 1}},
        {{"name", "shot"}, {"camera", 0}, {"translation", {0, 1, 5}}}}},
      {"cameras",
       {{{"name", "lens"},
         {"type", "perspective"},
         {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"aspectRatio", 1.0}}}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
            {"indices", 3},
            {"material", 0}}}}},
        {{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 3}, {"material", 3}}}}}}},
      {"materials",
       {{{"name", "paint"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}, {"metallicFactor", 0.0}}}},
        {{"name", "gold"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {1.0, 0.8, 0.3, 1.0}},
           {"metallicFactor", 1.0},
           {"roughnessFactor", 0.3}}}},
        {{"name", "lamp"},
         {"emissiveFactor", {1.0, 0.5, 0.25}},
         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}},
        {{"name", "glass"},
         {"extensions",
          {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
           {"KHR_materials_ior", {{"ior", 1.33}}}}}}}},
      {"buffers", {{{"uri", bufferUri}, {"byteLength", bufferBytes}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
        {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
        {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
        {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
        {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
        {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
      {"extensionsUsed",
       {"KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"}}};
  return j;
}

inline std::string dataUri(const std::string& bytes) {
  return "data:application/octet-stream;base64," + base64(bytes);
}

// Under a folder of the test's own: CTest runs the tests in parallel processes.
inline std::string writeFile(const std::string& name, const std::string& contents) {
  const std::string path = test::outputPath(
      std::string("gltf/") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "/" +
      name);
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

inline std::string writeGltf(const std::string& name, const Json& j) {
  return writeFile(name, j.dump());
}

using test::expectNear;

// Every warning of a loaded file, one a line (to search for a part of one).
template <typename Loaded>
std::string allWarnings(const Loaded& loaded) {
  std::string all;
  for (const std::string& w : loaded.warnings) all += w + "\n";
  return all;
}

// A data: URI of a PNG of w x h texels with n channels.
inline std::string pngUri(int w, int h, int n, const std::vector<uint8_t>& texels) {
  const std::vector<uint8_t> png = encodePng8(w, h, n, texels);
  return "data:image/png;base64," + base64(std::string(png.begin(), png.end()));
}

}  // namespace penumbra::gltf_test
