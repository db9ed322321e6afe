#include "scene/gltf_animation.h"

#include "scene/gltf_accessors.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::gltf {

glm::dvec4 Track::at(double t) const {
  const size_t n = times.size();
  if (t <= times.front()) return value(0, 1);
  if (t >= times.back()) return value(n - 1, 1);
  const size_t k = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const double dt = times[k + 1] - times[k];
  const double u = dt > 0 ? (t - times[k]) / dt : 0.0;
  glm::dvec4 v;
  switch (interpolation) {
    case Interpolation::Step:
      return value(k, 1);
    case Interpolation::CubicSpline: {
      const double u2 = u * u, u3 = u2 * u;
      v = (2 * u3 - 3 * u2 + 1) * value(k, 1) + (u3 - 2 * u2 + u) * dt * value(k, 2) +
          (-2 * u3 + 3 * u2) * value(k + 1, 1) + (u3 - u2) * dt * value(k + 1, 0);
      break;
    }
    case Interpolation::Linear:
      if (path == Path::Rotation) {
        const glm::dquat a(value(k, 1).w, value(k, 1).x, value(k, 1).y, value(k, 1).z);
        const glm::dquat b(value(k + 1, 1).w, value(k + 1, 1).x, value(k + 1, 1).y,
                           value(k + 1, 1).z);
        const glm::dquat q = glm::slerp(a, b, u);
        return {q.x, q.y, q.z, q.w};
      }
      v = (1 - u) * value(k, 1) + u * value(k + 1, 1);
      break;
  }
  return v;
}

const tinygltf::AnimationSampler& readKeyTimes(
    const std::string& path_, const tinygltf::Model& model_, const tinygltf::Animation& animation,
    const tinygltf::AnimationChannel& channel, const std::string& where,
    Track::Interpolation& interpolation, std::vector<double>& times) {
  if (channel.sampler < 0 || size_t(channel.sampler) >= animation.samplers.size())
    fail(path_, where + ".sampler",
         "sampler " + std::to_string(channel.sampler) + " does not exist");
  const tinygltf::AnimationSampler& sampler = animation.samplers[size_t(channel.sampler)];
  if (sampler.interpolation == "STEP")
    interpolation = Track::Interpolation::Step;
  else if (sampler.interpolation == "CUBICSPLINE")
    interpolation = Track::Interpolation::CubicSpline;
  else if (sampler.interpolation == "LINEAR" || sampler.interpolation.empty())
    interpolation = Track::Interpolation::Linear;
  else
    fail(path_, where, "unknown interpolation '" + sampler.interpolation + "'");
  const AccessorReader input(path_, model_, sampler.input, where + ".input");
  if (input.components() != 1 || !input.isFloat() || input.count() == 0)
    fail(path_, input.where(), "keyframe times must be a non-empty float SCALAR accessor");
  for (size_t k = 0; k < input.count(); ++k) {
    const double t = input.get(k, 0);
    if (!std::isfinite(t) || (k > 0 && !(t > times.back())))
      fail(path_, input.where(),
           "keyframe time " + number(t) + " at " + std::to_string(k) +
               " is not finite and after the one before");
    times.push_back(t);
  }
  return sampler;
}

