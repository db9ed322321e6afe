// The layers glTF's material extensions put on the metallic-roughness model, for gltf_io.cpp:
// KHR_materials_specular (the dielectric base's specular layer), KHR_materials_clearcoat (a
// clear coat over the whole material), KHR_materials_sheen (fibres under the coat),
// KHR_materials_anisotropy (the specular lobes stretched along a direction),
// KHR_materials_transmission's texture and KHR_materials_volume (absorption inside it); and
// KHR_materials_unlit, which puts them all aside. Internal to the glTF reader.
#pragma once

#include "scene/scene.h"

#include "scene/gltf_textures.h"

#include <tiny_gltf.h>

#include <functional>

#include <string>
#include <vector>

namespace penumbra::gltf {

// Converts a texture reference (its texture, uv set and extensions) into one of the scene's,
// read as `texels` say; -1 when it is left out. `where` names the reference.
using LayerTexture =
    std::function<int(int index, int texCoord, const tinygltf::ExtensionMap& extensions,
                      const std::string& where, Texels texels)>;

// Reads the extensions into `out` (Material::specular, specularColor, clearcoat,
// clearcoatRoughness, sheenColor, sheenRoughness and their textures, converted by `texture`;
// transmissionTexture; the coat's normal map and its scale; attenuationColor and
// attenuationDistance; unlit; anisotropy). Throws SceneError naming the file and the field for a
// malformed colour, attenuation distance or texture reference.
void readMaterialLayers(const std::string& path, const tinygltf::Material& m,
                        const std::string& where, Material& out, const LayerTexture& texture);

// glTF's archived KHR_materials_pbrSpecularGlossiness (older exporters', Sketchfab's among
// them) when `m` has it: `m` rewritten as the metallic-roughness model with
// KHR_materials_specular, which has the same BRDF (the specular colour as f0, the diffuse
// colour under the same Fresnel mix): baseColorFactor the diffuse factor times
// 1 - max(specularFactor) (the spec's c_diff; 1 under a specular texture), baseColorTexture the
// diffuse texture, metallic 0, roughness 1 - glossiness, and specularColorFactor
// specularFactor / 0.04 (f0 at ior 1.5 is 0.04) with specularGlossinessTexture as the colour
// texture. A glossiness texture, which roughness reads as 1 - glossiness x texel, is left to
// the caller: `glossiness` receives the reference (index -1: none) and the factor. Else `m`.
// Throws SceneError naming the field for a malformed factor.
struct Glossiness {
  tinygltf::TextureInfo texture;
  float factor = 1.0f;
};
tinygltf::Material asMetallicRoughness(const std::string& path, const tinygltf::Material& m,
                                       const std::string& where, Glossiness& glossiness);

}  // namespace penumbra::gltf
