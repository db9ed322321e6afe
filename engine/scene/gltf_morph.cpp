#include "scene/gltf_morph.h"

#include "scene/gltf_accessors.h"

#include <algorithm>
#include <cmath>

namespace penumbra::gltf {

std::vector<float> WeightsTrack::at(double t) const {
  const size_t n = times.size();
  const size_t parts = interpolation == Track::Interpolation::CubicSpline ? 3 : 1;
  const size_t middle = parts == 3 ? 1 : 0;
  const auto value = [&](size_t key, size_t part, size_t i) {
    return values[(key * parts + part) * targets + i];
  };
  std::vector<float> out(targets);
  size_t k = 0;
  double u = 0, dt = 0;
  const bool before = t <= times.front(), after = t >= times.back();
  if (!before && !after) {
    k = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    dt = times[k + 1] - times[k];
    u = dt > 0 ? (t - times[k]) / dt : 0.0;
  }
  for (size_t i = 0; i < targets; ++i) {
    double v;
    if (before || after)
      v = value(before ? 0 : n - 1, middle, i);
    else if (interpolation == Track::Interpolation::Step)
      v = value(k, middle, i);
    else if (interpolation == Track::Interpolation::Linear)
      v = (1 - u) * value(k, 0, i) + u * value(k + 1, 0, i);
    else {
      const double u2 = u * u, u3 = u2 * u;
      v = (2 * u3 - 3 * u2 + 1) * value(k, 1, i) + (u3 - 2 * u2 + u) * dt * value(k, 2, i) +
          (-2 * u3 + 3 * u2) * value(k + 1, 1, i) + (u3 - u2) * dt * value(k + 1, 0, i);
    }
    out[i] = float(v);
  }
  return out;
}

WeightsTrack readWeightsTrack(const std::string& path, const tinygltf::Model& model,
                              const tinygltf::Animation& animation,
                              const tinygltf::AnimationChannel& channel, size_t targets,
                              const std::string& where) {
  WeightsTrack track;
  track.targets = targets;
  const tinygltf::AnimationSampler& sampler =
      readKeyTimes(path, model, animation, channel, where, track.interpolation, track.times);
  const size_t parts = track.interpolation == Track::Interpolation::CubicSpline ? 3 : 1;
  const AccessorReader output(path, model, sampler.output, where + ".output");
  const size_t expected = parts * track.times.size() * targets;
  if (output.components() != 1 || output.count() != expected)
    fail(path, output.where(),
         "expected " + std::to_string(expected) + " SCALAR weights: " + std::to_string(targets) +
             " targets for each of " + std::to_string(track.times.size()) + " keyframes");
  for (size_t k = 0; k < expected; ++k) {
    const double v = output.get(k, 0);
    if (!std::isfinite(v)) fail(path, output.where(), "non-finite value at " + std::to_string(k));
    track.values.push_back(v);
  }
  return track;
}

int weightSegments(const std::vector<std::vector<float>>& samples) {
  const int last = int(samples.size()) - 1;
  if (last < 1) return 1;
  return fewestSegments(last, 1e-3f, [&](size_t j, size_t a, size_t b, float w) {
    float worst = 0;
    for (size_t i = 0; i < samples[j].size(); ++i)
      worst =
          std::max(worst, std::abs((1 - w) * samples[a][i] + w * samples[b][i] - samples[j][i]));
    return worst;
  });
}

size_t morphTargetCount(const tinygltf::Model& model, int index) {
  const int mesh = model.nodes[size_t(index)].mesh;
  if (mesh < 0 || size_t(mesh) >= model.meshes.size()) return 0;
  const auto& primitives = model.meshes[size_t(mesh)].primitives;
  return primitives.empty() ? 0 : primitives.front().targets.size();
}

std::vector<std::vector<float>> morphWeights(const tinygltf::Model& model,
                                             const tinygltf::Node& node,
                                             const std::optional<WeightsTrack>& track,
                                             const std::vector<double>& times) {
  if (node.mesh < 0 || size_t(node.mesh) >= model.meshes.size()) return {};
  std::vector<std::vector<float>> samples;
  if (track) {
    for (double t : times) samples.push_back(track->at(t));
    return samples;
  }
  const std::vector<double>& fixed =
      node.weights.empty() ? model.meshes[size_t(node.mesh)].weights : node.weights;
  if (fixed.empty()) return {};
  std::vector<float> weights;
  for (double w : fixed) weights.push_back(std::isfinite(w) ? float(w) : 0.0f);
  return {weights};
}

MorphTargets::MorphTargets(const std::string& path, const tinygltf::Model& model,
                           const tinygltf::Primitive& primitive, size_t vertexCount,
                           const std::vector<std::vector<float>>& weights,
                           const std::string& where) {
  static const char* const kNames[3] = {"POSITION", "NORMAL", "TANGENT"};
  for (size_t t = 0; t < primitive.targets.size(); ++t) {
    Target target;
    bool weighted = false;
    for (const std::vector<float>& step : weights)
      weighted = weighted || (t < step.size() && step[t] != 0.0f);
    for (int a = 0; a < 3 && weighted; ++a) {
      const auto it = primitive.targets[t].find(kNames[a]);
      if (it == primitive.targets[t].end()) continue;
      const AccessorReader r(path, model, it->second,
                             where + "." + indexed("targets", t) + "." + kNames[a]);
      if (r.components() != 3 || r.count() != vertexCount)
        fail(path, r.where(), "expected " + std::to_string(vertexCount) + " VEC3 displacements");
      target.deltas[a].resize(vertexCount);
      for (size_t v = 0; v < vertexCount; ++v) {
        const glm::vec3 d(r.get(v, 0), r.get(v, 1), r.get(v, 2));
        target.deltas[a][v] = std::isfinite(d.x + d.y + d.z) ? d : glm::vec3(0.0f);
      }
    }
    targets_.push_back(std::move(target));
  }
}

glm::vec3 MorphTargets::displaced(int attribute, size_t v, glm::vec3 value,
                                  const std::vector<float>& weights) const {
  const size_t n = std::min(targets_.size(), weights.size());
  for (size_t t = 0; t < n; ++t) {
    const std::vector<glm::vec3>& d = targets_[t].deltas[attribute];
    if (weights[t] != 0.0f && !d.empty()) value += weights[t] * d[v];
  }
  return value;
}

}  // namespace penumbra::gltf
