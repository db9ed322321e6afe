#include "scene/scene_loader.h"

#include "core/image_io.h"
#include "scene/gltf_io.h"
#include "scene/mesh_io.h"
#include "scene/shapes.h"
#include "scene/tangents.h"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace penumbra {

namespace {
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// Reads typed values out of a JSON node; every error names the file and the field path.
class Reader {
 public:
  // Every file the scene refers to is added to `sources`.
  Reader(const std::string& file, const std::string& baseDir, std::vector<std::string>& sources)
      : file_(file), baseDir_(baseDir), sources_(&sources) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw SceneError(file_ + ": " + (field.empty() ? "" : field + ": ") + message);
  }

  // Rejects fields the format does not define (a typo would otherwise be silently ignored).
  void checkKeys(const Json& node, const std::string& field,
                 std::initializer_list<const char*> allowed) const {
    if (!node.is_object()) fail(field, "expected an object, got " + describe(node));
    for (const auto& item : node.items()) {
      if (std::none_of(allowed.begin(), allowed.end(),
                       [&](const char* k) { return item.key() == k; })) {
        std::string list;
        for (const char* k : allowed) list += std::string(list.empty() ? "" : ", ") + k;
        fail(join(field, item.key()), "unknown field (expected one of: " + list + ")");
      }
    }
  }

  static std::string join(const std::string& field, const std::string& key) {
    return field.empty() ? key : field + "." + key;
  }
  static std::string index(const std::string& field, size_t i) {
    return field + "[" + std::to_string(i) + "]";
  }

  static std::string describe(const Json& node) {
    std::string text = node.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return std::string(node.type_name()) + " " + text;
  }

