#include "scene/lights.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
float triangleArea(vec3 p0, vec3 p1, vec3 p2) {
  return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
}

float emitterWeight(const Scene& scene, const Mesh& mesh, uint32_t primId) {
  vec3 p0, p1, p2;
  trianglePositions(mesh, primId, 0.0f, p0, p1, p2);
  return triangleArea(p0, p1, p2) * luminance(scene.materials[mesh.materialIds[primId]].emission);
}
}  // namespace

void trianglePositions(const Mesh& mesh, uint32_t primId, float time, vec3& p0, vec3& p1,
                       vec3& p2) {
  const uint32_t* idx = &mesh.indices[3 * size_t(primId)];
  p0 = vertexAtTime(mesh.positions, mesh, idx[0], time);
  p1 = vertexAtTime(mesh.positions, mesh, idx[1], time);
  p2 = vertexAtTime(mesh.positions, mesh, idx[2], time);
}

LightSampler buildLightSampler(const Scene& scene) {
  LightSampler ls;
  ls.triangleProbability.resize(scene.meshes.size());
  std::vector<double> weights;
  double sum = 0;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
      if (!scene.materials[mesh.materialIds[t]].isEmissive()) continue;
      const double w = emitterWeight(scene, mesh, t);
      if (!(w > 0) || !std::isfinite(w)) continue;
      ls.emitters.push_back({m, t, 0.0f});
      weights.push_back(w);
      sum += w;
    }
  }
  double running = 0;
  for (size_t i = 0; i < ls.emitters.size(); ++i) {
    LightSampler::Emitter& e = ls.emitters[i];
    e.probability = float(weights[i] / sum);
    running += weights[i];
    ls.cdf.push_back(float(running / sum));
    auto& perTriangle = ls.triangleProbability[e.meshId];
    if (perTriangle.empty()) perTriangle.assign(scene.meshes[e.meshId].triangleCount(), 0.0f);
    perTriangle[e.primId] = e.probability;
  }
  if (!ls.cdf.empty()) ls.cdf.back() = 1.0f;
  return ls;
}

bool sampleLight(const Scene& scene, const LightSampler& lights, vec3 reference, float time,
                 float uChoose, glm::vec2 uTri, LightSample& out) {
  if (lights.empty()) return false;
  const size_t i =
      size_t(std::upper_bound(lights.cdf.begin(), lights.cdf.end(), uChoose) - lights.cdf.begin());
  const auto& e = lights.emitters[std::min(i, lights.emitters.size() - 1)];
  const Mesh& mesh = scene.meshes[e.meshId];
  vec3 p0, p1, p2;
  trianglePositions(mesh, e.primId, time, p0, p1, p2);
  // Uniform point on the triangle.
  const float su = std::sqrt(uTri.x);
  const float b0 = 1 - su, b1 = uTri.y * su;
  out.point = b0 * p0 + b1 * p1 + (1 - b0 - b1) * p2;
  const vec3 cross = glm::cross(p1 - p0, p2 - p0);
  const float doubleArea = glm::length(cross);
  if (!(doubleArea > 0)) return false;
  out.normal = cross / doubleArea;
  const vec3 toLight = out.point - reference;
  const float dist2 = glm::dot(toLight, toLight);
  const float cosLight = -glm::dot(out.normal, toLight) / std::sqrt(dist2);
  if (!(cosLight > 0) || !(dist2 > 0)) return false;  // back side does not emit
  out.pdf = e.probability * dist2 / (0.5f * doubleArea * cosLight);
  out.radiance = scene.materials[mesh.materialIds[e.primId]].emission;
  return std::isfinite(out.pdf);
}

float lightPdf(const Scene& scene, const LightSampler& lights, uint32_t meshId, uint32_t primId,
               vec3 reference, vec3 point, vec3 normal, float time) {
  const std::vector<float>& perTriangle = lights.triangleProbability[meshId];
  if (perTriangle.empty() || !(perTriangle[primId] > 0)) return 0;
  vec3 p0, p1, p2;
  trianglePositions(scene.meshes[meshId], primId, time, p0, p1, p2);
  const float area = triangleArea(p0, p1, p2);
  const vec3 d = point - reference;
  const float dist2 = glm::dot(d, d);
  const float cosLight = std::abs(glm::dot(normal, d)) / std::sqrt(dist2);
  if (!(area > 0) || !(cosLight > 0)) return 0;
  return perTriangle[primId] * dist2 / (area * cosLight);
}

}  // namespace penumbra
