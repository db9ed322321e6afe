// The layers glTF's material extensions put on the metallic-roughness model, for gltf_io.cpp:
// KHR_materials_specular (the dielectric base's specular layer) and KHR_materials_clearcoat (a
// clear coat over the whole material). Internal to the glTF reader.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <string>
#include <vector>

namespace penumbra::gltf {

// Reads the extensions' factors into `out` (Material::specular, specularColor, clearcoat,
// clearcoatRoughness); returns a warning for each texture of theirs, which is not read. Throws
// SceneError naming the file and the field for a malformed specularColorFactor.
std::vector<std::string> readMaterialLayers(const std::string& path, const tinygltf::Material& m,
                                            const std::string& where, Material& out);

}  // namespace penumbra::gltf
