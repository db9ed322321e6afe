// glTF 2.0 files (.gltf with its buffers and images, or .glb) through tinygltf, turned into
// penumbra's meshes, materials, textures and camera. docs/scene-format.md says what maps to
// what; a feature that is not rendered yet is named in `warnings`, never dropped silently.
//
// Read: triangle primitives (lists, strips, fans; indexed or not) with positions, normals
// and the first uv set, placed by the default scene's node hierarchy (TRS or matrix); the
// metallic-roughness material (Material::Type::Pbr: base colour factor and texture, metallic
// and roughness factors and texture, KHR_materials_transmission and _ior, normal maps,
// alphaMode MASK as cut-outs); emissive factors and textures (with KHR_materials_emissive_strength)
// as area lights; KHR_lights_punctual lights; node animation (translation, rotation, scale; linear,
// step, cubic spline) as motion blur; the first camera (perspective or orthographic), or the one
// named. Buffers and images are read from data: URIs, the .glb's binary chunk, or files by relative
// path only: a URI with a scheme (a network location) or an absolute path is refused.
#pragma once

#include "core/image.h"
#include "scene/camera.h"
#include "scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace penumbra {

struct GltfOptions {
  std::string camera;  // the camera's node or camera name; empty: the first one
  // Seconds into the animations at which the shutter opens (default: their start), and how
  // long it stays open. Scene time [0, 1] spans [frameTime, frameTime + shutterSeconds].
  std::optional<double> frameTime;
  double shutterSeconds = 1.0 / 48.0;
  // false: every node where it is at the frame time, all in `mesh` (no motion blur).
  bool animate = true;
  // Past this many bytes of image textures the largest are halved as each is converted
  // (fitTexturesToBudget), with a warning, so that the full-size images never all take memory
  // at once; 0: no limit.
  size_t textureBudgetBytes = 0;
};

struct GltfData {
  // Every primitive of every node of the scene that does not move while the shutter is open,
  // in world space, as one mesh; materialIds index `materials`.
  Mesh mesh;
  // The primitives that move, one mesh each, with their motion baked into vertex time steps.
  std::vector<Mesh> animatedMeshes;
  std::vector<PunctualLight> lights;  // KHR_lights_punctual, where they are at the frame time
  double frameTime = 0, shutterSeconds = 0;
  std::vector<Material> materials;   // albedoTexture indexes `textures`
  std::vector<Texture> textures;     // Kind::Image, imageIndex into `images`, factor applied
  std::vector<TextureImage> images;  // at lookup; 8-bit images stay 8-bit (texture_image.h)
  bool hasCamera = false;
  Camera camera;
  std::vector<std::string> warnings;  // features present but not rendered, one line each
  std::vector<std::string> files;     // external buffers and images read (relative URIs)
};

// Reads `path` (.gltf or .glb). `cameraName`, when not empty, picks the camera whose node or
// camera name it is (a SceneError lists the names there are). Throws SceneError naming the
// file and the element ("meshes[2].primitives[0]: ...").
GltfData loadGltf(const std::string& path, const GltfOptions& options);
GltfData loadGltf(const std::string& path, const std::string& cameraName = "");

}  // namespace penumbra
