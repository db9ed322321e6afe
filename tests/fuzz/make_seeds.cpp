// Writes the seed corpora of the file-format fuzz targets: small, valid files of every kind the
// readers take, made with the project's own writers where it has them.
// Usage: make_seeds FOLDER   (creates FOLDER/obj, mtl, ply, exr, png, pfm)
#include "core/image.h"
#include "core/image_io.h"
#include "tests/base64.h"
#include "tests/engine/scene/draco_encode.h"

#include <meshoptimizer.h>
#include <webp/encode.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace penumbra;

namespace {

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// A PLY quad (two triangles) with normals and uvs, in the given format; binary values are
// written in the named byte order.
std::string plyQuad(const std::string& format) {
  std::string header = "ply\nformat " + format +
                       " 1.0\ncomment seed\nelement vertex 4\nproperty float x\n"
                       "property float y\nproperty float z\nproperty float nx\n"
                       "property float ny\nproperty float nz\nproperty float u\nproperty float v\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float vertices[4][8] = {{0, 0, 0, 0, 0, 1, 0, 0},
                                {1, 0, 0, 0, 0, 1, 1, 0},
                                {1, 1, 0, 0, 0, 1, 1, 1},
                                {0, 1, 0, 0, 0, 1, 0, 1}};
  if (format == "ascii") {
    std::string body;
    for (const auto& v : vertices) {
      for (float x : v) body += std::to_string(x) + " ";
      body += "\n";
    }
    return header + body + "4 0 1 2 3\n";
  }
  const bool big = format == "binary_big_endian";
  std::string body;
  auto put = [&](const void* value, size_t n) {
    std::string bytes(static_cast<const char*>(value), n);
    if (big) bytes.assign(bytes.rbegin(), bytes.rend());
    body += bytes;
  };
  for (const auto& v : vertices)
    for (float x : v) put(&x, 4);
  const uint8_t corners = 4;
  body += char(corners);
  for (int32_t i = 0; i < 4; ++i) put(&i, 4);
  return header + body;
}

// A normal-mapped triangle with TANGENTs and a morph target, skinned by two joints, the second
// joint and the target's weight animated.
const char* const kSkinnedGltf =
    R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1,3]}],"nodes":[{"mesh":0,"skin":0,"translation":[5,0,0]},{"children":[2]},{"translation":[1,0,0]},{"camera":0,"translation":[1,0.5,4]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.7,"znear":0.1}}],"skins":[{"joints":[1,2],"inverseBindMatrices":6}],"meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TANGENT":2,"JOINTS_0":3,"WEIGHTS_0":4},"indices":5,"material":0,"targets":[{"POSITION":9}]}],"weights":[0.5]}],"materials":[{"normalTexture":{"index":0},"emissiveFactor":[1,0.5,0.2]}],"textures":[{"source":0}],"images":[{"uri":"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGNoOHECAAPcAhH5w/3PAAAAAElFTkSuQmCC"}],"animations":[{"channels":[{"sampler":0,"target":{"node":2,"path":"rotation"}},{"sampler":1,"target":{"node":0,"path":"weights"}}],"samplers":[{"input":7,"output":8,"interpolation":"LINEAR"},{"input":7,"output":10,"interpolation":"STEP"}]}],"buffers":[{"byteLength":408,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAAAAQAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAIA/AAAAAAAAAAAAAIA/AAAAAAEAAAAAAQAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAAA/AAAAPwAAAAAAAAAAAAABAAIAAAAAAIA/AAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/AACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAAAACAvwAAAAAAAAAAAACAPwAAAAAAAIA/AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA8wQ1P/MENT8AAAAAAAAAAAAAAD8AAAAAAAAAAAAAAAAAAAAAAAAAPwAAAAAAAAAAAACAPwAAAD8AAAAA"}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":36},{"buffer":0,"byteOffset":72,"byteLength":48},{"buffer":0,"byteOffset":120,"byteLength":12},{"buffer":0,"byteOffset":132,"byteLength":48},{"buffer":0,"byteOffset":180,"byteLength":8},{"buffer":0,"byteOffset":188,"byteLength":128},{"buffer":0,"byteOffset":316,"byteLength":8},{"buffer":0,"byteOffset":324,"byteLength":32},{"buffer":0,"byteOffset":356,"byteLength":36},{"buffer":0,"byteOffset":392,"byteLength":8}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[2,1,0]},{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"},{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"},{"bufferView":3,"componentType":5121,"count":3,"type":"VEC4"},{"bufferView":4,"componentType":5126,"count":3,"type":"VEC4"},{"bufferView":5,"componentType":5123,"count":3,"type":"SCALAR"},{"bufferView":6,"componentType":5126,"count":2,"type":"MAT4"},{"bufferView":7,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]},{"bufferView":8,"componentType":5126,"count":2,"type":"VEC4"},{"bufferView":9,"componentType":5126,"count":3,"type":"VEC3"},{"bufferView":10,"componentType":5126,"count":2,"type":"SCALAR"}]})";

