// glTF node animation for gltf_io.cpp: a channel's keyframes read and checked, sampled at any
// time (LINEAR with slerp for rotations, STEP, CUBICSPLINE), and the number of time steps a
// motion needs. Internal to the glTF reader; docs/scene-format.md says what it does.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <glm/vec4.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace penumbra::gltf {

// One animated property of a node: keyframe times and values (for CUBICSPLINE, three values per
// key: in-tangent, value, out-tangent).
struct Track {
  enum class Path { Translation, Rotation, Scale };
  enum class Interpolation { Linear, Step, CubicSpline };
  Path path = Path::Translation;
  Interpolation interpolation = Interpolation::Linear;
  std::vector<double> times;
  std::vector<glm::dvec4> values;

  glm::dvec4 value(size_t key, int part) const {
    return interpolation == Interpolation::CubicSpline ? values[3 * key + size_t(part)]
                                                       : values[key];
  }

  // The property at time t (held at the first and last keys outside them); rotations by
  // slerp, CUBICSPLINE by glTF's Hermite formula.
  glm::dvec4 at(double t) const;
};

// Reads `channel`'s sampler's interpolation and keyframe times (finite, increasing); returns the
// sampler. Throws SceneError naming `where`.
const tinygltf::AnimationSampler& readKeyTimes(
    const std::string& path, const tinygltf::Model& model, const tinygltf::Animation& animation,
    const tinygltf::AnimationChannel& channel, const std::string& where,
    Track::Interpolation& interpolation, std::vector<double>& times);

// Reads `channel`'s sampler: keyframe times (finite, increasing) and values (VEC3, or VEC4 for a
// rotation; three per key for CUBICSPLINE). Throws SceneError naming `where`.
Track readTrack(const std::string& path, const tinygltf::Model& model,
                const tinygltf::Animation& animation, const tinygltf::AnimationChannel& channel,
                const std::string& where);

// Node `index`'s local transform at animation time t: its TRS with the parts its `tracks`
// animate replaced. Throws SceneError when the rotation is not a quaternion.
glm::mat4 animatedLocal(const std::string& path, const tinygltf::Node& node, size_t index,
                        const std::vector<Track>& tracks, double t);

// The samples of a transform over the shutter that motion is measured on.
constexpr int kMotionSamples = 129;

// The fewest segments (1, 2, 4, ... of equal length) into which samples 0 to `last` can be cut
// so that the linear interpolation between each segment's ends stays within `tolerance` of every
// sample: `error(j, a, b, w)` is sample j's distance from the mix of samples a and b at weight
// w (0: a, 1: b). `last` when none fewer does.
template <typename Error>
int fewestSegments(int last, float tolerance, Error&& error) {
  for (int segments = 1; segments < last; segments *= 2) {
    const int stride = last / segments;
    float worst = 0;
    for (int j = 0; j <= last; ++j) {
      const int s = std::min(j / stride, segments - 1);
      const float w = float(j - s * stride) / float(stride);
      worst = std::max(worst, error(size_t(j), size_t(s * stride), size_t((s + 1) * stride), w));
    }
    if (worst <= tolerance) return segments;
  }
  return last;
}

// The fewest segments (1, 2, 4, ... 128 of equal time) whose linear interpolation of `world`
// (kMotionSamples transforms evenly over the shutter) stays within 0.1% of the object's size
// of every sample; `radius` is the object's, about its origin.
int motionSegments(const std::vector<glm::mat4>& world, float radius);

// A node's own transform: its `matrix`, else translation x rotation x scale. Throws SceneError
// naming nodes[index] for a matrix of the wrong size or a rotation that is not a quaternion.
mat4 localTransform(const std::string& path, const tinygltf::Node& node, size_t index);

}  // namespace penumbra::gltf
