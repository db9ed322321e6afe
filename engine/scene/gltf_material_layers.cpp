#include "scene/gltf_material_layers.h"

#include "scene/gltf_accessors.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra::gltf {

namespace {

// The extension's number `key` in [0, 1] (`fallback` when absent or not finite).
float unitFactor(const tinygltf::Value& extension, const char* key, float fallback) {
  if (!extension.Has(key) || !extension.Get(key).IsNumber()) return fallback;
  const double v = extension.Get(key).GetNumberAsDouble();
  return std::isfinite(v) ? std::clamp(float(v), 0.0f, 1.0f) : fallback;
}

// The extension's number `key`, finite and at least `least` (more than 0 when `least` is 0 and
// `positive`); `fallback` when absent. Throws SceneError naming `field`.key otherwise.
float readNumber(const std::string& path, const tinygltf::Value& extension, const char* key,
                 const std::string& field, float fallback, bool positive) {
  if (!extension.Has(key)) return fallback;
  const tinygltf::Value& n = extension.Get(key);
  const double v = n.IsNumber() ? n.GetNumberAsDouble() : NAN;
  if (!std::isfinite(v) || v < 0.0 || (positive && !(v > 0.0)))
    fail(path, field + "." + key,
         positive ? "must be a finite number above 0" : "must be a finite number of at least 0");
  return float(v);
}

// The extension's colour `key` (three finite numbers of at least 0, and at most `most`) into
// `out`; left as it is when absent. Throws SceneError naming `field`.key otherwise.
void readColor(const std::string& path, const tinygltf::Value& extension, const char* key,
               const std::string& field, float most, vec3& out) {
  if (!extension.Has(key)) return;
  const tinygltf::Value& c = extension.Get(key);
  const std::string where = field + "." + key;
  if (!c.IsArray() || c.ArrayLen() != 3) fail(path, where, "must be an array of three numbers");
  for (int k = 0; k < 3; ++k) {
    const double v = c.Get(k).IsNumber() ? c.Get(k).GetNumberAsDouble() : -1.0;
    if (!(v >= 0.0 && v <= most && std::isfinite(v)))
      fail(path, where,
           "must hold three finite numbers of at least 0" +
               (std::isfinite(most) ? " and at most " + number(most) : std::string()));
    out[k] = float(v);
  }
}

// The texture reference `key` of an extension as tinygltf's (index -1 when absent). Throws
// SceneError naming where.key when it is not an object with an integer index.
tinygltf::TextureInfo textureInfo(const std::string& path, const tinygltf::Value& extension,
                                  const char* key, const std::string& where) {
  tinygltf::TextureInfo info;
  if (!extension.Has(key)) return info;
  const tinygltf::Value& v = extension.Get(key);
  if (!v.IsObject() || !v.Has("index") || !v.Get("index").IsInt())
    fail(path, where + "." + key, "must be a texture reference with an index");
  info.index = v.Get("index").GetNumberAsInt();
  if (v.Has("texCoord") && v.Get("texCoord").IsInt())
    info.texCoord = v.Get("texCoord").GetNumberAsInt();
  if (v.Has("extensions") && v.Get("extensions").IsObject())
    for (const std::string& name : v.Get("extensions").Keys())
      info.extensions[name] = v.Get("extensions").Get(name);
  return info;
}

// The extension's texture reference `key` converted by `texture`; -1 when absent.
int layerTexture(const std::string& path, const tinygltf::Value& extension, const char* key,
                 const std::string& where, Texels texels, const LayerTexture& texture) {
  const tinygltf::TextureInfo info = textureInfo(path, extension, key, where);
  if (info.index < 0) return -1;
  return texture(info.index, info.texCoord, info.extensions, where + "." + key, texels);
}

}  // namespace

