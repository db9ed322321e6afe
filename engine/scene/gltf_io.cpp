#include "scene/gltf_io.h"

#include "scene/mesh_io.h"

#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& where,
                       const std::string& message) {
  throw SceneError(path + ": " + (where.empty() ? "" : where + ": ") + message);
}

// A factor as a user wrote it: 0.7, not 0.700000.
std::string number(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

std::string indexed(const char* array, size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

// ---- URIs: data: or a relative path, nothing else ------------------------------------------

std::string readFileBytes(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail(path, "", "cannot open file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) fail(path, "", "read error");
  return std::move(bytes).str();
}

uint32_t littleEndian32(const std::string& bytes, size_t at) {
  return uint32_t(uint8_t(bytes[at])) | uint32_t(uint8_t(bytes[at + 1])) << 8 |
         uint32_t(uint8_t(bytes[at + 2])) << 16 | uint32_t(uint8_t(bytes[at + 3])) << 24;
}

// The JSON part of a .gltf, or of a .glb (its first chunk).
std::string jsonText(const std::string& path, const std::string& bytes, bool binary) {
  if (!binary) return bytes;
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0)
    fail(path, "", "not a binary glTF file (no 'glTF' header)");
  const uint32_t version = littleEndian32(bytes, 4), length = littleEndian32(bytes, 12);
  if (version != 2) fail(path, "", "glTF version " + std::to_string(version) + " (expected 2)");
  if (littleEndian32(bytes, 16) != 0x4E4F534Au)  // "JSON"
    fail(path, "", "the first chunk of a .glb must be JSON");
  if (length > bytes.size() - 20)
    fail(path, "",
         "JSON chunk of " + std::to_string(length) + " bytes runs past the end of the file");
  return bytes.substr(20, length);
}

// Refuses a URI that names a network location (any scheme but data:) or an absolute path.
void checkUri(const std::string& path, const std::string& where, const std::string& uri) {
  if (uri.rfind("data:", 0) == 0) return;
  const size_t colon = uri.find(':');
  const size_t slash = uri.find('/');
  const bool scheme = colon != std::string::npos && colon > 0 &&
                      (slash == std::string::npos || colon < slash) &&
                      std::isalpha(static_cast<unsigned char>(uri[0]));
  const bool windowsDrive = scheme && colon == 1;
  if (scheme && !windowsDrive)
    fail(path, where,
         "URI '" + uri + "' names a network location; only relative paths and data: URIs are read");
  if (windowsDrive || uri.rfind('/', 0) == 0 || uri.rfind('\\', 0) == 0 || uri.rfind("//", 0) == 0)
    fail(path, where, "URI '" + uri + "' is an absolute path; only relative paths are read");
}

// Checks every buffer's and image's URI; returns the files the relative ones name.
std::vector<std::string> checkUris(const std::string& path, const std::string& json) {
  std::vector<std::string> files;
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    fail(path, "", std::string("invalid JSON: ") + e.what());
  }
  if (!root.is_object()) fail(path, "", "the top level is not a JSON object");
  for (const char* array : {"buffers", "images"}) {
    if (!root.contains(array) || !root[array].is_array()) continue;
    const auto& items = root[array];
    for (size_t i = 0; i < items.size(); ++i)
      if (items[i].is_object() && items[i].contains("uri") && items[i]["uri"].is_string()) {
        const std::string uri = items[i]["uri"].get<std::string>();
        checkUri(path, indexed(array, i) + ".uri", uri);
        if (uri.rfind("data:", 0) != 0)
          files.push_back((fs::path(path).parent_path() / uri).lexically_normal().string());
      }
  }
  return files;
}

// ---- accessors ------------------------------------------------------------------------------

size_t componentBytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;
  }
}

