// Area lights: every triangle whose material emits. Triangles are chosen in proportion
// to area (at time 0) times emitted luminance, then sampled uniformly in area at the
// ray's time, so moving emitters light the scene where they are.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace penumbra {

struct LightSampler {
  struct Emitter {
    uint32_t meshId, primId;
    float probability;  // of choosing this triangle
  };
  std::vector<Emitter> emitters;
  std::vector<float> cdf;  // normalised, cdf.back() == 1
  // probability[mesh][triangle] for meshes with emitters (empty otherwise), so a BSDF
  // ray that hits an emitter finds its light-sampling pdf without a search.
  std::vector<std::vector<float>> triangleProbability;

  bool empty() const { return emitters.empty(); }
};

LightSampler buildLightSampler(const Scene& scene);

// Vertices of a triangle at scene time t in [0,1] (linear between time steps).
void trianglePositions(const Mesh& mesh, uint32_t primId, float time, vec3& p0, vec3& p1, vec3& p2);

struct LightSample {
  vec3 point, normal;  // normal: the emitting (counter-clockwise) side
  vec3 radiance;       // emitted towards the reference point (0 if it sees the back)
  float pdf = 0;       // solid angle at the reference point
};

bool sampleLight(const Scene& scene, const LightSampler& lights, vec3 reference, float time,
                 float uChoose, glm::vec2 uTriangle, LightSample& out);

// Solid-angle pdf with which sampleLight would produce `point` on triangle (meshId, primId).
float lightPdf(const Scene& scene, const LightSampler& lights, uint32_t meshId, uint32_t primId,
               vec3 reference, vec3 point, vec3 normal, float time);

}  // namespace penumbra
