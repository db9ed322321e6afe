// glTF skins for gltf_io.cpp: a skinned mesh is posed by its joints as they stand at the frame
// time (and over the shutter, for motion blur), by linear blend skinning: a vertex goes where
// the weighted sum of its joints' matrices (each joint's world transform times its inverse bind
// matrix) takes it, and the transform of the node holding the mesh is ignored, as glTF says.
// Internal to the glTF reader; docs/scene-format.md says what it does.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <glm/mat4x4.hpp>

#include <functional>
#include <string>
#include <vector>

namespace penumbra::gltf {

// A skin's joint matrices at each time step: one step, or as many as the motion needs.
struct SkinPose {
  std::vector<std::vector<glm::mat4>> steps;  // [step][joint]

  size_t jointCount() const { return steps.empty() ? 0 : steps.front().size(); }
  // Whether a joint's matrix differs between the steps.
  bool moves() const;
  // The fewest segments of equal time (motionSegments) that follow every joint within 0.1% of
  // `radius`, the mesh's size about its origin; the steps are kMotionSamples.
  int segments(float radius) const;
};

// Skin `skin` of the file posed: its joints' world transforms (`worldOf(node)`: one sample,
// or kMotionSamples over the shutter) times their inverse bind matrices (identity when the
// skin has none). Throws SceneError naming `where` for a damaged skin.
SkinPose poseSkin(const std::string& path, const tinygltf::Model& model, int skin,
                  const std::function<const std::vector<glm::mat4>&(int node)>& worldOf,
                  const std::string& where);

// A skinned primitive's joints and weights per vertex (JOINTS_0/WEIGHTS_0, and the _1 pair
// where a vertex has eight), checked against the skin's joint count.
class SkinWeights {
 public:
  SkinWeights(const std::string& path, const tinygltf::Model& model,
              const tinygltf::Primitive& primitive, size_t vertexCount, size_t jointCount,
              const std::string& where);

  // The vertex's matrix: its joints' matrices weighted by its weights (normalised to sum to
  // one; a vertex with no weight keeps its bind position).
  glm::mat4 matrix(size_t vertex, const std::vector<glm::mat4>& joints) const;

 private:
  struct Influence {
    uint32_t joint;
    float weight;
  };
  size_t sets_ = 0;                    // influences per vertex: 4 or 8
  std::vector<Influence> influences_;  // sets_ per vertex
};

}  // namespace penumbra::gltf
