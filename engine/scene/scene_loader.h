// Scene files: JSON scenes (docs/scene-format.md) and Wavefront OBJ files used directly
// as scenes. Every error is a SceneError naming the file and the field, e.g.
// "scenes/balls.json: objects[2].material: unknown material 'chrom'".
#pragma once

#include "scene/scene.h"

#include <string>

namespace penumbra {

// Loads a .json scene or a .obj file (camera framed automatically) by extension.
Scene loadScene(const std::string& path);
// Parses JSON scene text; `path` names it in messages, relative files resolve from `baseDir`.
Scene parseSceneJson(const std::string& text, const std::string& path, const std::string& baseDir);
// Wraps an OBJ (with its MTL) as a scene.
Scene sceneFromObj(const std::string& path);

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
