// Lights for next-event estimation: every triangle whose material emits (area lights), and
// the scene's punctual lights. One light is chosen in proportion to its power: a triangle's
// area (at time 0) times its emitted luminance (times its emission texture's mean over it), a
// punctual light's luminous intensity times its cone's solid angle (a directional light's
// illuminance times the scene's cross-section), both divided by pi. A triangle is then
// sampled uniformly in area at the ray's time, so moving emitters light the scene where they
// are; a punctual light has one point (or direction). The environment (the scene's map, or a
// constant background without one) is one more light, weighing the scene's cross-section
// times its radiance integrated over the sphere (a directional light's weight, generalised),
// and samples a direction by its own importance (environment.h).
//
// Light charts: where a light sample landed, in coordinates continuous over its emitting
// object, for what learns along the light's dimensions (a penumbra is a step in the light
// sample's position). sampleLight's (u, v) warp each triangle on its own, so across a
// rectangle's diagonal they jump; the chart does not:
//  - a flat emitting mesh (its emitting triangles' area-weighted normals summing to at least
//    kFlatChart of their area: a rectangle, a disk, a panel): the point projected onto the
//    mesh's plane, in two fixed axes of it, scaled so that the emitting triangles span
//    [0, 1]^2; for a rectangle, its own (s, t) up to the axes' order and sense;
//  - any other emitting mesh (a sphere, a bulb, a closed shape): the point's direction from
//    the emitting triangles' area-weighted centroid, as (azimuth, (1 - cos polar) / 2) in
//    [0, 1]^2 about +y, continuous over a star-shaped emitter but for its azimuth seam;
//  - the environment: the sampled direction's (azimuth, (1 - cos polar) / 2), the azimuth as
//    the map's u (environment.h) before its rotation;
//  - a punctual light (one point or direction): (0.5, 0.5).
// The chart is computed at time 0: a moving emitter's samples move across it.
#pragma once

#include "scene/scene.h"
#include "scene/textures.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace penumbra {

// The chart of one emitting mesh (see the top of this file).
struct EmitterChart {
  bool flat = true;
  vec3 origin{0.0f};                    // flat: the corner of the bounds; curved: the centroid
  vec3 axisU{1, 0, 0}, axisV{0, 0, 1};  // flat: the plane's axes, divided by the bounds' size
};
inline constexpr float kFlatChart = 0.9f;

struct LightSampler {
  struct Emitter {
    uint32_t meshId, primId;
    float probability;  // of choosing this light
    int punctual = -1;  // index into Scene::lights; -1: the triangle (meshId, primId);
                        // kEnvironment: the environment
  };
  static constexpr int kEnvironment = -2;
  std::vector<Emitter> emitters;
  std::vector<float> cdf;  // normalised, cdf.back() == 1
  // probability[mesh][triangle] for meshes with emitters (empty otherwise), so a BSDF
  // ray that hits an emitter finds its light-sampling pdf without a search.
  std::vector<std::vector<float>> triangleProbability;
  // What lights the scene from far away (null: nothing), and the probability of choosing it.
  std::shared_ptr<const EnvironmentLight> environment;
  float environmentProbability = 0;
  // Per mesh: its chart (meaningful for meshes with emitters only).
  std::vector<EmitterChart> charts;
  size_t meshCount = 0, punctualCount = 0;  // for the lights' object ids (LightSample::object)

  bool empty() const { return emitters.empty(); }
};

// The environment that lights a scene: its map, else its background as a constant; null when
// there is neither (or it is black).
std::shared_ptr<const EnvironmentLight> lightingEnvironment(const Scene& scene);
// What a ray that leaves the scene sees: camera rays (`cameraRay`) see the backdrop (the
// background when the scene has both an environment and a background; nothing when the scene is
// transparent), the others the lighting environment. With `lightPdf`, also the solid-angle pdf
// with which sampleLight would produce the direction from the lighting environment (0 for the
// backdrop), sharing its map lookup.
vec3 escapedRadiance(const Scene& scene, const LightSampler& lights, vec3 direction, bool cameraRay,
                     float* lightPdf = nullptr);

LightSampler buildLightSampler(const Scene& scene);

// Vertices of a triangle at scene time t in [0,1] (linear between time steps).
void trianglePositions(const Mesh& mesh, uint32_t primId, float time, vec3& p0, vec3& p1, vec3& p2);

struct LightSample {
  vec3 point, normal;  // area lights: normal on the emitting (counter-clockwise) side
  vec3 wi;             // unit direction from the reference point towards the light
  float distance = 0;  // to the light; infinite for a directional light and the environment
  vec3 radiance;       // emitted towards the reference point; punctual lights: the irradiance
                       // it gives on a surface facing it (intensity / distance^2, cone applied)
  float pdf = 0;       // area lights: solid angle at the reference point; punctual lights:
                       // the probability of choosing it
  bool delta = false;  // a punctual light: no BSDF sample can reach it, so no MIS
  // Which emitting object the sample is on: a mesh's id for its triangles, then the scene's
  // punctual lights (meshes + light index), then the environment (meshes + punctual lights);
  // and where on it, in its chart (the top of this file).
  int object = -1;
  glm::vec2 chart{0.5f};
};

// A point of an emitting mesh in its chart.
glm::vec2 emitterChartAt(const EmitterChart& chart, vec3 point);
// The chart coordinates of a direction: (azimuth as the environment map's u, (1 - y) / 2).
glm::vec2 directionChart(vec3 direction);
// Where a light sample (of sampleLight with these lights) landed, in its object's chart;
// (0.5, 0.5) for a punctual light or no sample (object -1).
glm::vec2 lightChart(const LightSampler& lights, const LightSample& sample);

// Radiance a material emits at texture coordinate uv (its emission times its texture, over
// the footprint when one is known).
// The window a point or spot light's `range` puts on its inverse square at squared distance
// dist2 (KHR_lights_punctual's recommendation): clamp(1 - (d / range)^4, 0, 1).
inline float rangeWindow(float range, float dist2) {
  const float q = dist2 / (range * range);
  return std::clamp(1.0f - q * q, 0.0f, 1.0f);
}

vec3 emittedRadiance(const Scene& scene, const Material& material, glm::vec2 uv,
                     const UvFootprint& footprint = {});

bool sampleLight(const Scene& scene, const LightSampler& lights, vec3 reference, float time,
                 float uChoose, glm::vec2 uTriangle, LightSample& out);

// Solid-angle pdf with which sampleLight would produce `point` on triangle (meshId, primId).
float lightPdf(const Scene& scene, const LightSampler& lights, uint32_t meshId, uint32_t primId,
               vec3 reference, vec3 point, vec3 normal, float time);

}  // namespace penumbra
