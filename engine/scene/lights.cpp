#include "scene/lights.h"

#include "core/constants.h"

#include "scene/textures.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
float triangleArea(vec3 p0, vec3 p1, vec3 p2) {
  return 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
}

// The mean luminance of a texture over its uv square (1 without a texture): a triangle's
// choice weight uses it, the radiance itself is the texture's at the sampled point.
float meanTextureLuminance(const Scene& scene, int texture) {
  return texture < 0 ? 1.0f : textureMeanLuminance(scene, scene.textures[size_t(texture)]);
}

// The share of an emission texture's mean that every triangle of its material keeps in its
// light-sampling weight, whatever its own part of the texture: a bright detail that the
// triangle's estimate below misses still gets next-event samples, not only BSDF hits.
constexpr float kEmissionWeightFloor = 0.01f;

// The luminance of a textured emitter's texture over one triangle, for its light-sampling
// weight: the mean of its four half-size sub-triangles' (midpoint subdivision) means, each a
// lookup at the sub-triangle's centroid at the mip level whose texels span its uv edges, so a
// bright patch anywhere inside counts. Floored at kEmissionWeightFloor of the texture's mean.
// A mesh without uvs emits the texture at uv (0, 0) everywhere (sampleLight): its weight too.
float triangleEmissionLuminance(const Scene& scene, const Mesh& mesh, uint32_t triangle,
                                const Texture& texture, float textureMean) {
  if (mesh.uvs.empty()) return luminance(evalTexture(scene, texture, glm::vec2(0.0f)));
  const uint32_t* idx = &mesh.indices[3 * size_t(triangle)];
  const glm::vec2 a = mesh.uvs[idx[0]], b = mesh.uvs[idx[1]], c = mesh.uvs[idx[2]];
  const UvFootprint halfEdges{0.5f * (b - a), 0.5f * (c - a)};
  constexpr float kFar = 2.0f / 3.0f, kNear = 1.0f / 6.0f, kMid = 1.0f / 3.0f;
  float sum = 0.0f;
  for (const glm::vec3 w : {glm::vec3(kFar, kNear, kNear), glm::vec3(kNear, kFar, kNear),
                            glm::vec3(kNear, kNear, kFar), glm::vec3(kMid)})
    sum += luminance(evalTexture(scene, texture, w.x * a + w.y * b + w.z * c, halfEdges));
  const float mean = 0.25f * sum;
  return std::isfinite(mean) ? std::max(mean, kEmissionWeightFloor * textureMean) : textureMean;
}

// A punctual light's power over pi, in the units of a triangle's area x luminance.
double punctualWeight(const PunctualLight& light, float sceneRadius) {
  const double intensity = luminance(light.intensity);
  switch (light.kind) {
    case PunctualLight::Kind::Point:
      return 4.0 * intensity;
    case PunctualLight::Kind::Spot:
      return 2.0 * (1.0 - 0.5 * (double(light.cosInner) + double(light.cosOuter))) * intensity;
    case PunctualLight::Kind::Directional:
      return double(sceneRadius) * double(sceneRadius) * intensity;
  }
  return 0;
}

// glTF's spot falloff: full inside the inner cone, none outside the outer, squared ramp between.
float spotFalloff(const PunctualLight& light, float cosAngle) {
  const float scale = 1.0f / std::max(1e-3f, light.cosInner - light.cosOuter);
  const float t = std::clamp((cosAngle - light.cosOuter) * scale, 0.0f, 1.0f);
  return t * t;
}

bool samplePunctual(const PunctualLight& light, vec3 reference, LightSample& out) {
  out.delta = true;
  out.normal = vec3(0.0f);
  if (light.kind == PunctualLight::Kind::Directional) {
    out.wi = -light.direction;
    out.distance = INFINITY;
    out.point = reference + out.wi;
    out.radiance = light.intensity;
    return true;
  }
  const vec3 toLight = light.position - reference;
  const float dist2 = glm::dot(toLight, toLight);
  if (!(dist2 > 0)) return false;
  out.distance = std::sqrt(dist2);
  out.wi = toLight / out.distance;
  out.point = light.position;
  out.radiance = light.intensity / dist2;
  if (light.range > 0) out.radiance *= rangeWindow(light.range, dist2);
  if (light.kind == PunctualLight::Kind::Spot)
    out.radiance *= spotFalloff(light, -glm::dot(out.wi, light.direction));
  return out.radiance.x > 0 || out.radiance.y > 0 || out.radiance.z > 0;
}
}  // namespace

vec3 emittedRadiance(const Scene& scene, const Material& material, glm::vec2 uv,
                     const UvFootprint& footprint) {
  if (material.emissionTexture < 0) return material.emission;
  return material.emission *
         evalTexture(scene, scene.textures[size_t(material.emissionTexture)], uv, footprint);
}

