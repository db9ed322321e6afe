#include "scene/gltf_compression.h"

#include "scene/draco_decode.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_file.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>

namespace penumbra::gltf {

namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kMeshoptNames[] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};

// The meshopt extension object of an extension map (either name), or null.
const tinygltf::Value* meshoptExtension(const tinygltf::ExtensionMap& extensions) {
  for (const char* name : kMeshoptNames) {
    const auto it = extensions.find(name);
    if (it != extensions.end()) return &it->second;
  }
  return nullptr;
}

void appendLittleEndian32(std::string& bytes, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes += char(uint8_t(v >> (8 * i)));
}

size_t integerField(const tinygltf::Value& object, const char* key, size_t fallback) {
  if (!object.Has(key)) return fallback;
  const tinygltf::Value& v = object.Get(key);
  const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
  if (!(d >= 0.0 && d < 9e18)) return size_t(-1);  // refused by the caller
  return size_t(d);
}

std::string stringField(const tinygltf::Value& object, const char* key, const char* fallback) {
  if (!object.Has(key) || !object.Get(key).IsString()) return fallback;
  return object.Get(key).Get<std::string>();
}

// ---- meshopt -----------------------------------------------------------------------------------

void decodeMeshoptView(const std::string& path, tinygltf::Model& model, size_t viewIndex,
                       const tinygltf::Value& ext) {
  const std::string where = indexed("bufferViews", viewIndex) + ".extensions.meshopt";
  tinygltf::BufferView& view = model.bufferViews[viewIndex];
  const size_t source = integerField(ext, "buffer", size_t(-1));
  const size_t offset = integerField(ext, "byteOffset", 0);
  const size_t length = integerField(ext, "byteLength", size_t(-1));
  const size_t stride = integerField(ext, "byteStride", size_t(-1));
  const size_t count = integerField(ext, "count", size_t(-1));
  const std::string mode = stringField(ext, "mode", "");
  const std::string filter = stringField(ext, "filter", "NONE");
  if (source >= model.buffers.size()) fail(path, where, "its buffer does not exist");
  const std::vector<unsigned char>& from = model.buffers[source].data;
  if (length == size_t(-1) || offset > from.size() || length > from.size() - offset)
    fail(path, where, "its compressed bytes run past the end of their buffer");
  if (stride == 0 || stride > 256 || count == size_t(-1))
    fail(path, where, "byteStride and count must be given, the stride in 1-256");
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    fail(path, where, "the view's buffer does not exist");
  std::vector<unsigned char>& to = model.buffers[size_t(view.buffer)].data;
  if (count > (size_t(1) << 32) / stride || view.byteOffset > to.size() ||
      count * stride > to.size() - view.byteOffset || count * stride > view.byteLength)
    fail(path, where,
         std::to_string(count) + " elements of " + std::to_string(stride) +
             " bytes do not fit the buffer view");
  unsigned char* out = to.data() + view.byteOffset;
  const unsigned char* in = from.data() + offset;
  int status = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0) fail(path, where, "attributes need a byte stride that is a multiple of 4");
    status = meshopt_decodeVertexBuffer(out, count, stride, in, length);
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) fail(path, where, "indices need a byte stride of 2 or 4");
    if (mode == "TRIANGLES" && count % 3 != 0)
      fail(path, where, "a TRIANGLES stream needs a count that is a multiple of 3");
    status = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out, count, stride, in, length)
                                 : meshopt_decodeIndexSequence(out, count, stride, in, length);
  } else {
    fail(path, where, "unknown mode '" + mode + "' (ATTRIBUTES, TRIANGLES or INDICES)");
  }
  if (status != 0)
    fail(path, where,
         "the compressed " + mode + " do not decode (meshoptimizer error " +
             std::to_string(status) + ": corrupt, or a newer encoding than this build reads)");
  if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8))
    meshopt_decodeFilterOct(out, count, stride);
  else if (filter == "QUATERNION" && stride == 8)
    meshopt_decodeFilterQuat(out, count, stride);
  else if (filter == "EXPONENTIAL" && stride % 4 == 0)
    meshopt_decodeFilterExp(out, count, stride);
  else if (filter != "NONE")
    fail(path, where,
         "filter '" + filter + "' with a byte stride of " + std::to_string(stride) +
             " is not one the extension defines");
}

// ---- Draco ------------------------------------------------------------------------------------

// Appends `bytes` to the model's decoded buffer as a new buffer view; points `accessor` at it.
void pointAccessorAt(tinygltf::Model& model, int buffer, tinygltf::Accessor& accessor,
                     const std::vector<unsigned char>& bytes) {
  std::vector<unsigned char>& data = model.buffers[size_t(buffer)].data;
  while (data.size() % 4 != 0) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = buffer;
  view.byteOffset = data.size();
  view.byteLength = bytes.size();
  data.insert(data.end(), bytes.begin(), bytes.end());
  model.bufferViews.push_back(view);
  accessor.bufferView = int(model.bufferViews.size() - 1);
  accessor.byteOffset = 0;
}

