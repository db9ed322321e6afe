// glTF 2.0 files (.gltf with its buffers and images, or .glb) through tinygltf, turned into
// penumbra's meshes, materials, textures and camera. docs/scene-format.md says what maps to
// what; a feature that is not rendered yet is named in `warnings`, never dropped silently.
//
// Read: triangle primitives (lists, strips, fans; indexed or not) with positions, normals
// and the first uv set, placed by the default scene's node hierarchy (TRS or matrix); the
// metallic-roughness material's base colour (factor and texture) and metallic / roughness
// factors; emissive factors (with KHR_materials_emissive_strength) as area lights;
// KHR_materials_transmission with KHR_materials_ior as glass; the first perspective camera,
// or the one named. Buffers and images are read from data: URIs, the .glb's binary chunk, or
// files by relative path only: a URI with a scheme (a network location) or an absolute path
// is refused.
#pragma once

#include "core/image.h"
#include "scene/camera.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace penumbra {

struct GltfData {
  // Every primitive of every node of the scene, in world space, as one mesh; materialIds
  // index `materials`.
  Mesh mesh;
  std::vector<Material> materials;  // albedoTexture indexes `textures`
  std::vector<Texture> textures;    // Kind::Image, imageIndex into `images`
  std::vector<Image> images;        // linear RGB (base colour factor applied)
  bool hasCamera = false;
  Camera camera;
  std::vector<std::string> warnings;  // features present but not rendered, one line each
  std::vector<std::string> files;     // external buffers and images read (relative URIs)
};

// Reads `path` (.gltf or .glb). `cameraName`, when not empty, picks the camera whose node or
// camera name it is (a SceneError lists the names there are). Throws SceneError naming the
// file and the element ("meshes[2].primitives[0]: ...").
GltfData loadGltf(const std::string& path, const std::string& cameraName = "");

}  // namespace penumbra