Track readTrack(const std::string& path_, const tinygltf::Model& model_,
                const tinygltf::Animation& animation, const tinygltf::AnimationChannel& channel,
                const std::string& where) {
  Track track;
  if (channel.target_path == "translation")
    track.path = Track::Path::Translation;
  else if (channel.target_path == "rotation")
    track.path = Track::Path::Rotation;
  else if (channel.target_path == "scale")
    track.path = Track::Path::Scale;
  else
    fail(path_, where + ".target.path", "unknown path '" + channel.target_path + "'");
  const tinygltf::AnimationSampler& sampler =
      readKeyTimes(path_, model_, animation, channel, where, track.interpolation, track.times);
  const int components = track.path == Track::Path::Rotation ? 4 : 3;
  const size_t perKey = track.interpolation == Track::Interpolation::CubicSpline ? 3 : 1;
  const AccessorReader output(path_, model_, sampler.output, where + ".output");
  const size_t keys = track.times.size();
  if (output.components() != components || output.count() != perKey * keys)
    fail(path_, output.where(),
         "expected " + std::to_string(perKey * keys) + " VEC" + std::to_string(components) +
             " values for " + std::to_string(keys) + " keyframes");
  for (size_t k = 0; k < output.count(); ++k) {
    glm::dvec4 v(0.0);
    for (int c = 0; c < components; ++c) v[c] = output.get(k, c);
    if (!std::isfinite(v.x + v.y + v.z + v.w))
      fail(path_, output.where(), "non-finite value at " + std::to_string(k));
    track.values.push_back(v);
  }
  return track;
}

mat4 animatedLocal(const std::string& path_, const tinygltf::Node& node, size_t index,
                   const std::vector<Track>& tracks, double t) {
  glm::dvec3 translation(0.0), scale(1.0);
  glm::dquat rotation(1.0, 0.0, 0.0, 0.0);
  if (node.translation.size() == 3)
    translation = glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
  if (node.rotation.size() == 4)
    rotation = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
  if (node.scale.size() == 3) scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
  for (const Track& track : tracks) {
    const glm::dvec4 v = track.at(t);
    switch (track.path) {
      case Track::Path::Translation:
        translation = glm::dvec3(v);
        break;
      case Track::Path::Rotation:
        rotation = glm::dquat(v.w, v.x, v.y, v.z);
        break;
      case Track::Path::Scale:
        scale = glm::dvec3(v);
        break;
    }
  }
  const double length = glm::length(rotation);
  if (!(length > 0.0) || !std::isfinite(length))
    fail(path_, indexed("nodes", index) + ".rotation", "not a rotation quaternion");
  const glm::dmat4 m = glm::translate(glm::dmat4(1.0), translation) *
                       glm::mat4_cast(rotation / length) * glm::scale(glm::dmat4(1.0), scale);
  return mat4(m);
}

int motionSegments(const std::vector<glm::mat4>& world, float radius) {
  const auto scaleOf = [](const mat4& m) {
    return std::max({glm::length(vec3(m[0])), glm::length(vec3(m[1])), glm::length(vec3(m[2]))});
  };
  const float tolerance = 1e-3f * std::max(radius * scaleOf(world.front()), 1e-6f);
  return fewestSegments(kMotionSamples - 1, tolerance, [&](size_t j, size_t a, size_t b, float w) {
    const mat4 d = (1 - w) * world[a] + w * world[b] - world[j];
    return radius * std::max({glm::length(vec3(d[0])), glm::length(vec3(d[1])),
                              glm::length(vec3(d[2]))}) +
           glm::length(vec3(d[3]));
  });
}

mat4 localTransform(const std::string& path, const tinygltf::Node& node, size_t index) {
  if (node.matrix.size() == 16) {
    mat4 m;
    for (int k = 0; k < 16; ++k) glm::value_ptr(m)[k] = float(node.matrix[size_t(k)]);
    return m;
  }
  if (!node.matrix.empty()) fail(path, indexed("nodes", index) + ".matrix", "expected 16 numbers");
  mat4 t(1.0f), r(1.0f), s(1.0f);
  if (node.translation.size() == 3)
    t = glm::translate(mat4(1.0f), vec3(float(node.translation[0]), float(node.translation[1]),
                                        float(node.translation[2])));
  if (node.rotation.size() == 4) {
    glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                float(node.rotation[2]));
    const float length = glm::length(q);
    if (!(length > 0.0f) || !std::isfinite(length))
      fail(path, indexed("nodes", index) + ".rotation", "not a rotation quaternion");
    r = glm::mat4_cast(q / length);
  }
  if (node.scale.size() == 3)
    s = glm::scale(mat4(1.0f),
                   vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
  return t * r * s;
}

}  // namespace penumbra::gltf
