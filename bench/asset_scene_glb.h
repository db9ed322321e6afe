// The asset-scene generator's glTF side (bench/make_asset_scene.cpp): its mesh and 8-bit
// image types and a minimal binary glTF (.glb) writer, one buffer, meshes with their
// attributes, materials and PNG images embedded.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace asset_scene {

using json = nlohmann::json;

struct Mesh {
  std::string name;
  std::vector<float> positions, normals, tangents, uvs;  // 3, 3, 4, 2 floats per vertex
  std::vector<uint32_t> indices;
  size_t vertexCount() const { return positions.size() / 3; }
  size_t triangleCount() const { return indices.size() / 3; }
};

struct Image8 {
  std::string name;
  int channels = 3;
  std::vector<uint8_t> pixels;
  std::vector<uint8_t> png;
};

// ---------------------------------------------------------------------------- glTF files
class Glb {
 public:
  json doc = {{"asset", {{"version", "2.0"}, {"generator", "penumbra bench/make_asset_scene"}}},
              {"scene", 0}};

  int view(const void* data, size_t bytes, int target) {
    while (bin_.size() % 4) bin_.push_back(0);
    json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
    if (target) v["target"] = target;
    const auto* p = static_cast<const uint8_t*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    doc["bufferViews"].push_back(v);
    return int(doc["bufferViews"].size() - 1);
  }

  int floats(const std::vector<float>& values, int components, const char* type, bool bounds) {
    const size_t count = values.size() / components;
    json a = {{"bufferView", view(values.data(), values.size() * 4, 34962)},
              {"componentType", 5126},
              {"count", count},
              {"type", type}};
    if (bounds) {
      std::vector<float> lo(components, INFINITY), hi(components, -INFINITY);
      for (size_t i = 0; i < values.size(); ++i) {
        lo[i % components] = std::min(lo[i % components], values[i]);
        hi[i % components] = std::max(hi[i % components], values[i]);
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size() - 1);
  }

  int indices(const std::vector<uint32_t>& values) {
    doc["accessors"].push_back({{"bufferView", view(values.data(), values.size() * 4, 34963)},
                                {"componentType", 5125},
                                {"count", values.size()},
                                {"type", "SCALAR"}});
    return int(doc["accessors"].size() - 1);
  }

  // A mesh with one primitive, on a node of its own in the scene.
  void mesh(const Mesh& m, int material) {
    json attributes = {{"POSITION", floats(m.positions, 3, "VEC3", true)},
                       {"NORMAL", floats(m.normals, 3, "VEC3", false)}};
    if (!m.tangents.empty()) attributes["TANGENT"] = floats(m.tangents, 4, "VEC4", false);
    if (!m.uvs.empty()) attributes["TEXCOORD_0"] = floats(m.uvs, 2, "VEC2", false);
    json primitive = {{"attributes", attributes},
                      {"indices", indices(m.indices)},
                      {"mode", 4},
                      {"material", material}};
    doc["meshes"].push_back({{"name", m.name}, {"primitives", json::array({primitive})}});
    doc["nodes"].push_back({{"name", m.name}, {"mesh", doc["meshes"].size() - 1}});
    doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
  }

  int image(const Image8& image) {
    doc["images"].push_back({{"name", image.name},
                             {"mimeType", "image/png"},
                             {"bufferView", view(image.png.data(), image.png.size(), 0)}});
    doc["textures"].push_back({{"sampler", 0}, {"source", doc["images"].size() - 1}});
    return int(doc["textures"].size() - 1);
  }

  int material(json m) {
    doc["materials"].push_back(std::move(m));
    return int(doc["materials"].size() - 1);
  }

  void write(const std::filesystem::path& path) {
    doc["buffers"] = json::array({{{"byteLength", bin_.size()}}});
    std::string text = doc.dump();
    while (text.size() % 4) text.push_back(' ');
    while (bin_.size() % 4) bin_.push_back(0);
    const uint32_t total = uint32_t(12 + 8 + text.size() + 8 + bin_.size());
    std::ofstream out(path, std::ios::binary);
    auto u32 = [&](uint32_t v) {
      out.write(reinterpret_cast<const char*>(&v), 4);
    };                 // little-endian host
    u32(0x46546C67u);  // "glTF"
    u32(2);
    u32(total);
    u32(uint32_t(text.size()));
    u32(0x4E4F534Au);  // "JSON"
    out.write(text.data(), std::streamsize(text.size()));
    u32(uint32_t(bin_.size()));
    u32(0x004E4942u);  // "BIN\0"
    out.write(reinterpret_cast<const char*>(bin_.data()), std::streamsize(bin_.size()));
    if (!out) throw std::runtime_error("cannot write " + path.string());
  }

 private:
  std::vector<uint8_t> bin_;
};

}  // namespace asset_scene