  float number(const Json& node, const std::string& field) const {
    if (!node.is_number()) fail(field, "expected a number, got " + describe(node));
    const double v = node.get<double>();
    if (!std::isfinite(v) || std::abs(v) > 1e30) fail(field, "number out of range: " + node.dump());
    return float(v);
  }
  float number(const Json& parent, const std::string& field, const char* key,
               float fallback) const {
    return parent.contains(key) ? number(parent[key], join(field, key)) : fallback;
  }
  float positive(const Json& parent, const std::string& field, const char* key,
                 float fallback) const {
    const float v = number(parent, field, key, fallback);
    if (!(v > 0)) fail(join(field, key), "expected a positive number, got " + std::to_string(v));
    return v;
  }
  int integer(const Json& parent, const std::string& field, const char* key, int fallback, int lo,
              int hi) const {
    if (!parent.contains(key)) return fallback;
    const Json& node = parent[key];
    const std::string f = join(field, key);
    if (!node.is_number_integer()) fail(f, "expected an integer, got " + describe(node));
    const long long v = node.get<long long>();
    if (v < lo || v > hi)
      fail(f, "value " + std::to_string(v) + " outside [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
    return int(v);
  }
  bool boolean(const Json& parent, const std::string& field, const char* key, bool fallback) const {
    if (!parent.contains(key)) return fallback;
    if (!parent[key].is_boolean())
      fail(join(field, key), "expected true or false, got " + describe(parent[key]));
    return parent[key].get<bool>();
  }
  std::string string(const Json& node, const std::string& field) const {
    if (!node.is_string()) fail(field, "expected a string, got " + describe(node));
    return node.get<std::string>();
  }
  vec3 vector3(const Json& node, const std::string& field) const {
    if (node.is_number()) return vec3(number(node, field));  // a grey value
    if (!node.is_array() || node.size() != 3)
      fail(field, "expected [x, y, z], got " + describe(node));
    return {number(node[0], index(field, 0)), number(node[1], index(field, 1)),
            number(node[2], index(field, 2))};
  }
  vec3 vector3(const Json& parent, const std::string& field, const char* key, vec3 fallback) const {
    return parent.contains(key) ? vector3(parent[key], join(field, key)) : fallback;
  }
  vec3 color(const Json& parent, const std::string& field, const char* key, vec3 fallback) const {
    const vec3 c = vector3(parent, field, key, fallback);
    if (c.x < 0 || c.y < 0 || c.z < 0)
      fail(join(field, key), "colour components must not be negative");
    return c;
  }
  vec2 vector2(const Json& node, const std::string& field) const {
    if (node.is_number()) return vec2(number(node, field));
    if (!node.is_array() || node.size() != 2) fail(field, "expected [a, b], got " + describe(node));
    return {number(node[0], index(field, 0)), number(node[1], index(field, 1))};
  }
  std::string filePath(const Json& parent, const std::string& field) const {
    if (!parent.contains("file")) fail(field, "missing field 'file'");
    const std::string name = string(parent["file"], join(field, "file"));
    const fs::path p = fs::path(name).is_absolute() ? fs::path(name) : fs::path(baseDir_) / name;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) fail(join(field, "file"), "cannot open '" + p.string() + "'");
    sources_->push_back(p.string());
    return p.string();
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_, baseDir_;
  std::vector<std::string>* sources_;
};

void readRender(const Reader& r, const Json& node, RenderSettings& s) {
  const std::string f = "render";
  r.checkKeys(node, f, {"width", "height", "spp", "max_depth"});
  s.width = r.integer(node, f, "width", s.width, 1, 16384);
  s.height = r.integer(node, f, "height", s.height, 1, 16384);
  s.spp = r.integer(node, f, "spp", s.spp, 1, 1 << 20);
  s.maxDepth = r.integer(node, f, "max_depth", s.maxDepth, 0, 1024);
}

void readCamera(const Reader& r, const Json& node, Camera& c) {
  const std::string f = "camera";
  r.checkKeys(node, f,
              {"eye", "look_at", "up", "fov", "orthographic_height", "lens_radius",
               "focus_distance", "shutter"});
  c.eye = r.vector3(node, f, "eye", c.eye);
  c.lookAt = r.vector3(node, f, "look_at", c.lookAt);
  c.up = r.vector3(node, f, "up", c.up);
  c.vfovDegrees = r.number(node, f, "fov", c.vfovDegrees);
  if (!(c.vfovDegrees > 0 && c.vfovDegrees < 180))
    r.fail(f + ".fov", "expected degrees in (0, 180)");
  c.orthographicHeight = r.number(node, f, "orthographic_height", c.orthographicHeight);
  if (node.contains("orthographic_height") &&
      !(c.orthographicHeight > 0 && std::isfinite(c.orthographicHeight)))
    r.fail(f + ".orthographic_height", "expected the view's height, a number above 0");
  c.lensRadius = r.number(node, f, "lens_radius", c.lensRadius);
  if (c.lensRadius < 0) r.fail(f + ".lens_radius", "must not be negative");
  c.focusDistance = r.number(node, f, "focus_distance", c.focusDistance);
  if (c.focusDistance < 0)
    r.fail(f + ".focus_distance", "must not be negative (0 = distance to look_at)");
  if (node.contains("shutter")) {
    const vec2 s = r.vector2(node["shutter"], f + ".shutter");
    if (!(s.x >= 0 && s.y <= 1 && s.x <= s.y))
      r.fail(f + ".shutter", "expected [open, close] with 0 <= open <= close <= 1");
    c.shutterOpen = s.x;
    c.shutterClose = s.y;
  }
  if (glm::length(c.lookAt - c.eye) < 1e-6f) r.fail(f, "eye and look_at coincide");
  if (glm::length(glm::cross(c.lookAt - c.eye, c.up)) < 1e-6f * glm::length(c.lookAt - c.eye))
    r.fail(f + ".up", "up is parallel to the viewing direction");
}

void readEnvironment(const Reader& r, const Json& node, Scene& scene) {
  const std::string f = "environment";
  r.checkKeys(node, f, {"file", "strength", "rotation"});
  Environment& e = scene.environment;
  e.file = r.filePath(node, f);
  try {
    std::string warning;
    e.map = readEnvironmentMap(e.file, &warning);
    if (!warning.empty()) scene.warnings.push_back(warning);
  } catch (const SceneError& error) {
    r.fail(f + ".file", error.what());
  }
  e.strength = r.number(node, f, "strength", 1.0f);
  if (e.strength < 0) r.fail(f + ".strength", "must not be negative");
  e.rotationDegrees = r.number(node, f, "rotation", 0.0f);
}

int readTexture(const Reader& r, const Json& node, const std::string& f, Scene& scene) {
  r.checkKeys(node, f, {"type", "file", "colors", "scale"});
  if (!node.contains("type")) r.fail(f, "missing field 'type' (image, checker, stripes)");
  const std::string type = r.string(node["type"], f + ".type");
  Texture t;
  if (type == "image") {
    t.kind = Texture::Kind::Image;
    const std::string path = r.filePath(node, f);
    try {
      scene.images.push_back(readTextureImage(path));
    } catch (const std::exception& e) {
      r.fail(f + ".file", e.what());
    }
    t.imageIndex = int(scene.images.size() - 1);
  } else if (type == "checker" || type == "stripes") {
    t.kind = type == "checker" ? Texture::Kind::Checker : Texture::Kind::Stripes;
    if (node.contains("colors")) {
      const Json& colors = node["colors"];
      if (!colors.is_array() || colors.size() != 2)
        r.fail(f + ".colors", "expected two colours [[r,g,b], [r,g,b]]");
      t.color0 = r.vector3(colors[0], f + ".colors[0]");
      t.color1 = r.vector3(colors[1], f + ".colors[1]");
    }
  } else {
    r.fail(f + ".type", "unknown texture type '" + type + "' (expected image, checker, stripes)");
  }
  if (node.contains("scale")) t.scale = r.vector2(node["scale"], f + ".scale");
  if (node.contains("scale") && t.kind != Texture::Kind::Image) {
    if (!(t.scale.x > 0 && t.scale.y > 0)) r.fail(f + ".scale", "must be positive");
  }
  scene.textures.push_back(t);
  return int(scene.textures.size() - 1);
}

Material readMaterial(const Reader& r, const Json& node, const std::string& f,
                      const std::map<std::string, int>& textures) {
  r.checkKeys(node, f,
              {"type", "albedo", "color", "roughness", "ior", "emission", "radiance", "metallic",
               "transmission", "attenuation_color", "attenuation_distance"});
  if (!node.contains("type"))
    r.fail(f, "missing field 'type' (diffuse, conductor, mirror, dielectric, emissive, pbr)");
  const std::string type = r.string(node["type"], f + ".type");
  const auto unit = [&](const char* key, float fallback) {
    const float v = r.number(node, f, key, fallback);
    if (!(v >= 0 && v <= 1)) r.fail(f + "." + key, "expected a value in [0, 1]");
    return v;
  };
  const auto albedo = [&](Material& m) {
    if (node.contains("albedo") && node["albedo"].is_string()) {
      const std::string name = node["albedo"].get<std::string>();
      const auto it = textures.find(name);
      if (it == textures.end()) r.fail(f + ".albedo", "unknown texture '" + name + "'");
      m.albedoTexture = it->second;
    } else {
      m.albedo = r.color(node, f, "albedo", m.albedo);
    }
  };
  // What light inside a glass keeps: attenuation_color after attenuation_distance.
  const auto volume = [&](Material& m) {
    m.attenuationColor = r.color(node, f, "attenuation_color", vec3(1.0f));
    if (glm::any(glm::greaterThan(m.attenuationColor, vec3(1.0f))))
      r.fail(f + ".attenuation_color", "expected values in [0, 1]");
    if (node.contains("attenuation_distance"))
      m.attenuationDistance = r.positive(node, f, "attenuation_distance", 1.0f);
  };
  Material m;
  if (type == "diffuse") {
    m.type = Material::Type::Diffuse;
    albedo(m);
  } else if (type == "pbr") {
    // glTF's metallic-roughness model (docs/scene-format.md).
    m.type = Material::Type::Pbr;
    albedo(m);
    m.metallic = unit("metallic", 0.0f);
    m.roughness = std::max(unit("roughness", 0.5f), 0.02f);
    m.transmission = unit("transmission", 0.0f);
    m.ior = r.positive(node, f, "ior", 1.5f);
    volume(m);
  } else if (type == "conductor" || type == "mirror") {
    m.type = type == "mirror" ? Material::Type::Mirror : Material::Type::Conductor;
    m.albedo = r.color(node, f, "color", vec3(0.9f));
    m.roughness = r.number(node, f, "roughness", 0.3f);
    if (!(m.roughness >= 0 && m.roughness <= 1))
      r.fail(f + ".roughness", "expected a value in [0, 1]");
  } else if (type == "dielectric") {
    m.type = Material::Type::Dielectric;
    m.ior = r.positive(node, f, "ior", 1.5f);
    volume(m);
  } else if (type == "emissive") {
    m.type = Material::Type::Diffuse;
    m.albedo = vec3(0.0f);
    if (!node.contains("radiance")) r.fail(f, "missing field 'radiance' for an emissive material");
    m.emission = r.color(node, f, "radiance", vec3(0.0f));
  } else {
    r.fail(f + ".type", "unknown material type '" + type +
                            "' (expected diffuse, conductor, mirror, dielectric, emissive, pbr)");
  }
  if (node.contains("emission")) m.emission = r.color(node, f, "emission", vec3(0.0f));
  return m;
}

mat4 readTransform(const Reader& r, const Json& node, const std::string& f) {
  r.checkKeys(node, f, {"translate", "rotate", "scale", "matrix"});
  mat4 m(1.0f);
  if (node.contains("matrix")) {
    const Json& a = node["matrix"];
    if (!a.is_array() || a.size() != 16)
      r.fail(f + ".matrix", "expected 16 numbers (row-major 4x4)");
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        m[col][row] =
            r.number(a[size_t(4 * row + col)], Reader::index(f + ".matrix", size_t(4 * row + col)));
    return m;
  }
  // Applied to the object in the order scale, rotate, translate.
  m = glm::translate(m, r.vector3(node, f, "translate", vec3(0.0f)));
  if (node.contains("rotate")) {
    const Json& rot = node["rotate"];
    const std::string rf = f + ".rotate";
    if (!rot.is_array() || rot.size() != 4)
      r.fail(rf, "expected [degrees, axis_x, axis_y, axis_z]");
    // Normalised in double: a component near 1e30 would overflow a float's squared length.
    const glm::dvec3 axis(r.number(rot[1], rf + "[1]"), r.number(rot[2], rf + "[2]"),
                          r.number(rot[3], rf + "[3]"));
    if (glm::length(axis) < 1e-8) r.fail(rf, "rotation axis is zero");
    m = glm::rotate(m, glm::radians(r.number(rot[0], rf + "[0]")), vec3(glm::normalize(axis)));
  }
  if (node.contains("scale")) {
    const vec3 s = r.vector3(node["scale"], f + ".scale");
    if (s.x == 0 || s.y == 0 || s.z == 0) r.fail(f + ".scale", "scale must not be zero");
    m = glm::scale(m, s);
  }
  return m;
}

Motion readMotion(const Reader& r, const Json& node, const std::string& f) {
  r.checkKeys(node, f, {"translate", "rotate", "time_steps"});
  Motion mo;
  mo.translation = r.vector3(node, f, "translate", vec3(0.0f));
  if (node.contains("rotate")) {
    const Json& rot = node["rotate"];
    const std::string rf = f + ".rotate";
    r.checkKeys(rot, rf, {"axis", "degrees"});
    const glm::dvec3 axis(r.vector3(rot, rf, "axis", vec3(0, 1, 0)));
    if (glm::length(axis) < 1e-8) r.fail(rf + ".axis", "rotation axis is zero");
    mo.axis = vec3(glm::normalize(axis));  // in double: a huge component would overflow a float
    mo.degrees = r.number(rot, rf, "degrees", 0.0f);
  }
  mo.timeSteps = r.integer(node, f, "time_steps", 0, 2, 129);
  return mo;
}

// Moves a glTF file's images and textures into the scene; returns the texture id offset.
int appendGltfTextures(Scene& scene, GltfData& gltf) {
  const int imageOffset = int(scene.images.size()), textureOffset = int(scene.textures.size());
  for (TextureImage& image : gltf.images) scene.images.push_back(std::move(image));
  for (Texture t : gltf.textures) {
    if (t.imageIndex >= 0) t.imageIndex += imageOffset;
    scene.textures.push_back(t);
  }
  return textureOffset;
}

// Moves a texture id of a glTF file's material into the scene's numbering.
void offsetTextures(Material& m, int offset) {
  for (int* id : m.textureIds())
    if (*id >= 0) *id += offset;
}

// Object-space geometry of one object: a built-in shape or a mesh file (with the materials and
// punctual lights a file brings).
Mesh readShape(const Reader& r, const Json& node, const std::string& f, const std::string& shape,
               Scene& scene, std::vector<Material>& objMaterials, std::vector<std::string>& objMaps,
               std::vector<PunctualLight>& objLights) {
  try {
    if (shape == "sphere")
      return makeSphere(r.positive(node, f, "radius", 1.0f),
                        r.integer(node, f, "segments", 96, 3, 2048),
                        r.integer(node, f, "rings", 48, 2, 1024));
    if (shape == "rectangle") {
      const vec2 size = node.contains("size") ? r.vector2(node["size"], f + ".size") : vec2(1.0f);
      if (!(size.x > 0 && size.y > 0)) r.fail(f + ".size", "must be positive");
      return makeRectangle(size);
    }
    if (shape == "disk")
      return makeDisk(r.positive(node, f, "radius", 1.0f),
                      r.integer(node, f, "segments", 96, 3, 2048));
    if (shape == "box") {
      const vec3 size = r.vector3(node, f, "size", vec3(1.0f));
      if (!(size.x > 0 && size.y > 0 && size.z > 0)) r.fail(f + ".size", "must be positive");
      return makeBox(size);
    }
    if (shape == "cylinder")
      return makeCylinder(r.positive(node, f, "radius", 1.0f), r.positive(node, f, "height", 1.0f),
                          r.integer(node, f, "segments", 96, 3, 2048),
                          r.boolean(node, f, "capped", true));
    if (shape == "torus")
      return makeTorus(r.positive(node, f, "major_radius", 1.0f),
                       r.positive(node, f, "minor_radius", 0.25f),
                       r.integer(node, f, "segments", 128, 3, 2048),
                       r.integer(node, f, "tube_segments", 48, 3, 1024));
    if (shape == "mesh") {
      const std::string path = r.filePath(node, f);
      const std::string ext = lowercaseExtension(path);
      if (ext == ".ply") return loadPly(path);
      if (ext == ".obj") {
        ObjData obj = loadObj(path);
        scene.sourceFiles.insert(scene.sourceFiles.end(), obj.files.begin(), obj.files.end());
        for (const std::string& w : obj.warnings) scene.warnings.push_back(path + ": " + w);
        objMaterials = std::move(obj.materials);
        objMaps = std::move(obj.diffuseMaps);
        return std::move(obj.mesh);
      }
      if (ext == ".gltf" || ext == ".glb") {
        GltfOptions options;
        options.animate = false;  // the object moves by its own "motion"
        GltfData gltf = loadGltf(path, options);
        scene.sourceFiles.insert(scene.sourceFiles.end(), gltf.files.begin(), gltf.files.end());
        const int textureOffset = appendGltfTextures(scene, gltf);
        for (Material& m : gltf.materials) offsetTextures(m, textureOffset);
        for (const std::string& w : gltf.warnings) scene.warnings.push_back(path + ": " + w);
        objMaterials = std::move(gltf.materials);
        objLights = std::move(gltf.lights);
        return std::move(gltf.mesh);
      }
      r.fail(f + ".file",
             "unsupported mesh format '" + ext + "' (expected .ply, .obj, .gltf or .glb)");
    }
  } catch (const std::invalid_argument& e) {
    r.fail(f, e.what());
  }
  r.fail(f + ".shape", "unknown shape '" + shape +
                           "' (expected sphere, rectangle, disk, box, cylinder, torus, mesh)");
}

// Appends OBJ materials (and their map_Kd textures) to the scene; returns the id offset.
uint32_t appendObjMaterials(Scene& scene, const std::vector<Material>& materials,
                            const std::vector<std::string>& diffuseMaps, const std::string& where) {
  const uint32_t offset = uint32_t(scene.materials.size());
  for (size_t i = 0; i < materials.size(); ++i) {
    Material m = materials[i];
    if (i < diffuseMaps.size() && !diffuseMaps[i].empty()) {
      scene.sourceFiles.push_back(diffuseMaps[i]);
      try {
        scene.images.push_back(readTextureImage(diffuseMaps[i]));
      } catch (const std::exception& e) {
        throw SceneError(where + ": map_Kd of material '" + m.name + "': " + e.what());
      }
      Texture t;
      t.kind = Texture::Kind::Image;
      t.imageIndex = int(scene.images.size() - 1);
      scene.textures.push_back(t);
      m.albedoTexture = int(scene.textures.size() - 1);
    }
    scene.materials.push_back(m);
  }
  return offset;
}

void readObject(const Reader& r, const Json& node, const std::string& f, Scene& scene,
                const std::map<std::string, int>& materials) {
  r.checkKeys(node, f,
              {"name", "shape", "material", "transform", "motion", "flip_normals", "radius", "size",
               "segments", "rings", "height", "capped", "major_radius", "minor_radius",
               "tube_segments", "file", "material_overrides"});
  if (!node.contains("shape")) r.fail(f, "missing field 'shape'");
  const std::string shape = r.string(node["shape"], f + ".shape");
  std::vector<Material> objMaterials;
  std::vector<std::string> objMaps;
  std::vector<PunctualLight> objLights;
  Mesh mesh = readShape(r, node, f, shape, scene, objMaterials, objMaps, objLights);
  mesh.name = node.contains("name") ? r.string(node["name"], f + ".name") : shape;

  if (node.contains("material_overrides") && (node.contains("material") || objMaterials.empty()))
    r.fail(f + ".material_overrides",
           node.contains("material")
               ? "give either 'material' (for all of it) or 'material_overrides', not both"
               : "only an OBJ or glTF file brings materials to override");
  if (node.contains("material")) {
    const std::string name = r.string(node["material"], f + ".material");
    const auto it = materials.find(name);
    if (it == materials.end()) r.fail(f + ".material", "unknown material '" + name + "'");
    mesh.materialIds.assign(mesh.triangleCount(), uint32_t(it->second));
  } else if (!objMaterials.empty()) {
    // material_overrides: {"a material of the file": "a material of the scene", ...}
    std::vector<int> replaced(objMaterials.size(), -1);
    if (node.contains("material_overrides")) {
      const std::string of = f + ".material_overrides";
      const Json& overrides = node["material_overrides"];
      if (!overrides.is_object()) r.fail(of, "expected an object of material names");
      for (const auto& item : overrides.items()) {
        const std::string target = r.string(item.value(), of + "." + item.key());
        const auto named = materials.find(target);
        if (named == materials.end())
          r.fail(of + "." + item.key(), "unknown material '" + target + "'");
        bool found = false;
        for (size_t i = 0; i < objMaterials.size(); ++i)
          if (objMaterials[i].name == item.key()) {
            replaced[i] = named->second;
            found = true;
          }
        if (!found) {
          std::string names;
          for (const Material& m : objMaterials) names += (names.empty() ? "" : ", ") + m.name;
          r.fail(of + "." + item.key(),
                 "the file has no material '" + item.key() + "' (it has: " + names + ")");
        }
      }
    }
    const uint32_t offset = appendObjMaterials(scene, objMaterials, objMaps, r.file() + ": " + f);
    for (uint32_t& id : mesh.materialIds)
      id = id < replaced.size() && replaced[id] >= 0 ? uint32_t(replaced[id]) : id + offset;
  } else {
    r.fail(f, "missing field 'material'");
  }
  if (r.boolean(node, f, "flip_normals", false)) {
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
      std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
    for (vec3& n : mesh.normals) n = -n;
    // The bitangent, w·cross(n, t), keeps its direction.
    for (glm::vec4& t : mesh.tangents) t.w = -t.w;
  }
  const mat4 base = node.contains("transform")
                        ? readTransform(r, node["transform"], f + ".transform")
                        : mat4(1.0f);
  const Motion motion =
      node.contains("motion") ? readMotion(r, node["motion"], f + ".motion") : Motion{};
  if (!(std::abs(glm::determinant(glm::mat3(base))) >= 1e-12f))
    r.fail(f + ".transform", "transform is singular or not finite");
  // Motion copies every vertex per time step: refuse what would not fit in memory.
  constexpr double kMaxVertexSteps = 5e7;
  if (double(mesh.vertexCount) * motionTimeSteps(motion) > kMaxVertexSteps)
    r.fail(f + ".motion", std::to_string(mesh.vertexCount) + " vertices x " +
                              std::to_string(motionTimeSteps(motion)) +
                              " time steps is too large; use fewer segments or time_steps");
  try {
    scene.meshes.push_back(placeMesh(mesh, base, motion));
  } catch (const std::invalid_argument& e) {
    r.fail(f + (node.contains("motion") ? ".motion" : ".transform"), e.what());
  }
  // An included file's lights go where the object's transform puts them (at rest).
  for (PunctualLight light : objLights) {
    light.position = vec3(base * glm::vec4(light.position, 1.0f));
    light.direction = glm::normalize(glm::mat3(base) * light.direction);
    scene.lights.push_back(light);
  }
}

// A punctual light: {"type": "point" | "spot" | "directional", "position", "direction",
// "color", "intensity", "inner_angle", "outer_angle", "range"} (angles in degrees, as glTF's
// cones; range as glTF's, 0 or absent for none).
PunctualLight readLight(const Reader& r, const Json& node, const std::string& f) {
  r.checkKeys(node, f,
              {"name", "type", "position", "direction", "color", "intensity", "inner_angle",
               "outer_angle", "range"});
  if (!node.contains("type")) r.fail(f, "missing field 'type' (point, spot, directional)");
  const std::string type = r.string(node["type"], f + ".type");
  PunctualLight light;
  if (type == "point")
    light.kind = PunctualLight::Kind::Point;
  else if (type == "spot")
    light.kind = PunctualLight::Kind::Spot;
  else if (type == "directional")
    light.kind = PunctualLight::Kind::Directional;
  else
    r.fail(f + ".type", "unknown light type '" + type + "' (expected point, spot, directional)");
  light.name = node.contains("name") ? r.string(node["name"], f + ".name") : f;
  light.position = r.vector3(node, f, "position", vec3(0.0f));
  const vec3 direction = r.vector3(node, f, "direction", vec3(0.0f, -1.0f, 0.0f));
  if (!(glm::length(direction) > 1e-8f)) r.fail(f + ".direction", "direction is zero");
  light.direction = glm::normalize(direction);
  const float intensity = r.number(node, f, "intensity", 1.0f);
  if (!(intensity >= 0)) r.fail(f + ".intensity", "must not be negative");
  light.intensity = r.color(node, f, "color", vec3(1.0f)) * intensity;
  const float inner = r.number(node, f, "inner_angle", 0.0f);
  const float outer = r.number(node, f, "outer_angle", 45.0f);
  if (!(inner >= 0 && inner <= outer && outer <= 90))
    r.fail(f + ".outer_angle", "expected 0 <= inner_angle <= outer_angle <= 90 degrees");
  light.cosInner = std::cos(glm::radians(inner));
  light.cosOuter = std::cos(glm::radians(outer));
  light.range = r.number(node, f, "range", 0.0f);
  if (!(light.range >= 0 && std::isfinite(light.range)))
    r.fail(f + ".range", "expected a distance >= 0 (0: the light never ends)");
  if (light.range > 0 && light.kind == PunctualLight::Kind::Directional)
    r.fail(f + ".range", "a directional light has no range");
  return light;
}

std::string lineAndColumn(const std::string& text, size_t byte) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

std::string readTextFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw SceneError(path + ": cannot open file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

Scene parseSceneJson(const std::string& text, const std::string& path, const std::string& baseDir) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    const size_t cut = what.find("syntax error");
    throw SceneError(path + ":" + lineAndColumn(text, e.byte == 0 ? 0 : e.byte - 1) + ": " +
                     (cut == std::string::npos ? what : what.substr(cut)));
  } catch (const Json::exception& e) {  // e.g. a number too large for a double
    std::string what = e.what();
    const size_t cut = what.find("] ");
    throw SceneError(path + ": " + (cut == std::string::npos ? what : what.substr(cut + 2)));
  }
  Scene scene;
  scene.sourcePath = path;
  scene.sourceFiles.push_back(path);
  const Reader r(path, baseDir, scene.sourceFiles);
  r.checkKeys(root, "",
              {"render", "camera", "background", "environment", "textures", "materials", "objects",
               "lights"});
  if (root.contains("render")) readRender(r, root["render"], scene.settings);
  if (root.contains("camera")) readCamera(r, root["camera"], scene.camera);
  if (root.contains("background")) scene.background = r.color(root, "", "background", vec3(0.0f));
  if (root.contains("environment")) readEnvironment(r, root["environment"], scene);