// Whether the primitive still needs its Draco data: an accessor of it has no buffer view (a
// file that keeps the uncompressed data too is read from that).
bool needsDraco(const tinygltf::Model& model, const tinygltf::Primitive& prim) {
  auto missing = [&](int accessor) {
    return accessor >= 0 && size_t(accessor) < model.accessors.size() &&
           model.accessors[size_t(accessor)].bufferView < 0 &&
           !model.accessors[size_t(accessor)].sparse.isSparse;
  };
  if (missing(prim.indices)) return true;
  for (const auto& [name, accessor] : prim.attributes)
    if (missing(accessor)) return true;
  return false;
}

void decodeDracoPrimitive(const std::string& path, tinygltf::Model& model,
                          tinygltf::Primitive& prim, const tinygltf::Value& ext, int decodedBuffer,
                          const std::string& where) {
  const size_t viewIndex = integerField(ext, "bufferView", size_t(-1));
  if (viewIndex >= model.bufferViews.size()) fail(path, where, "its buffer view does not exist");
  const tinygltf::BufferView& view = model.bufferViews[viewIndex];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    fail(path, where, "its buffer view's buffer does not exist");
  const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    fail(path, where, "its buffer view runs past the end of its buffer");
  if (!ext.Has("attributes") || !ext.Get("attributes").IsObject())
    fail(path, where, "'attributes' is missing");
  // The attributes the primitive names, each converted to its accessor's type.
  const tinygltf::Value& ids = ext.Get("attributes");
  std::vector<DracoAttribute> wanted;
  std::vector<int> accessorOf;
  std::vector<std::string> names;
  for (const std::string& name : ids.Keys()) {
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) continue;  // compressed but not named by the primitive
    if (it->second < 0 || size_t(it->second) >= model.accessors.size())
      fail(path, where + ".attributes." + name, "its accessor does not exist");
    const tinygltf::Accessor& a = model.accessors[size_t(it->second)];
    const size_t id = integerField(ids, name.c_str(), size_t(-1));
    const int components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (id > 0xffffffffu) fail(path, where + ".attributes." + name, "not an attribute id");
    if (components < 1 || components > 4 || componentBytes(a.componentType) == 0)
      fail(path, where + ".attributes." + name, "unsupported accessor type");
    wanted.push_back({uint32_t(id), a.componentType, components, {}});
    accessorOf.push_back(it->second);
    names.push_back(name);
  }
  DracoMesh mesh;
  const std::string problem =
      decodeDraco(buffer.data() + view.byteOffset, view.byteLength, mesh, wanted);
  if (!problem.empty()) fail(path, where, "the Draco data does not decode: " + problem);
  const size_t points = mesh.points;
  if (prim.indices >= 0) {
    if (size_t(prim.indices) >= model.accessors.size())
      fail(path, where, "its indices accessor does not exist");
    tinygltf::Accessor& a = model.accessors[size_t(prim.indices)];
    if (a.count != mesh.indices.size())
      fail(path, where,
           "its indices accessor counts " + std::to_string(a.count) + " indices, the Draco mesh " +
               std::to_string(mesh.indices.size()));
    const size_t size = componentBytes(a.componentType);
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && points > 0 &&
        points - 1 > (size == 1 ? 255u : 65535u))
      fail(path, where, "the Draco mesh has more points than its index type can name");
    std::vector<unsigned char> bytes(mesh.indices.size() * size);
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
      const uint32_t v = mesh.indices[i];
      if (size == 1)
        bytes[i] = uint8_t(v);
      else if (size == 2)
        std::memcpy(&bytes[2 * i], &v, 2);  // little-endian
      else
        std::memcpy(&bytes[4 * i], &v, 4);
    }
    pointAccessorAt(model, decodedBuffer, a, bytes);
  }
  for (size_t k = 0; k < wanted.size(); ++k) {
    tinygltf::Accessor& a = model.accessors[size_t(accessorOf[k])];
    if (a.count != points)
      fail(path, where + ".attributes." + names[k],
           "its accessor counts " + std::to_string(a.count) + " elements, the Draco mesh " +
               std::to_string(points) + " points");
    pointAccessorAt(model, decodedBuffer, a, wanted[k].bytes);
  }
}

}  // namespace

bool isMeshCompression(const std::string& extension) {
  return extension == kDraco || extension == kMeshoptNames[0] || extension == kMeshoptNames[1];
}