// A red emissive triangle seen by a camera: as .gltf (buffer in a data: URI) and as .glb.
const char* const kTriangleGltf =
    R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[0,0,-1],"rotation":[0,0,0,1],"scale":[1,1,1]},{"camera":0,"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,3,1]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.7,"znear":0.1}}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0,"mode":4}]}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1],"metallicFactor":0},"emissiveFactor":[1,1,1]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
const char* const kTriangleGlbJson =
    R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[0,0,-1],"rotation":[0,0,0,1],"scale":[1,1,1]},{"camera":0,"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,3,1]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.7,"znear":0.1}}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0,"mode":4}]}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1],"metallicFactor":0},"emissiveFactor":[1,1,1]}],"buffers":[{"byteLength":44}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";

// The triangle with everything the reader turns into rendering: a half-metal, partly
// transmissive material with a base colour texture (alpha MASK), a normal map and an emissive
// texture (PNGs in data: URIs), a spot and a directional light, and an animation (linear
// translation, step rotation).
const char* const kFeaturesGltf =
    R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1,2,3]}],"nodes":[{"mesh":0,"translation":[0,0,-1]},{"camera":0,"translation":[0,0,3]},{"translation":[0,2,0],"rotation":[-0.7071068,0,0,0.7071068],"extensions":{"KHR_lights_punctual":{"light":0}}},{"extensions":{"KHR_lights_punctual":{"light":1}}}],"cameras":[{"type":"perspective","perspective":{"yfov":0.7,"znear":0.1}}],"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1,"material":0}]}],"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0.5,"roughnessFactor":0.4},"normalTexture":{"index":1,"scale":0.8},"alphaMode":"MASK","alphaCutoff":0.5,"emissiveFactor":[1,1,1],"emissiveTexture":{"index":0},"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":2},"KHR_materials_transmission":{"transmissionFactor":0.3}}}],"textures":[{"source":0},{"source":1}],"images":[{"uri":"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAYAAAD0In+KAAAAEElEQVR4nGP4zwAE/xn+AwAL/QL+6O7ISQAAAABJRU5ErkJggg=="},{"uri":"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGNoOHECAAPcAhH5w/3PAAAAAElFTkSuQmCC"}],"extensionsUsed":["KHR_lights_punctual","KHR_materials_emissive_strength","KHR_materials_transmission"],"extensions":{"KHR_lights_punctual":{"lights":[{"type":"spot","intensity":5,"range":8,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}},{"type":"directional","color":[1,0.9,0.8],"intensity":2}]}},"animations":[{"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}},{"sampler":1,"target":{"node":0,"path":"rotation"}}],"samplers":[{"input":3,"output":4,"interpolation":"LINEAR"},{"input":3,"output":5,"interpolation":"STEP"}]}],"buffers":[{"byteLength":132,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAAAAAAAAAAAAgD8AAAAA9AQ1PwAAAAD0BDU/"}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6},{"buffer":0,"byteOffset":44,"byteLength":24},{"buffer":0,"byteOffset":68,"byteLength":8},{"buffer":0,"byteOffset":76,"byteLength":24},{"buffer":0,"byteOffset":100,"byteLength":32}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},{"bufferView":2,"componentType":5126,"count":3,"type":"VEC2"},{"bufferView":3,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]},{"bufferView":4,"componentType":5126,"count":2,"type":"VEC3"},{"bufferView":5,"componentType":5126,"count":2,"type":"VEC4"}]})";