  std::map<std::string, int> textures, materials;
  if (root.contains("textures")) {
    if (!root["textures"].is_object()) r.fail("textures", "expected an object of named textures");
    for (const auto& item : root["textures"].items())
      textures[item.key()] = readTexture(r, item.value(), "textures." + item.key(), scene);
  }
  if (!root.contains("materials") || !root["materials"].is_object())
    r.fail("materials", "expected an object of named materials");
  for (const auto& item : root["materials"].items()) {
    Material m = readMaterial(r, item.value(), "materials." + item.key(), textures);
    m.name = item.key();
    materials[item.key()] = int(scene.materials.size());
    scene.materials.push_back(m);
  }
  if (!root.contains("objects") || !root["objects"].is_array() || root["objects"].empty())
    r.fail("objects", "expected a non-empty array of objects");
  const Json& objects = root["objects"];
  for (size_t i = 0; i < objects.size(); ++i)
    readObject(r, objects[i], Reader::index("objects", i), scene, materials);
  if (root.contains("lights")) {
    if (!root["lights"].is_array()) r.fail("lights", "expected an array of lights");
    for (size_t i = 0; i < root["lights"].size(); ++i)
      scene.lights.push_back(readLight(r, root["lights"][i], Reader::index("lights", i)));
  }
  return scene;
}

