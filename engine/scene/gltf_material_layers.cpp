#include "scene/gltf_material_layers.h"

#include "scene/gltf_accessors.h"

#include <algorithm>
#include <cmath>

namespace penumbra::gltf {

namespace {

// The extension's number `key` in [0, 1] (`fallback` when absent or not finite).
float unitFactor(const tinygltf::Value& extension, const char* key, float fallback) {
  if (!extension.Has(key) || !extension.Get(key).IsNumber()) return fallback;
  const double v = extension.Get(key).GetNumberAsDouble();
  return std::isfinite(v) ? std::clamp(float(v), 0.0f, 1.0f) : fallback;
}

}  // namespace

std::vector<std::string> readMaterialLayers(const std::string& path, const tinygltf::Material& m,
                                            const std::string& where, Material& out) {
  std::vector<std::string> warnings;
  auto texturesNotRead = [&](const tinygltf::Value& e, std::initializer_list<const char*> names) {
    for (const char* t : names)
      if (e.Has(t)) warnings.push_back(where + ": " + t + " is not read (the factor is)");
  };
  if (const auto it = m.extensions.find("KHR_materials_specular");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    out.specular = unitFactor(e, "specularFactor", 1.0f);
    if (e.Has("specularColorFactor")) {
      const std::string field = where + ".extensions.KHR_materials_specular.specularColorFactor";
      const tinygltf::Value& c = e.Get("specularColorFactor");
      if (!c.IsArray() || c.ArrayLen() != 3) fail(path, field, "must be an array of three numbers");
      for (int k = 0; k < 3; ++k) {
        const double v = c.Get(k).IsNumber() ? c.Get(k).GetNumberAsDouble() : -1.0;
        if (!(v >= 0.0 && std::isfinite(v)))
          fail(path, field, "must hold three finite numbers of at least 0");
        out.specularColor[k] = float(v);
      }
    }
    texturesNotRead(e, {"specularTexture", "specularColorTexture"});
  }
  if (const auto it = m.extensions.find("KHR_materials_clearcoat");
      it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& e = it->second;
    out.clearcoat = unitFactor(e, "clearcoatFactor", 0.0f);
    out.clearcoatRoughness = unitFactor(e, "clearcoatRoughnessFactor", 0.0f);
    texturesNotRead(e, {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"});
  }
  return warnings;
}

}  // namespace penumbra::gltf