void trianglePositions(const Mesh& mesh, uint32_t primId, float time, vec3& p0, vec3& p1,
                       vec3& p2) {
  const uint32_t* idx = &mesh.indices[3 * size_t(primId)];
  p0 = vertexAtTime(mesh.positions, mesh, idx[0], time);
  p1 = vertexAtTime(mesh.positions, mesh, idx[1], time);
  p2 = vertexAtTime(mesh.positions, mesh, idx[2], time);
}

namespace {
// The chart of a mesh's emitting triangles (those of positive weight), at time 0.
EmitterChart makeEmitterChart(const Mesh& mesh, const std::vector<double>& weight) {
  glm::dvec3 normalSum(0.0), centroid(0.0);
  double area = 0;
  for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!(weight[t] > 0) || !std::isfinite(weight[t])) continue;
    vec3 p0, p1, p2;
    trianglePositions(mesh, t, 0.0f, p0, p1, p2);
    const glm::dvec3 halfCross = 0.5 * glm::dvec3(glm::cross(p1 - p0, p2 - p0));
    const double a = glm::length(halfCross);
    normalSum += halfCross;
    centroid += a * glm::dvec3(p0 + p1 + p2) / 3.0;
    area += a;
  }
  EmitterChart chart;
  if (!(area > 0)) return chart;
  centroid /= area;
  if (glm::length(normalSum) < double(kFlatChart) * area) {
    chart.flat = false;
    chart.origin = vec3(centroid);
    return chart;
  }
  // Fixed axes of the plane: the world axis least along the normal, made perpendicular to it,
  // and the normal's cross product with that (a rectangle's u and v as makeRectangle has them).
  const glm::dvec3 n = glm::normalize(normalSum);
  const glm::dvec3 a = glm::abs(n);
  const glm::dvec3 reference = a.x <= a.y && a.x <= a.z ? glm::dvec3(1, 0, 0)
                               : a.y <= a.z             ? glm::dvec3(0, 1, 0)
                                                        : glm::dvec3(0, 0, 1);
  const glm::dvec3 u = glm::normalize(reference - n * glm::dot(n, reference));
  const glm::dvec3 v = glm::cross(n, u);
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!(weight[t] > 0) || !std::isfinite(weight[t])) continue;
    vec3 p[3];
    trianglePositions(mesh, t, 0.0f, p[0], p[1], p[2]);
    for (const vec3 q : p) {
      const glm::dvec2 c(glm::dot(glm::dvec3(q) - centroid, u),
                         glm::dot(glm::dvec3(q) - centroid, v));
      lo = glm::min(lo, c);
      hi = glm::max(hi, c);
    }
  }
  const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-12));
  chart.origin = vec3(centroid + lo.x * u + lo.y * v);
  chart.axisU = vec3(u / size.x);
  chart.axisV = vec3(v / size.y);
  return chart;
}
}  // namespace

glm::vec2 directionChart(vec3 d) {
  return {equirectU(d), std::clamp(0.5f * (1.0f - d.y), 0.0f, 1.0f)};
}

glm::vec2 emitterChartAt(const EmitterChart& chart, vec3 point) {
  const vec3 d = point - chart.origin;
  if (chart.flat)
    return glm::clamp(glm::vec2(glm::dot(d, chart.axisU), glm::dot(d, chart.axisV)), 0.0f, 1.0f);
  const float length = glm::length(d);
  return length > 0 ? directionChart(d / length) : glm::vec2(0.5f);
}

glm::vec2 lightChart(const LightSampler& lights, const LightSample& sample) {
  if (sample.object < 0) return glm::vec2(0.5f);
  const size_t object = size_t(sample.object);
  if (object < lights.meshCount) return emitterChartAt(lights.charts[object], sample.point);
  if (object < lights.meshCount + lights.punctualCount) return glm::vec2(0.5f);
  return directionChart(sample.wi);
}