// A glTF or OBJ file opened as a scene by itself is an asset: if nothing in it lights it (no
// punctual light, no emitter other than textured emission, which is decoration), it gets the
// built-in environment, as other glTF viewers give it.
namespace {
void lightUnlitAsset(Scene& scene) {
  if (!scene.lights.empty() || scene.environment.present()) return;
  std::vector<bool> used(scene.materials.size(), false);
  for (const Mesh& mesh : scene.meshes)
    for (uint32_t id : mesh.materialIds) used[id] = true;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    if (used[i] && m.isEmissive() && m.emissionTexture < 0) return;
  }
  scene.environment.map = builtinEnvironmentMap();
  scene.environment.builtin = true;
}
}  // namespace

Scene sceneFromObj(const std::string& path) {
  ObjData obj = loadObj(path);
  Scene scene;
  scene.sourcePath = path;
  scene.sourceFiles.push_back(path);
  scene.sourceFiles.insert(scene.sourceFiles.end(), obj.files.begin(), obj.files.end());
  for (const std::string& w : obj.warnings) scene.warnings.push_back(path + ": " + w);
  const uint32_t offset = appendObjMaterials(scene, obj.materials, obj.diffuseMaps, path);
  for (uint32_t& id : obj.mesh.materialIds) id += offset;
  obj.mesh.name = fs::path(path).stem().string();
  if (obj.mesh.triangleCount() == 0) throw SceneError(path + ": no faces");
  scene.meshes.push_back(std::move(obj.mesh));
  frameCamera(scene);
  lightUnlitAsset(scene);
  return scene;
}