void readMaterialLayers(const std::string& path, const tinygltf::Material& m,
                        const std::string& where, Material& out, const LayerTexture& texture) {
  out.unlit = m.extensions.count("KHR_materials_unlit") > 0;
  if (const auto it = m.extensions.find("KHR_materials_specular");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    out.specular = unitFactor(e, "specularFactor", 1.0f);
    const std::string field = where + ".extensions.KHR_materials_specular";
    readColor(path, e, "specularColorFactor", field, INFINITY, out.specularColor);
    // The weight is in the alpha channel; an image without one is 1 (the factor alone).
    out.specularTexture = layerTexture(path, e, "specularTexture", field, Texels::Alpha, texture);
    out.specularColorTexture =
        layerTexture(path, e, "specularColorTexture", field, Texels::Color, texture);
  }
  if (const auto it = m.extensions.find("KHR_materials_clearcoat");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    out.clearcoat = unitFactor(e, "clearcoatFactor", 0.0f);
    out.clearcoatRoughness = unitFactor(e, "clearcoatRoughnessFactor", 0.0f);
    const std::string field = where + ".extensions.KHR_materials_clearcoat";
    out.clearcoatTexture = layerTexture(path, e, "clearcoatTexture", field, Texels::Data, texture);
    out.clearcoatRoughnessTexture =
        layerTexture(path, e, "clearcoatRoughnessTexture", field, Texels::Data, texture);
    out.clearcoatNormalTexture =
        layerTexture(path, e, "clearcoatNormalTexture", field, Texels::Data, texture);
    if (out.clearcoatNormalTexture >= 0) {
      const tinygltf::Value& info = e.Get("clearcoatNormalTexture");
      if (info.Has("scale") && info.Get("scale").IsNumber() &&
          std::isfinite(info.Get("scale").GetNumberAsDouble()))
        out.clearcoatNormalScale = float(info.Get("scale").GetNumberAsDouble());
    }
  }
  if (const auto it = m.extensions.find("KHR_materials_sheen");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    const std::string field = where + ".extensions.KHR_materials_sheen";
    readColor(path, e, "sheenColorFactor", field, 1.0f, out.sheenColor);
    out.sheenRoughness = unitFactor(e, "sheenRoughnessFactor", 0.0f);
    out.sheenColorTexture =
        layerTexture(path, e, "sheenColorTexture", field, Texels::Color, texture);
    // The roughness is in the alpha channel; an image without one is 1 (the factor alone).
    out.sheenRoughnessTexture =
        layerTexture(path, e, "sheenRoughnessTexture", field, Texels::Alpha, texture);
  }
  if (const auto it = m.extensions.find("KHR_materials_anisotropy");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    const std::string field = where + ".extensions.KHR_materials_anisotropy";
    out.anisotropyStrength = unitFactor(e, "anisotropyStrength", 0.0f);
    if (e.Has("anisotropyRotation")) {
      const tinygltf::Value& r = e.Get("anisotropyRotation");
      const double v = r.IsNumber() ? r.GetNumberAsDouble() : NAN;
      if (!std::isfinite(v)) fail(path, field + ".anisotropyRotation", "must be a finite number");
      out.anisotropyRotation = float(v);
    }
    out.anisotropyTexture =
        layerTexture(path, e, "anisotropyTexture", field, Texels::Data, texture);
  }
  if (const auto it = m.extensions.find("KHR_materials_iridescence");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    const std::string field = where + ".extensions.KHR_materials_iridescence";
    out.iridescence = unitFactor(e, "iridescenceFactor", 0.0f);
    out.iridescenceIor = readNumber(path, e, "iridescenceIor", field, 1.3f, true);
    out.iridescenceThicknessMin =
        readNumber(path, e, "iridescenceThicknessMinimum", field, 100.0f, false);
    out.iridescenceThicknessMax =
        readNumber(path, e, "iridescenceThicknessMaximum", field, 400.0f, false);
    out.iridescenceTexture =
        layerTexture(path, e, "iridescenceTexture", field, Texels::Data, texture);
    out.iridescenceThicknessTexture =
        layerTexture(path, e, "iridescenceThicknessTexture", field, Texels::Data, texture);
  }
  if (const auto it = m.extensions.find("KHR_materials_transmission");
      it != m.extensions.end() && it->second.IsObject())
    out.transmissionTexture =
        layerTexture(path, it->second, "transmissionTexture",
                     where + ".extensions.KHR_materials_transmission", Texels::Data, texture);
  // A volume (thicknessFactor > 0; 0 is a thin wall, which light crosses unchanged) absorbs
  // what travels inside it. Its thickness is a rasteriser's stand-in for the geometry, which a
  // path tracer has: not needed.
  if (const auto it = m.extensions.find("KHR_materials_volume");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    const std::string field = where + ".extensions.KHR_materials_volume";
    const bool thick = e.Has("thicknessFactor") && e.Get("thicknessFactor").IsNumber() &&
                       e.Get("thicknessFactor").GetNumberAsDouble() > 0;
    if (thick) {
      readColor(path, e, "attenuationColor", field, 1.0f, out.attenuationColor);
      if (e.Has("attenuationDistance")) {
        const tinygltf::Value& d = e.Get("attenuationDistance");
        const double v = d.IsNumber() ? d.GetNumberAsDouble() : -1.0;
        if (!(v > 0)) fail(path, field + ".attenuationDistance", "must be a number above 0");
        out.attenuationDistance = float(v);
      }
    }
  }
}