std::string glbOf(std::string json, std::string bin) {
  while (json.size() % 4) json += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string glb = "glTF";
  auto put = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  put(2);
  put(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  put(uint32_t(json.size()));
  put(0x4E4F534Au);  // "JSON"
  glb += json;
  put(uint32_t(bin.size()));
  put(0x004E4942u);  // "BIN"
  glb += bin;
  return glb;
}

std::string triangleGlb() {
  std::string bin;
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint16_t indices[4] = {0, 1, 2, 0};  // the last is padding to 4 bytes
  bin.append(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  return glbOf(kTriangleGlbJson, bin);
}

// The triangle textured with a 2 x 1 lossless WebP image (EXT_texture_webp), in a data: URI.
std::string webpTriangleGltf() {
  nlohmann::json j = nlohmann::json::parse(kTriangleGltf);
  const uint8_t rgb[6] = {255, 0, 0, 0, 0, 255};
  uint8_t* webp = nullptr;
  const size_t size = WebPEncodeLosslessRGB(rgb, 2, 1, 6, &webp);
  const std::string bytes(reinterpret_cast<const char*>(webp), size);
  WebPFree(webp);
  j["images"] = {{{"uri", "data:image/webp;base64," + test::base64(bytes)}}};
  j["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
  j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  j["extensionsUsed"] = j["extensionsRequired"] = {"EXT_texture_webp"};
  return j.dump();
}

// The features file with its material's layers: sheen, anisotropy, a transmission texture,
// and a second material in the specular-glossiness model reading the second uv set.
std::string layeredMaterialsGltf() {
  nlohmann::json j = nlohmann::json::parse(kFeaturesGltf);
  auto& e = j["materials"][0]["extensions"];
  e["KHR_materials_sheen"] = {{"sheenColorFactor", {1, 0.5, 0.25}},
                              {"sheenRoughnessFactor", 0.4},
                              {"sheenColorTexture", {{"index", 0}}},
                              {"sheenRoughnessTexture", {{"index", 1}}}};
  e["KHR_materials_anisotropy"] = {{"anisotropyStrength", 0.7},
                                   {"anisotropyRotation", 0.5},
                                   {"anisotropyTexture", {{"index", 1}}}};
  e["KHR_materials_transmission"]["transmissionTexture"] = {{"index", 1}};
  e["KHR_materials_iridescence"] = {{"iridescenceFactor", 0.8},
                                    {"iridescenceIor", 1.4},
                                    {"iridescenceThicknessMinimum", 150},
                                    {"iridescenceThicknessMaximum", 500},
                                    {"iridescenceTexture", {{"index", 0}}},
                                    {"iridescenceThicknessTexture", {{"index", 1}}}};
  j["materials"].push_back(
      {{"extensions",
        {{"KHR_materials_pbrSpecularGlossiness",
          {{"diffuseFactor", {0.8, 0.6, 0.4, 1}},
           {"specularFactor", {0.1, 0.1, 0.1}},
           {"glossinessFactor", 0.6},
           {"diffuseTexture", {{"index", 0}, {"texCoord", 1}}},
           {"specularGlossinessTexture", {{"index", 0}, {"texCoord", 1}}}}}}}});
  auto& primitive = j["meshes"][0]["primitives"][0];
  nlohmann::json second = primitive;
  second["material"] = 1;
  second["attributes"]["TEXCOORD_1"] = primitive["attributes"]["TEXCOORD_0"];
  j["meshes"][0]["primitives"].push_back(second);
  for (const char* name : {"KHR_materials_sheen", "KHR_materials_anisotropy",
                           "KHR_materials_pbrSpecularGlossiness", "KHR_materials_iridescence"})
    j["extensionsUsed"].push_back(name);
  return j.dump();
}

// The .glb triangle with its positions and indices meshopt-compressed into the binary chunk, the
// views in a fallback buffer with no data; and with the triangle Draco-compressed.
std::string compressedTriangleGlb(bool draco) {
  nlohmann::json j = nlohmann::json::parse(kTriangleGlbJson);
  const std::vector<std::array<float, 3>> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<uint32_t> indices = {0, 1, 2};
  std::string bin;
  if (draco) {
    const test::DracoEncoded d = test::encodeDraco(positions, {{0, 0}, {1, 0}, {0, 1}}, indices);
    bin = d.bytes;
    j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
    j["meshes"][0]["primitives"][0]["extensions"] = {
        {"KHR_draco_mesh_compression",
         {{"bufferView", 0},
          {"attributes", {{"POSITION", d.positionId}, {"TEXCOORD_0", d.uvId}}}}}};
    j["accessors"] = {{{"componentType", 5126}, {"count", d.points}, {"type", "VEC3"}},
                      {{"componentType", 5123}, {"count", d.faces * 3}, {"type", "SCALAR"}},
                      {{"componentType", 5126}, {"count", d.points}, {"type", "VEC2"}}};
    j["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", bin.size()}}};
    j["buffers"] = {{{"byteLength", bin.size()}}};
    j["extensionsUsed"] = j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    return glbOf(j.dump(), bin);
  }
  std::vector<unsigned char> v(meshopt_encodeVertexBufferBound(3, 12));
  v.resize(meshopt_encodeVertexBuffer(v.data(), v.size(), positions.data(), 3, 12));
  std::vector<unsigned char> t(meshopt_encodeIndexBufferBound(3, 3));
  t.resize(meshopt_encodeIndexBuffer(t.data(), t.size(), indices.data(), 3));
  bin.assign(v.begin(), v.end());
  while (bin.size() % 4) bin += '\0';
  const size_t at = bin.size();
  bin.append(t.begin(), t.end());
  auto ext = [](size_t offset, size_t length, int stride, const char* mode) {
    return nlohmann::json{{"EXT_meshopt_compression",
                           {{"buffer", 0},
                            {"byteOffset", offset},
                            {"byteLength", length},
                            {"byteStride", stride},
                            {"count", 3},
                            {"mode", mode}}}};
  };
  j["bufferViews"][0]["buffer"] = j["bufferViews"][1]["buffer"] = 1;
  j["bufferViews"][0]["extensions"] = ext(0, v.size(), 12, "ATTRIBUTES");
  j["bufferViews"][1]["extensions"] = ext(at, t.size(), 2, "TRIANGLES");
  j["buffers"] = {
      {{"byteLength", bin.size()}},
      {{"byteLength", 44}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  j["extensionsUsed"] = j["extensionsRequired"] = {"EXT_meshopt_compression"};
  return glbOf(j.dump(), bin);
}

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.pixels[size_t(y) * w + x] = vec3(x * 0.25f, y * 0.5f, 1.5f);
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds FOLDER\n");
    return 2;
  }
  const fs::path root = argv[1];
  for (const char* kind : {"obj", "mtl", "ply", "gltf", "exr", "png", "pfm"})
    fs::create_directories(root / kind);

  writeBytes(root / "obj" / "quad.obj",
             "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
             "vn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\nusemtl b\nf -4 -2 -1\n");
  writeBytes(root / "obj" / "groups.obj",
             "# comment\no thing\ng part\ns off\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\n"
             "f 1//1 2//1 3//1\nvn 0 0 1\nl 1 2\np 3\n");
  writeBytes(root / "mtl" / "materials.mtl",
             "newmtl a\nKa 0 0 0\nKd 0.5 0.4 0.3\nKs 0.9 0.9 0.9\nNs 100\nillum 2\n"
             "newmtl b\nKe 10 8 6\nd 0.5\nNi 1.5\nTr 0\nmap_Kd tex.png\n");
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"})
    writeBytes(root / "ply" / (std::string(format) + ".ply"), plyQuad(format));

  writeBytes(root / "gltf" / "triangle.gltf", kTriangleGltf);
  writeBytes(root / "gltf" / "triangle.glb", triangleGlb());
  writeBytes(root / "gltf" / "features.gltf", kFeaturesGltf);
  writeBytes(root / "gltf" / "skinned.gltf", kSkinnedGltf);
  writeBytes(root / "gltf" / "meshopt.glb", compressedTriangleGlb(false));
  writeBytes(root / "gltf" / "draco.glb", compressedTriangleGlb(true));
  writeBytes(root / "gltf" / "webp.gltf", webpTriangleGltf());
  writeBytes(root / "gltf" / "layered.gltf", layeredMaterialsGltf());

  const Image image = gradient(4, 3);
  writeImage((root / "exr" / "gradient.exr").string(), image);
  writeImage((root / "pfm" / "gradient.pfm").string(), image);
  writeImage((root / "png" / "gradient.png").string(), image);
  writeExrLayers((root / "exr" / "layers.exr").string(), 2, 2,
                 {{"R", {1, 2, 3, 4}},
                  {"G", {0, 0, 0, 0}},
                  {"B", {1, 1, 1, 1}},
                  {"variance.Y", {0.1f, 0.2f, 0.3f, 0.4f}}});
  std::printf("seeds written under %s\n", root.string().c_str());
  return 0;
}