Scene sceneFromGltf(const std::string& path, const SceneLoadOptions& options) {
  GltfOptions gltfOptions;
  gltfOptions.camera = options.camera;
  gltfOptions.frameTime = options.frameTime;
  gltfOptions.shutterSeconds = options.shutterSeconds;
  gltfOptions.textureBudgetBytes = options.textureBudgetBytes;
  GltfData gltf = loadGltf(path, gltfOptions);
  Scene scene;
  scene.sourcePath = path;
  scene.sourceFiles.push_back(path);
  scene.sourceFiles.insert(scene.sourceFiles.end(), gltf.files.begin(), gltf.files.end());
  appendGltfTextures(scene, gltf);
  scene.materials = std::move(gltf.materials);
  if (!gltf.mesh.indices.empty()) scene.meshes.push_back(std::move(gltf.mesh));
  for (Mesh& mesh : gltf.animatedMeshes) scene.meshes.push_back(std::move(mesh));
  scene.lights = std::move(gltf.lights);
  for (const std::string& w : gltf.warnings) scene.warnings.push_back(path + ": " + w);
  if (gltf.hasCamera)
    scene.camera = gltf.camera;
  else
    frameCamera(scene);
  lightUnlitAsset(scene);
  return scene;
}

namespace {

// Halves the largest image textures until they fit the budget, saying so in a warning.
void fitTextures(const std::string& path, Scene& scene, size_t budgetBytes) {
  if (budgetBytes == 0) return;
  size_t before = 0;
  for (const TextureImage& image : scene.images) before += image.byteSize();
  if (before <= budgetBytes) return;
  const int dropped = fitTexturesToBudget(scene.images, budgetBytes);
  size_t after = 0;
  for (const TextureImage& image : scene.images) after += image.byteSize();
  scene.warnings.push_back(path + ": " + textureBudgetWarning(before, budgetBytes, after, dropped));
}

Scene loadSceneFile(const std::string& path, const SceneLoadOptions& options) {
  const std::string ext = lowercaseExtension(path);
  if (!options.camera.empty() && ext != ".gltf" && ext != ".glb")
    throw SceneError(path + ": --camera picks a camera of a glTF scene; this is a '" + ext +
                     "' file");
  if (options.frameTime && ext != ".gltf" && ext != ".glb")
    throw SceneError(path +
                     ": --frame-time picks a moment of a glTF scene's animation; this is a '" +
                     ext + "' file");
  if (ext == ".obj") return sceneFromObj(path);
  if (ext == ".gltf" || ext == ".glb") return sceneFromGltf(path, options);
  if (ext != ".json")
    throw SceneError(path + ": unsupported scene format '" + ext +
                     "' (expected .json, .gltf, .glb or .obj)");
  const std::string text = readTextFile(path);
  return parseSceneJson(text, path, fs::path(path).parent_path().string());
}

}  // namespace

Scene loadScene(const std::string& path, const SceneLoadOptions& options) {
  Scene scene = loadSceneFile(path, options);
  fitTextures(path, scene, options.textureBudgetBytes);
  generateTangents(scene);
  return scene;
}

void replaceEnvironment(Scene& scene, const std::string& file) {
  Environment& e = scene.environment;
  if (file == "none") {
    e = Environment{};
    return;
  }
  std::string warning;
  e.map = readEnvironmentMap(file, &warning);
  if (!warning.empty()) scene.warnings.push_back(warning);
  e.file = file;
  e.builtin = false;
  scene.sourceFiles.push_back(file);
}

void frameCamera(Scene& scene) {
  vec3 lo, hi;
  sceneBounds(scene, lo, hi);
  if (!(lo.x <= hi.x)) return;
  const vec3 center = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  Camera& c = scene.camera;
  const float halfFov = glm::radians(0.5f * c.vfovDegrees);
  const float distance = 1.1f * radius / std::sin(halfFov);
  c.lookAt = center;
  c.eye = center + distance * glm::normalize(vec3(0.0f, 0.25f, 1.0f));
  c.up = vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace penumbra