namespace {

tinygltf::Value textureValue(const tinygltf::TextureInfo& info) {
  tinygltf::Value::Object o;
  o["index"] = tinygltf::Value(info.index);
  o["texCoord"] = tinygltf::Value(info.texCoord);
  if (!info.extensions.empty()) {
    tinygltf::Value::Object e(info.extensions.begin(), info.extensions.end());
    o["extensions"] = tinygltf::Value(std::move(e));
  }
  return tinygltf::Value(std::move(o));
}

}  // namespace

tinygltf::Material asMetallicRoughness(const std::string& path, const tinygltf::Material& m,
                                       const std::string& where, Glossiness& glossiness) {
  const auto it = m.extensions.find("KHR_materials_pbrSpecularGlossiness");
  if (it == m.extensions.end() || !it->second.IsObject()) return m;
  const tinygltf::Value& e = it->second;
  const std::string field = where + ".extensions.KHR_materials_pbrSpecularGlossiness";
  vec3 specular(1.0f);
  readColor(path, e, "specularFactor", field, 1.0f, specular);
  glossiness.factor = unitFactor(e, "glossinessFactor", 1.0f);
  glossiness.texture = textureInfo(path, e, "specularGlossinessTexture", field);
  std::array<double, 4> diffuse{1, 1, 1, 1};
  if (e.Has("diffuseFactor")) {
    const tinygltf::Value& d = e.Get("diffuseFactor");
    if (!d.IsArray() || d.ArrayLen() != 4)
      fail(path, field + ".diffuseFactor", "must be an array of four numbers");
    for (int k = 0; k < 4; ++k) {
      diffuse[size_t(k)] = d.Get(k).IsNumber() ? d.Get(k).GetNumberAsDouble() : -1.0;
      if (!(diffuse[size_t(k)] >= 0.0 && diffuse[size_t(k)] <= 1.0))
        fail(path, field + ".diffuseFactor", "must hold four numbers in [0, 1]");
    }
  }
  tinygltf::Material out = m;
  out.extensions.erase("KHR_materials_pbrSpecularGlossiness");
  // c_diff's 1 - max(specular), where the specular colour is the factor alone; under a
  // specular texture it varies per texel (dielectrics' few percent, usually), and the diffuse
  // colour is taken whole: the factor (1 by default) says nothing of it.
  const double keep =
      glossiness.texture.index >= 0 ? 1.0 : 1.0 - std::max({specular.x, specular.y, specular.z});
  out.pbrMetallicRoughness.baseColorFactor = {diffuse[0] * keep, diffuse[1] * keep,
                                              diffuse[2] * keep, diffuse[3]};
  out.pbrMetallicRoughness.baseColorTexture = textureInfo(path, e, "diffuseTexture", field);
  out.pbrMetallicRoughness.metallicFactor = 0.0;
  out.pbrMetallicRoughness.roughnessFactor = 1.0 - glossiness.factor;
  out.pbrMetallicRoughness.metallicRoughnessTexture = tinygltf::TextureInfo();
  tinygltf::Value::Object layer;
  layer["specularFactor"] = tinygltf::Value(1.0);
  tinygltf::Value::Array colour;
  for (int k = 0; k < 3; ++k) colour.push_back(tinygltf::Value(double(specular[k]) / 0.04));
  layer["specularColorFactor"] = tinygltf::Value(std::move(colour));
  if (glossiness.texture.index >= 0)
    layer["specularColorTexture"] = textureValue(glossiness.texture);
  out.extensions["KHR_materials_specular"] = tinygltf::Value(std::move(layer));
  out.extensions.erase("KHR_materials_ior");
  return out;
}

}  // namespace penumbra::gltf