// An accessor's elements as doubles (normalised integers scaled to [0, 1] or [-1, 1]), after
// checking every byte it reads lies inside its buffer view and buffer.
class AccessorReader {
 public:
  AccessorReader(const std::string& path, const tinygltf::Model& model, int index,
                 const std::string& where)
      : path_(path), where_(where + " (accessors[" + std::to_string(index) + "])") {
    if (index < 0 || size_t(index) >= model.accessors.size())
      fail(path, where, "accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    if (a.sparse.isSparse) fail(path_, where_, "sparse accessors are not supported");
    count_ = a.count;
    components_ = componentCount(a.type);
    componentType_ = a.componentType;
    normalized_ = a.normalized;
    const size_t size = componentBytes(a.componentType);
    if (components_ == 0 || size == 0) fail(path_, where_, "unsupported accessor type");
    element_ = size * size_t(components_);
    if (a.bufferView < 0) return;  // all zeros, as the specification says
    if (size_t(a.bufferView) >= model.bufferViews.size())
      fail(path_, where_, "buffer view " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
      fail(path_, where_, "buffer " + std::to_string(view.buffer) + " does not exist");
    const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
    stride_ = view.byteStride ? view.byteStride : element_;
    if (stride_ < element_) fail(path_, where_, "byte stride smaller than an element");
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      fail(path_, where_, "buffer view runs past the end of its buffer");
    const size_t need = count_ == 0 ? 0 : a.byteOffset + stride_ * (count_ - 1) + element_;
    if (a.byteOffset > view.byteLength ||
        (count_ > 0 && (stride_ * (count_ - 1)) / stride_ != count_ - 1) ||
        need > view.byteLength || need < a.byteOffset)
      fail(path_, where_,
           std::to_string(count_) + " elements run past the end of their buffer view");
    data_ = buffer.data() + view.byteOffset + a.byteOffset;
  }

  size_t count() const { return count_; }
  int components() const { return components_; }
  bool isFloat() const { return componentType_ == TINYGLTF_COMPONENT_TYPE_FLOAT; }

  double get(size_t i, int c) const {
    if (!data_) return 0.0;
    const unsigned char* p = data_ + i * stride_ + size_t(c) * (element_ / size_t(components_));
    switch (componentType_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return scaled(double(p[0]), 255.0);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return std::max(scaled(double(int8_t(p[0])), 127.0), -1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return scaled(double(v), 65535.0);
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return std::max(scaled(double(v), 32767.0), -1.0);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return double(v);
      }
      default: {
        int32_t v;
        std::memcpy(&v, p, 4);
        return double(v);
      }
    }
  }

  const std::string& where() const { return where_; }

 private:
  double scaled(double v, double max) const { return normalized_ ? v / max : v; }

  const std::string& path_;
  std::string where_;
  const unsigned char* data_ = nullptr;
  size_t count_ = 0, stride_ = 0, element_ = 0;
  int components_ = 0, componentType_ = 0;
  bool normalized_ = false;
};

// ---- transforms -----------------------------------------------------------------------------

mat4 localTransform(const std::string& path, const tinygltf::Node& node, size_t index) {
  if (node.matrix.size() == 16) {
    mat4 m;
    for (int k = 0; k < 16; ++k) glm::value_ptr(m)[k] = float(node.matrix[size_t(k)]);
    return m;
  }
  if (!node.matrix.empty()) fail(path, indexed("nodes", index) + ".matrix", "expected 16 numbers");
  mat4 t(1.0f), r(1.0f), s(1.0f);
  if (node.translation.size() == 3)
    t = glm::translate(mat4(1.0f), vec3(float(node.translation[0]), float(node.translation[1]),
                                        float(node.translation[2])));
  if (node.rotation.size() == 4) {
    glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                float(node.rotation[2]));
    const float length = glm::length(q);
    if (!(length > 0.0f) || !std::isfinite(length))
      fail(path, indexed("nodes", index) + ".rotation", "not a rotation quaternion");
    r = glm::mat4_cast(q / length);
  }
  if (node.scale.size() == 3)
    s = glm::scale(mat4(1.0f),
                   vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
  return t * r * s;
}

// ---- images ---------------------------------------------------------------------------------

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// A decoded glTF image as linear RGB, times `factor`.
Image linearImage(const std::string& path, const tinygltf::Image& source, size_t index,
                  vec3 factor) {
  const std::string where = indexed("images", index);
  const int w = source.width, h = source.height, n = source.component;
  const int bytesPer = source.bits == 16 ? 2 : 1;
  if (w <= 0 || h <= 0 || n < 1 || n > 4 || (source.bits != 8 && source.bits != 16) ||
      source.image.size() != size_t(w) * size_t(h) * size_t(n) * size_t(bytesPer))
    fail(path, where,
         (source.uri.empty() || source.uri.rfind("data:", 0) == 0 ? std::string("its data")
                                                                  : "'" + source.uri + "'") +
             " could not be read or decoded as an image");
  Image image(w, h);
  for (size_t p = 0; p < image.pixels.size(); ++p) {
    float c[4] = {0, 0, 0, 1};
    for (int k = 0; k < n; ++k) {
      const size_t at = (p * size_t(n) + size_t(k)) * size_t(bytesPer);
      c[k] = bytesPer == 2 ? float(source.image[at] | source.image[at + 1] << 8) / 65535.0f
                           : float(source.image[at]) / 255.0f;
    }
    const vec3 rgb = n < 3 ? vec3(c[0]) : vec3(c[0], c[1], c[2]);
    image.pixels[p] = factor * vec3(srgbToLinear(rgb.x), srgbToLinear(rgb.y), srgbToLinear(rgb.z));
  }
  return image;
}

// ---- the conversion -------------------------------------------------------------------------

class Converter {
 public:
  Converter(const std::string& path, const tinygltf::Model& model, GltfData& out)
      : path_(path), model_(model), out_(out) {}

  void materials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) out_.materials.push_back(material(i));
  }

