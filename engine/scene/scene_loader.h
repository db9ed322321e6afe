// Scene files: JSON scenes (docs/scene-format.md) and Wavefront OBJ files used directly
// as scenes. Every error is a SceneError naming the file and the field, e.g.
// "scenes/balls.json: objects[2].material: unknown material 'chrom'".
#pragma once

#include "scene/scene.h"

#include <optional>
#include <string>

namespace penumbra {

struct SceneLoadOptions {
  std::string camera;  // glTF: the camera (node or camera name) to view from; empty = first
  // glTF animation: seconds into it at which the shutter opens (default: its start), and how
  // long the shutter stays open (scene time [0, 1] spans that interval).
  std::optional<double> frameTime;
  double shutterSeconds = 1.0 / 48.0;
  // The image textures' memory: past it, the largest are halved (their finest mip level
  // dropped) until they fit, with a warning; 0 keeps every level.
  size_t textureBudgetBytes = kDefaultTextureBudgetBytes;
  static constexpr size_t kDefaultTextureBudgetBytes = size_t(384) * 1000 * 1000;
};

// Loads a .json scene, a .gltf / .glb scene (its first camera, or the one named
// in options; framed automatically when it has none) or a .obj file (camera framed
// automatically) by extension.
Scene loadScene(const std::string& path, const SceneLoadOptions& options = {});
// Parses JSON scene text; `path` names it in messages, relative files resolve from `baseDir`.
Scene parseSceneJson(const std::string& text, const std::string& path, const std::string& baseDir);
// Wraps an OBJ (with its MTL) as a scene.
Scene sceneFromObj(const std::string& path);
// Wraps a glTF file as a scene (its camera, lights and animation as options say).
Scene sceneFromGltf(const std::string& path, const SceneLoadOptions& options = {});

// Replaces the scene's environment by the map in `file` (read as the scene's own; it becomes a
// watched source file), or removes it when `file` is "none". Throws SceneError naming the file.
void replaceEnvironment(Scene& scene, const std::string& file);

// Points the camera at the scene's bounding box from the front (+z side, slightly above).
void frameCamera(Scene& scene);

// Object motion over scene time [0,1]: a translation, and a rotation about an axis through
// the object's own origin (so a sphere spins in place).
struct Motion {
  vec3 translation = vec3(0.0f);
  vec3 axis = vec3(0.0f, 1.0f, 0.0f);
  float degrees = 0.0f;
  int timeSteps = 0;  // 0: chosen from the rotation (one step per 5 degrees, at most 129)
  bool moving() const;
};
// World transform of an object with rest transform `base` at scene time t.
mat4 transformAt(const mat4& base, const Motion& motion, float t);
// Number of vertex time steps used to represent `motion`.
int motionTimeSteps(const Motion& motion);
// Turns an object-space mesh into a world-space mesh with the motion baked into time steps.
Mesh placeMesh(const Mesh& objectSpace, const mat4& base, const Motion& motion);

}  // namespace penumbra
