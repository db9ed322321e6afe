// glTF morph targets for gltf_io.cpp: a primitive's vertices moved by the weighted sum of its
// targets' displacements (positions, normals, tangents), with the weights of the node (or its
// mesh's defaults) as they stand at the frame time, and over the shutter when an animation
// drives them. Morphing comes before skinning, as glTF says. Internal to the glTF reader;
// docs/scene-format.md says what it does.
#pragma once

#include "scene/gltf_animation.h"
#include "scene/scene.h"

#include <tiny_gltf.h>

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <vector>

namespace penumbra::gltf {

// A node's morph weights over time: keyframe times and, per key, one weight per target (three
// sets per key for CUBICSPLINE: in-tangents, values, out-tangents).
struct WeightsTrack {
  Track::Interpolation interpolation = Track::Interpolation::Linear;
  size_t targets = 0;
  std::vector<double> times;
  std::vector<double> values;  // [(key * parts + part) * targets + target]

  // The weights at time t (held at the first and last keys outside them).
  std::vector<float> at(double t) const;
};

// Reads a "weights" channel's sampler (SCALAR outputs, `targets` per key). Throws SceneError
// naming `where`.
WeightsTrack readWeightsTrack(const std::string& path, const tinygltf::Model& model,
                              const tinygltf::Animation& animation,
                              const tinygltf::AnimationChannel& channel, size_t targets,
                              const std::string& where);

// The fewest segments (1, 2, 4, ... 128 of equal time) whose linear interpolation of the
// weights (kMotionSamples sets evenly over the shutter) stays within 0.001 of every sample.
int weightSegments(const std::vector<std::vector<float>>& samples);

// The morph targets of node `index`'s mesh (its first primitive's; 0 without a mesh).
size_t morphTargetCount(const tinygltf::Model& model, int index);

// A node's morph weights at each of `times`: its animation's (`track`), else the node's, else
// its mesh's (then one set). Empty: none.
std::vector<std::vector<float>> morphWeights(const tinygltf::Model& model,
                                             const tinygltf::Node& node,
                                             const std::optional<WeightsTrack>& track,
                                             const std::vector<double>& times);

// A primitive's morph targets: per target, the displacement of each vertex's position, normal
// and tangent (each may be absent). Only the targets with a weight in `weights` (per step) are
// read: a face rig's many shapes mostly rest at 0.
class MorphTargets {
 public:
  MorphTargets(const std::string& path, const tinygltf::Model& model,
               const tinygltf::Primitive& primitive, size_t vertexCount,
               const std::vector<std::vector<float>>& weights, const std::string& where);

  size_t count() const { return targets_.size(); }
  // `value` of vertex v displaced by the weighted sum of the targets' `attribute` (0: POSITION,
  // 1: NORMAL, 2: TANGENT) displacements; weights past the targets are ignored, missing ones 0.
  glm::vec3 displaced(int attribute, size_t v, glm::vec3 value,
                      const std::vector<float>& weights) const;

 private:
  struct Target {
    std::vector<glm::vec3> deltas[3];  // POSITION, NORMAL, TANGENT; empty: none
  };
  std::vector<Target> targets_;
};

}  // namespace penumbra::gltf