  // Walks the scene's node tree from its roots.
  void nodes(const std::string& cameraName) {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const size_t scene =
          model_.defaultScene >= 0 && size_t(model_.defaultScene) < model_.scenes.size()
              ? size_t(model_.defaultScene)
              : 0;
      roots = model_.scenes[scene].nodes;
    } else {
      // No scene: every node that is no other node's child is a root.
      std::vector<char> child(model_.nodes.size(), 0);
      for (const tinygltf::Node& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = 1;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!child[i]) roots.push_back(int(i));
    }
    onPath_.assign(model_.nodes.size(), 0);
    for (int root : roots) visit(root, mat4(1.0f), "scenes.nodes");
    pickCamera(cameraName);
  }

  void warnAboutTheRest() {
    if (!model_.animations.empty())
      warn("animations: " + std::to_string(model_.animations.size()) +
           " animation(s) not rendered yet (the scene is shown at rest)");
    if (!model_.skins.empty()) warn("skins: skinning is not supported; meshes are shown unposed");
    for (const std::string& e : model_.extensionsUsed)
      if (!supportedExtension(e)) warn("extension " + e + " is not supported and is ignored");
    for (const std::string& e : model_.extensionsRequired)
      if (!supportedExtension(e))
        warn("extension " + e +
             " is required by the file but not supported: the picture may be wrong");
  }

 private:
  static bool supportedExtension(const std::string& e) {
    return e == "KHR_materials_emissive_strength" || e == "KHR_materials_transmission" ||
           e == "KHR_materials_ior";
  }

  void warn(const std::string& message) {
    if (warned_.insert(message).second) out_.warnings.push_back(message);
  }

  static double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension,
                                const char* key, double fallback) {
    const auto it = extensions.find(extension);
    if (it == extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
  }

  // The base colour texture as one of ours (factor baked in), or -1.
  int baseColorTexture(const tinygltf::Material& m, size_t index, vec3 factor) {
    const int t = m.pbrMetallicRoughness.baseColorTexture.index;
    if (t < 0) return -1;
    const std::string where = indexed("materials", index) + ".baseColorTexture";
    if (size_t(t) >= model_.textures.size())
      fail(path_, where, "texture " + std::to_string(t) + " does not exist");
    const int source = model_.textures[size_t(t)].source;
    if (source < 0 || size_t(source) >= model_.images.size())
      fail(path_, where, "its texture has no image");
    if (m.pbrMetallicRoughness.baseColorTexture.texCoord != 0)
      warn(where + ": uv set " + std::to_string(m.pbrMetallicRoughness.baseColorTexture.texCoord) +
           " is not read; the first uv set is used");
    out_.images.push_back(
        linearImage(path_, model_.images[size_t(source)], size_t(source), factor));
    Texture texture;
    texture.kind = Texture::Kind::Image;
    texture.imageIndex = int(out_.images.size() - 1);
    out_.textures.push_back(texture);
    return int(out_.textures.size() - 1);
  }

  Material material(size_t index) {
    const tinygltf::Material& m = model_.materials[index];
    const std::string where = indexed("materials", index);
    Material out;
    out.name = m.name.empty() ? where : m.name;
    const auto& pbr = m.pbrMetallicRoughness;
    vec3 base(1.0f);
    if (pbr.baseColorFactor.size() >= 3)
      base = vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                  float(pbr.baseColorFactor[2]));
    base = glm::clamp(base, vec3(0.0f), vec3(1.0f));
    const float metallic = std::clamp(float(pbr.metallicFactor), 0.0f, 1.0f);
    const float roughness = std::clamp(float(pbr.roughnessFactor), 0.0f, 1.0f);
    const float transmission = float(
        extensionNumber(m.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
    if (transmission >= 0.5f) {
      out.type = Material::Type::Dielectric;
      out.ior = float(extensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5));
      if (!(out.ior >= 1.0f && out.ior < 10.0f)) out.ior = 1.5f;
      if (transmission < 1.0f)
        warn(where + ": transmission " + number(transmission) +
             " rendered as full glass (partial transmission is not built yet)");
    } else if (metallic >= 0.5f) {
      out.type = Material::Type::Conductor;
      out.albedo = base;
      out.roughness = std::max(roughness, 0.02f);
    } else {
      out.type = Material::Type::Diffuse;
      out.albedo = base;
      out.albedoTexture = baseColorTexture(m, index, base);
    }
    if (transmission > 0.0f && transmission < 0.5f)
      warn(where + ": transmission " + number(transmission) +
           " below 0.5 rendered as opaque (partial transmission is not built yet)");
    if (metallic > 0.0f && metallic < 1.0f)
      warn(where + ": metallic " + number(metallic) + " rendered as " +
           (metallic >= 0.5f ? "a conductor" : "diffuse") +
           " (the stochastic mix of the two is not built yet)");
    if (out.type == Material::Type::Conductor && pbr.baseColorTexture.index >= 0)
      warn(where + ": the base colour texture of a metal is not used (its factor is)");
    if (pbr.metallicRoughnessTexture.index >= 0)
      warn(where + ": metallicRoughnessTexture is not read (the factors are)");
    if (m.normalTexture.index >= 0) warn(where + ": normalTexture is not rendered yet");
    if (m.occlusionTexture.index >= 0)
      warn(where + ": occlusionTexture is ignored (a path tracer computes occlusion)");
    if (m.alphaMode == "MASK" || m.alphaMode == "BLEND")
      warn(where + ": alphaMode " + m.alphaMode + " is not rendered yet (drawn opaque)");
    if (m.emissiveFactor.size() == 3) {
      const float strength = float(extensionNumber(m.extensions, "KHR_materials_emissive_strength",
                                                   "emissiveStrength", 1.0));
      out.emission = glm::max(
          vec3(float(m.emissiveFactor[0]), float(m.emissiveFactor[1]), float(m.emissiveFactor[2])) *
              std::max(strength, 0.0f),
          vec3(0.0f));
      if (!std::isfinite(out.emission.x + out.emission.y + out.emission.z))
        fail(path_, where + ".emissiveFactor", "not finite");
    }
    if (m.emissiveTexture.index >= 0)
      warn(where + ": emissiveTexture is not rendered yet (the emissive factor is, uniformly)");
    return out;
  }

  uint32_t defaultMaterial() {
    if (defaultMaterial_ < 0) {
      Material m;
      m.name = "default";
      m.albedo = vec3(0.8f);
      out_.materials.push_back(m);
      defaultMaterial_ = int(out_.materials.size() - 1);
    }
    return uint32_t(defaultMaterial_);
  }

  void visit(int index, const mat4& parent, const std::string& from) {
    if (index < 0 || size_t(index) >= model_.nodes.size())
      fail(path_, from, "node " + std::to_string(index) + " does not exist");
    if (onPath_[size_t(index)]) fail(path_, indexed("nodes", size_t(index)), "is its own ancestor");
    // A node may be reached along many paths (instancing); a small file whose nodes list the
    // same child twice, level after level, would reach it 2^depth times.
    if (++visits_ > kMaxNodeInstances)
      fail(path_, "",
           "more than " + std::to_string(kMaxNodeInstances) +
               " node instances (a child listed many times over)");
    onPath_[size_t(index)] = 1;
    const tinygltf::Node& node = model_.nodes[size_t(index)];
    const mat4 world = parent * localTransform(path_, node, size_t(index));
    if (node.mesh >= 0) addMesh(node.mesh, world, indexed("nodes", size_t(index)));
    if (node.camera >= 0) cameraNodes_.push_back({index, world});
    if (node.extensions.count("KHR_lights_punctual"))
      warn("KHR_lights_punctual: punctual lights are not rendered yet");
    for (int child : node.children)
      visit(child, world, indexed("nodes", size_t(index)) + ".children");
    onPath_[size_t(index)] = 0;
  }

  void addMesh(int meshIndex, const mat4& world, const std::string& from) {
    if (size_t(meshIndex) >= model_.meshes.size())
      fail(path_, from, "mesh " + std::to_string(meshIndex) + " does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
    const glm::mat3 normalMatrix = glm::inverseTranspose(glm::mat3(world));
    const bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string where =
          indexed("meshes", size_t(meshIndex)) + "." + indexed("primitives", p);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        warn(where + ": points and lines are not rendered");
        continue;
      }
      if (!prim.targets.empty()) warn(where + ": morph targets are not applied");
      const auto position = prim.attributes.find("POSITION");
      if (position == prim.attributes.end()) fail(path_, where, "no POSITION attribute");
      const AccessorReader positions(path_, model_, position->second, where + ".POSITION");
      if (positions.components() != 3 || !positions.isFloat())
        fail(path_, positions.where(), "POSITION must be float VEC3");
      const size_t vertexCount = positions.count();
      if (vertexCount == 0) continue;
      if (vertexCount > kMaxVertices - out_.mesh.vertexCount)
        fail(path_, where,
             "the scene would have more than " + std::to_string(kMaxVertices) + " vertices");

      const uint32_t base = out_.mesh.vertexCount;
      for (size_t v = 0; v < vertexCount; ++v) {
        const glm::vec4 pw =
            world * glm::vec4(float(positions.get(v, 0)), float(positions.get(v, 1)),
                              float(positions.get(v, 2)), 1.0f);
        if (!std::isfinite(pw.x + pw.y + pw.z))
          fail(path_, positions.where(), "non-finite position");
        out_.mesh.positions.push_back(vec3(pw));
      }
      const auto accessorOf = [&](const char* name) {
        const auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
      };
      appendAttribute(accessorOf("NORMAL"), where + ".NORMAL", vertexCount, 3, out_.mesh.normals,
                      anyNormals_, [&](const AccessorReader& r, size_t v) {
                        const vec3 n = normalMatrix * vec3(float(r.get(v, 0)), float(r.get(v, 1)),
                                                           float(r.get(v, 2)));
                        return n;
                      });
      appendAttribute(accessorOf("TEXCOORD_0"), where + ".TEXCOORD_0", vertexCount, 2,
                      out_.mesh.uvs, anyUvs_, [&](const AccessorReader& r, size_t v) {
                        // glTF's v runs down the image; ours runs up.
                        return vec2(float(r.get(v, 0)), 1.0f - float(r.get(v, 1)));
                      });
      out_.mesh.vertexCount += uint32_t(vertexCount);

      std::vector<uint32_t> order;
      if (prim.indices >= 0) {
        const AccessorReader indices(path_, model_, prim.indices, where + ".indices");
        if (indices.components() != 1 || indices.isFloat())
          fail(path_, indices.where(), "indices must be unsigned integer scalars");
        order.resize(indices.count());
        for (size_t k = 0; k < order.size(); ++k) {
          const double i = indices.get(k, 0);
          if (!(i >= 0 && i < double(vertexCount)))
            fail(path_, indices.where(),
                 "index " + std::to_string(int64_t(i)) + " at " + std::to_string(k) +
                     " is not below the " + std::to_string(vertexCount) + " vertices");
          order[k] = uint32_t(i);
        }
      } else {
        order.resize(vertexCount);
        for (size_t k = 0; k < vertexCount; ++k) order[k] = uint32_t(k);
      }
      if (order.size() > 3 * kMaxVertices - out_.mesh.indices.size())
        fail(path_, where,
             "the scene would have more than " + std::to_string(kMaxVertices) + " triangles");
      uint32_t materialId;
      if (prim.material >= 0) {
        if (size_t(prim.material) >= model_.materials.size())
          fail(path_, where + ".material",
               "material " + std::to_string(prim.material) + " does not exist");
        materialId = uint32_t(prim.material);
      } else {
        materialId = defaultMaterial();
      }
      const auto triangle = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (a == b || b == c || a == c) return;  // degenerate strip joints
        if (mirrored) std::swap(b, c);
        out_.mesh.indices.insert(out_.mesh.indices.end(), {base + a, base + b, base + c});
        out_.mesh.materialIds.push_back(materialId);
      };
      if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
        if (order.size() % 3 != 0)
          fail(path_, where,
               std::to_string(order.size()) + " indices is not a whole number of triangles");
        for (size_t k = 0; k + 2 < order.size(); k += 3)
          triangle(order[k], order[k + 1], order[k + 2]);
      } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t k = 0; k + 2 < order.size(); ++k)
          k % 2 == 0 ? triangle(order[k], order[k + 1], order[k + 2])
                     : triangle(order[k + 1], order[k], order[k + 2]);
      } else {
        for (size_t k = 1; k + 1 < order.size(); ++k) triangle(order[0], order[k], order[k + 1]);
      }
    }
  }

  // Appends an optional per-vertex attribute; once one primitive has it, every vertex gets a
  // value (zeros for primitives without, and for the vertices before).
  template <typename T, typename Read>
  void appendAttribute(int accessor, const std::string& where, size_t vertexCount, int components,
                       std::vector<T>& values, bool& any, Read&& read) {
    const bool has = accessor >= 0;
    if (!has && !any) return;
    if (has && !any) {
      values.assign(out_.mesh.vertexCount, T(0.0f));
      any = true;
    }
    if (!has) {
      values.resize(values.size() + vertexCount, T(0.0f));
      return;
    }
    const AccessorReader r(path_, model_, accessor, where);
    if (r.components() != components || r.count() != vertexCount)
      fail(path_, r.where(),
           "expected " + std::to_string(vertexCount) + " VEC" + std::to_string(components) +
               " values");
    for (size_t v = 0; v < vertexCount; ++v) {
      const T value = read(r, v);
      bool finite = true;
      for (int c = 0; c < components; ++c) finite = finite && std::isfinite(value[c]);
      values.push_back(finite ? value : T(0.0f));
    }
  }

  void pickCamera(const std::string& name) {
    std::vector<std::string> names;
    const std::pair<int, mat4>* chosen = nullptr;
    for (const auto& entry : cameraNodes_) {
      const tinygltf::Node& node = model_.nodes[size_t(entry.first)];
      if (node.camera < 0 || size_t(node.camera) >= model_.cameras.size())
        fail(path_, indexed("nodes", size_t(entry.first)) + ".camera", "camera does not exist");
      const tinygltf::Camera& camera = model_.cameras[size_t(node.camera)];
      if (camera.type != "perspective") {
        warn(indexed("cameras", size_t(node.camera)) + ": " + camera.type +
             " cameras are not supported");
        continue;
      }
      const std::string label = node.name.empty() ? camera.name : node.name;
      names.push_back(label.empty() ? indexed("cameras", size_t(node.camera)) : label);
      if (chosen) continue;
      if (name.empty() || name == node.name || name == camera.name) chosen = &entry;
    }
    if (!name.empty() && !chosen) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      fail(path_, "",
           "no perspective camera named '" + name +
               "' (there are: " + (list.empty() ? "none" : list) + ")");
    }
    if (!chosen) return;
    const tinygltf::Node& node = model_.nodes[size_t(chosen->first)];
    const tinygltf::PerspectiveCamera& p = model_.cameras[size_t(node.camera)].perspective;
    const mat4& world = chosen->second;
    const vec3 eye = vec3(world * glm::vec4(0, 0, 0, 1));
    const vec3 forward = vec3(world * glm::vec4(0, 0, -1, 0));
    const vec3 up = vec3(world * glm::vec4(0, 1, 0, 0));
    if (!(glm::length(forward) > 0.0f) || !(glm::length(glm::cross(forward, up)) > 0.0f) ||
        !std::isfinite(eye.x + eye.y + eye.z))
      fail(path_, indexed("nodes", size_t(chosen->first)), "the camera's transform is degenerate");
    out_.hasCamera = true;
    out_.camera.eye = eye;
    out_.camera.lookAt = eye + glm::normalize(forward);
    out_.camera.up = glm::normalize(up);
    const double degrees = p.yfov * 180.0 / 3.14159265358979323846;
    out_.camera.vfovDegrees = degrees > 0.01 && degrees < 179.9 ? float(degrees) : 40.0f;
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  GltfData& out_;
  std::vector<char> onPath_;
  std::vector<std::pair<int, mat4>> cameraNodes_;
  std::set<std::string> warned_;
  int defaultMaterial_ = -1;
  size_t visits_ = 0;
  // Bounds on what instancing can multiply a small file into (about 2 GB of vertices).
  static constexpr size_t kMaxNodeInstances = size_t(1) << 20;
  static constexpr size_t kMaxVertices = size_t(1) << 26;
  bool anyNormals_ = false, anyUvs_ = false;
};

}  // namespace

GltfData loadGltf(const std::string& path, const std::string& cameraName) {
  const std::string ext = fs::path(path).extension().string();
  const bool binary = ext == ".glb" || ext == ".GLB";
  const std::string bytes = readFileBytes(path);
  const std::vector<std::string> files = checkUris(path, jsonText(path, bytes, binary));

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = fs::path(path).parent_path().string();
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           unsigned(bytes.size()), base)
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                          base);
  if (!ok || !err.empty()) {
    while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
    fail(path, "", err.empty() ? "cannot parse file" : err);
  }

  GltfData out;
  out.files = files;
  Converter convert(path, model, out);
  convert.materials();
  convert.nodes(cameraName);
  convert.warnAboutTheRest();
  out.mesh.name = fs::path(path).stem().string();
  if (out.mesh.indices.empty()) fail(path, "", "no triangles in the scene");
  repairNormals(out.mesh);
  return out;
}

}  // namespace penumbra