CompressionStubs stubCompressedData(const std::string& path, std::string& json, bool binary) {
  CompressionStubs stubs;
  const bool meshopt = json.find("meshopt_compression") != std::string::npos;
  if (!meshopt && json.find(kDraco) == std::string::npos) return stubs;
  nlohmann::json root = nlohmann::json::parse(json, nullptr, false);
  if (!root.is_object()) return stubs;
  auto array = [&](const char* name) -> nlohmann::json* {
    return root.contains(name) && root[name].is_array() ? &root[name] : nullptr;
  };
  if (nlohmann::json* buffers = array("buffers"); buffers && meshopt) {
    for (size_t i = 0; i < buffers->size(); ++i) {
      nlohmann::json& b = (*buffers)[i];
      // A .glb's first buffer without a URI is its binary chunk, whatever its extensions say.
      if (!b.is_object() || b.contains("uri") || (binary && i == 0) || !b.contains("extensions") ||
          !b["extensions"].is_object())
        continue;
      bool fallback = false;
      for (const char* name : kMeshoptNames) {
        const nlohmann::json& e = b["extensions"];
        if (e.contains(name) && e[name].is_object() && e[name].value("fallback", false))
          fallback = true;
      }
      if (!fallback) continue;
      if (!b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
        fail(path, indexed("buffers", i), "a fallback buffer needs its byteLength");
      stubs.fallbacks.emplace_back(i, b["byteLength"].get<size_t>());
      b["byteLength"] = 1;
      b["uri"] = "data:application/octet-stream;base64,AA==";
    }
  }
  nlohmann::json* meshes = array("meshes");
  nlohmann::json* accessors = array("accessors");
  if (meshes && accessors)
    for (nlohmann::json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
        continue;
      for (nlohmann::json& prim : mesh["primitives"]) {
        if (!prim.is_object() || !prim.contains("indices") ||
            !prim["indices"].is_number_unsigned() || !prim.contains("extensions") ||
            !prim["extensions"].is_object() || !prim["extensions"].contains(kDraco) ||
            !prim["extensions"][kDraco].is_object())
          continue;
        const nlohmann::json& draco = prim["extensions"][kDraco];
        const size_t index = prim["indices"].get<size_t>();
        if (index >= accessors->size() || !(*accessors)[index].is_object() ||
            (*accessors)[index].contains("bufferView") || !draco.contains("bufferView"))
          continue;
        (*accessors)[index]["bufferView"] = draco["bufferView"];
        stubs.dracoIndices.push_back(int(index));
      }
    }
  if (!stubs.empty()) json = root.dump();
  return stubs;
}

std::string replaceGlbJson(const std::string& glb, const std::string& json) {
  const uint32_t oldLength = littleEndian32(glb, 12);
  std::string padded = json;
  while (padded.size() % 4 != 0) padded += ' ';
  std::string out = glb.substr(0, 12);
  appendLittleEndian32(out, uint32_t(padded.size()));
  out += "JSON";
  out += padded;
  out += glb.substr(std::min(glb.size(), size_t(20) + oldLength));
  const uint32_t total = uint32_t(out.size());
  for (int i = 0; i < 4; ++i) out[size_t(8 + i)] = char(uint8_t(total >> (8 * i)));
  return out;
}

void decodeCompressedMeshes(const std::string& path, tinygltf::Model& model,
                            const CompressionStubs& stubs) {
  for (const auto& [index, byteLength] : stubs.fallbacks)
    if (index < model.buffers.size()) model.buffers[index].data.assign(byteLength, 0);
  // The stubbed index accessors read nothing until the Draco data is decoded into them.
  for (int a : stubs.dracoIndices)
    if (a >= 0 && size_t(a) < model.accessors.size()) model.accessors[size_t(a)].bufferView = -1;
  for (size_t v = 0; v < model.bufferViews.size(); ++v) {
    const tinygltf::BufferView& view = model.bufferViews[v];
    const tinygltf::Value* ext = meshoptExtension(view.extensions);
    if (!ext) continue;
    bool stubbed = false;
    for (const auto& [index, byteLength] : stubs.fallbacks) stubbed |= int(index) == view.buffer;
    if (stubbed) decodeMeshoptView(path, model, v, *ext);  // else its data is there already
  }

  int decodedBuffer = -1;
  for (size_t m = 0; m < model.meshes.size(); ++m)
    for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
      tinygltf::Primitive& prim = model.meshes[m].primitives[p];
      const auto it = prim.extensions.find(kDraco);
      if (it == prim.extensions.end() || !needsDraco(model, prim)) continue;
      const std::string where =
          indexed("meshes", m) + "." + indexed("primitives", p) + ".extensions." + kDraco;
      if (!it->second.IsObject()) fail(path, where, "not an object");
      if (decodedBuffer < 0) {
        model.buffers.emplace_back();
        decodedBuffer = int(model.buffers.size() - 1);
      }
      decodeDracoPrimitive(path, model, prim, it->second, decodedBuffer, where);
    }
}

}  // namespace penumbra::gltf
