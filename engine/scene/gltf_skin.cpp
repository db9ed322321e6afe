#include "scene/gltf_skin.h"

#include "scene/gltf_accessors.h"
#include "scene/gltf_animation.h"

#include <algorithm>
#include <cmath>

namespace penumbra::gltf {

bool SkinPose::moves() const {
  for (const std::vector<glm::mat4>& step : steps)
    if (step != steps.front()) return true;
  return false;
}

int SkinPose::segments(float radius) const {
  int most = 1;
  std::vector<glm::mat4> joint(steps.size());
  for (size_t j = 0; j < jointCount(); ++j) {
    for (size_t s = 0; s < steps.size(); ++s) joint[s] = steps[s][j];
    most = std::max(most, motionSegments(joint, radius));
  }
  return most;
}

SkinPose poseSkin(const std::string& path, const tinygltf::Model& model, int skin,
                  const std::function<const std::vector<glm::mat4>&(int node)>& worldOf,
                  const std::string& where) {
  if (skin < 0 || size_t(skin) >= model.skins.size())
    fail(path, where, "skin " + std::to_string(skin) + " does not exist");
  const tinygltf::Skin& s = model.skins[size_t(skin)];
  const std::string skinWhere = indexed("skins", size_t(skin));
  if (s.joints.empty()) fail(path, skinWhere + ".joints", "a skin needs at least one joint");
  // JOINTS_n holds 16-bit indices at most; a longer list is a damaged file, whose poses over
  // the shutter would take memory in proportion.
  constexpr size_t kMaxJoints = 65536;
  if (s.joints.size() > kMaxJoints)
    fail(path, skinWhere + ".joints", "more than " + std::to_string(kMaxJoints) + " joints");
  std::vector<glm::mat4> inverseBind(s.joints.size(), glm::mat4(1.0f));
  if (s.inverseBindMatrices >= 0) {
    const AccessorReader r(path, model, s.inverseBindMatrices, skinWhere + ".inverseBindMatrices");
    if (r.components() != 16 || r.count() < s.joints.size())
      fail(path, r.where(),
           "expected " + std::to_string(s.joints.size()) + " MAT4 values, one per joint");
    for (size_t j = 0; j < s.joints.size(); ++j)
      for (int c = 0; c < 16; ++c) {
        const double v = r.get(j, c);
        if (!std::isfinite(v)) fail(path, r.where(), "not finite");
        inverseBind[j][c / 4][c % 4] = float(v);  // column-major, as glTF stores them
      }
  }
  size_t stepCount = 1;
  std::vector<const std::vector<glm::mat4>*> worlds;
  for (size_t j = 0; j < s.joints.size(); ++j) {
    const int node = s.joints[j];
    if (node < 0 || size_t(node) >= model.nodes.size())
      fail(path, skinWhere + "." + indexed("joints", j),
           "node " + std::to_string(node) + " does not exist");
    worlds.push_back(&worldOf(node));
    stepCount = std::max(stepCount, worlds.back()->size());
  }
  SkinPose pose;
  pose.steps.assign(stepCount, std::vector<glm::mat4>(s.joints.size()));
  for (size_t step = 0; step < stepCount; ++step)
    for (size_t j = 0; j < s.joints.size(); ++j)
      pose.steps[step][j] = (*worlds[j])[std::min(step, worlds[j]->size() - 1)] * inverseBind[j];
  return pose;
}

SkinWeights::SkinWeights(const std::string& path, const tinygltf::Model& model,
                         const tinygltf::Primitive& primitive, size_t vertexCount,
                         size_t jointCount, const std::string& where) {
  for (const char* set : {"0", "1"}) {
    const auto joints = primitive.attributes.find(std::string("JOINTS_") + set);
    const auto weights = primitive.attributes.find(std::string("WEIGHTS_") + set);
    if (joints == primitive.attributes.end() && weights == primitive.attributes.end()) break;
    if (joints == primitive.attributes.end() || weights == primitive.attributes.end())
      fail(path, where,
           std::string("a skinned primitive needs both JOINTS_") + set + " and WEIGHTS_" + set);
    const AccessorReader j(path, model, joints->second, where + ".JOINTS_" + set);
    const AccessorReader w(path, model, weights->second, where + ".WEIGHTS_" + set);
    if (j.components() != 4 || j.isFloat() || j.count() != vertexCount)
      fail(path, j.where(),
           "expected " + std::to_string(vertexCount) + " VEC4 values of unsigned integers");
    if (w.components() != 4 || w.count() != vertexCount)
      fail(path, w.where(), "expected " + std::to_string(vertexCount) + " VEC4 values");
    ++sets_;
  }
  if (sets_ == 0) fail(path, where, "a skinned primitive needs JOINTS_0 and WEIGHTS_0");
  influences_.resize(4 * sets_ * vertexCount);
  for (size_t set = 0; set < sets_; ++set) {
    const std::string suffix = std::to_string(set);
    const AccessorReader j(path, model, primitive.attributes.at("JOINTS_" + suffix),
                           where + ".JOINTS_" + suffix);
    const AccessorReader w(path, model, primitive.attributes.at("WEIGHTS_" + suffix),
                           where + ".WEIGHTS_" + suffix);
    for (size_t v = 0; v < vertexCount; ++v)
      for (int c = 0; c < 4; ++c) {
        const double joint = j.get(v, c), weight = w.get(v, c);
        Influence& out = influences_[(v * sets_ + set) * 4 + size_t(c)];
        // A joint out of range is an error only where it has weight (exporters pad with 0).
        const bool weighted = weight > 0 && std::isfinite(weight);
        if (weighted && !(joint < double(jointCount)))
          fail(path, j.where(),
               "joint " + std::to_string(int64_t(joint)) + " of vertex " + std::to_string(v) +
                   " is not below the skin's " + std::to_string(jointCount) + " joints");
        out = weighted ? Influence{uint32_t(joint), float(weight)} : Influence{0, 0.0f};
      }
  }
}

glm::mat4 SkinWeights::matrix(size_t vertex, const std::vector<glm::mat4>& joints) const {
  glm::mat4 sum(0.0f);
  float total = 0;
  for (size_t i = 0; i < 4 * sets_; ++i) {
    const Influence& in = influences_[vertex * 4 * sets_ + i];
    if (in.weight == 0.0f) continue;
    sum += in.weight * joints[in.joint];
    total += in.weight;
  }
  return total > 0.0f ? sum / total : glm::mat4(1.0f);
}

}  // namespace penumbra::gltf