LightSampler buildLightSampler(const Scene& scene) {
  LightSampler ls;
  ls.triangleProbability.resize(scene.meshes.size());
  ls.charts.resize(scene.meshes.size());
  ls.meshCount = scene.meshes.size();
  ls.punctualCount = scene.lights.size();
  std::vector<double> weights;
  double sum = 0;
  std::vector<float> textureMean(scene.materials.size(), -1.0f);
  for (size_t id = 0; id < scene.materials.size(); ++id)
    if (scene.materials[id].isEmissive())
      textureMean[id] = meanTextureLuminance(scene, scene.materials[id].emissionTexture);
  std::vector<double> triangleWeight;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    // Each emitting triangle's weight: its area times its emitted luminance.
    triangleWeight.assign(mesh.triangleCount(), 0.0);
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
      const uint32_t id = mesh.materialIds[t];
      const Material& material = scene.materials[id];
      if (!material.isEmissive()) continue;
      vec3 p0, p1, p2;
      trianglePositions(mesh, t, 0.0f, p0, p1, p2);
      double w = triangleArea(p0, p1, p2) * luminance(material.emission);
      if (material.emissionTexture >= 0)
        w *= double(triangleEmissionLuminance(
            scene, mesh, t, scene.textures[size_t(material.emissionTexture)], textureMean[id]));
      triangleWeight[t] = w;
    }
    if (std::any_of(triangleWeight.begin(), triangleWeight.end(),
                    [](double w) { return w > 0 && std::isfinite(w); }))
      ls.charts[m] = makeEmitterChart(mesh, triangleWeight);
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
      const double w = triangleWeight[t];
      if (!(w > 0) || !std::isfinite(w)) continue;
      ls.emitters.push_back({m, t, 0.0f});
      weights.push_back(w);
      sum += w;
    }
  }
  ls.environment = lightingEnvironment(scene);
  // The scene's cross-section weighs the lights from far away (the environment, directional
  // lights); the bounds are a pass over every vertex, made only when such a light is there.
  float radius = 1.0f;
  if (ls.environment || !scene.lights.empty()) {
    vec3 lo, hi;
    sceneBounds(scene, lo, hi);
    if (lo.x <= hi.x) radius = 0.5f * glm::length(hi - lo);
  }
  if (ls.environment) {
    // Power over pi through the scene's cross-section, as for a directional light (whose
    // illuminance is what the environment's integrated radiance generalises).
    const double w = double(radius) * double(radius) * ls.environment->integratedLuminance();
    if (w > 0 && std::isfinite(w)) {
      ls.emitters.push_back({0, 0, 0.0f, LightSampler::kEnvironment});
      weights.push_back(w);
      sum += w;
    } else {
      ls.environment = nullptr;
    }
  }
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const double w = punctualWeight(scene.lights[i], radius);
    if (!(w > 0) || !std::isfinite(w)) continue;
    ls.emitters.push_back({0, 0, 0.0f, int(i)});
    weights.push_back(w);
    sum += w;
  }
  double running = 0;
  for (size_t i = 0; i < ls.emitters.size(); ++i) {
    LightSampler::Emitter& e = ls.emitters[i];
    e.probability = float(weights[i] / sum);
    running += weights[i];
    ls.cdf.push_back(float(running / sum));
    if (e.punctual == LightSampler::kEnvironment) ls.environmentProbability = e.probability;
    if (e.punctual != -1) continue;
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
  if (e.punctual == LightSampler::kEnvironment) {
    float pdf = 0;
    if (!lights.environment->sample(uTri, out.wi, pdf, &out.radiance)) return false;
    out.pdf = e.probability * pdf;
    out.distance = INFINITY;
    out.point = reference + out.wi;
    out.normal = -out.wi;
    out.delta = false;
    out.object = int(lights.meshCount + lights.punctualCount);
    return out.pdf > 0 && std::isfinite(out.pdf);
  }
  if (e.punctual >= 0) {
    if (!samplePunctual(scene.lights[size_t(e.punctual)], reference, out)) return false;
    out.pdf = e.probability;
    out.object = int(lights.meshCount) + e.punctual;
    return true;
  }
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
  out.distance = std::sqrt(dist2);
  out.wi = toLight / out.distance;
  out.delta = false;
  out.object = int(e.meshId);
  const Material& material = scene.materials[mesh.materialIds[e.primId]];
  if (material.emissionTexture >= 0 && !mesh.uvs.empty()) {
    const uint32_t* idx = &mesh.indices[3 * size_t(e.primId)];
    const glm::vec2 uv =
        b0 * mesh.uvs[idx[0]] + b1 * mesh.uvs[idx[1]] + (1 - b0 - b1) * mesh.uvs[idx[2]];
    out.radiance = emittedRadiance(scene, material, uv);
  } else {
    out.radiance = emittedRadiance(scene, material, glm::vec2(0.0f));
  }
  return std::isfinite(out.pdf);
}

std::shared_ptr<const EnvironmentLight> lightingEnvironment(const Scene& scene) {
  std::shared_ptr<const EnvironmentLight> light;
  const Environment& e = scene.environment;
  if (e.present())
    light = std::make_shared<const EnvironmentLight>(e.map, e.strength, e.rotationDegrees);
  else if (scene.background)
    light = std::make_shared<const EnvironmentLight>(EnvironmentLight::constant(*scene.background));
  return light && !light->black() ? light : nullptr;
}

vec3 escapedRadiance(const Scene& scene, const LightSampler& lights, vec3 direction, bool cameraRay,
                     float* lightPdf) {
  if (lightPdf) *lightPdf = 0.0f;
  if (cameraRay) {
    if (scene.transparent) return vec3(0.0f);
    if (scene.environment.present() && scene.background) return *scene.background;
  }
  if (!lights.environment) return vec3(0.0f);
  const vec3 radiance = lights.environment->radiance(direction, lightPdf);
  if (lightPdf) *lightPdf *= lights.environmentProbability;
  return radiance;
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
