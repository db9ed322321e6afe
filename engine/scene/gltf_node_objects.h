// What a glTF node holds besides a mesh, for gltf_io.cpp: its KHR_lights_punctual light and its
// camera, placed by the node's world transform, and the instances of its mesh that
// EXT_mesh_gpu_instancing lists. Internal to the glTF reader;
// docs/scene-format.md says what it does.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <glm/mat4x4.hpp>

#include <string>
#include <utility>
#include <vector>

namespace penumbra::gltf {

// The light of `node` (its KHR_lights_punctual extension) where `world` places it: at the
// node's origin, shining along its -z. Throws SceneError naming `where` for a light that does
// not exist, an unknown type, a non-finite intensity or range, or a degenerate transform.
PunctualLight readPunctualLight(const std::string& path, const tinygltf::Model& model,
                                const tinygltf::Node& node, const glm::mat4& world,
                                const std::string& where);

// The transforms of a node's EXT_mesh_gpu_instancing instances (T·R·S of each instance's
// TRANSLATION, ROTATION and SCALE, those it lacks the identity), applied before the node's own
// transform; empty when the node has none. Throws SceneError naming the extension's field for
// attributes that are not VEC3 / VEC4 or disagree on the count.
std::vector<glm::mat4> readInstances(const std::string& path, const tinygltf::Model& model,
                                     const tinygltf::Node& node, const std::string& where);

// The camera named `name` (the first when `name` is empty) among `cameraNodes` (a node and
// its world transform), set in `out`: a perspective one's field of view, or an orthographic
// one's height (2 ymag); false when there is none. Other camera types, and orthographic ones
// whose ymag is 0 or not finite, are left out with a line in `warnings`. Throws SceneError when
// `name` names no camera, or the chosen camera's transform is degenerate.
bool pickCamera(const std::string& path, const tinygltf::Model& model,
                const std::vector<std::pair<int, glm::mat4>>& cameraNodes, const std::string& name,
                Camera& out, std::vector<std::string>& warnings);

}  // namespace penumbra::gltf
