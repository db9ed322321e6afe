// Ray queries on Embree 3: one triangle geometry per scene mesh (geometry ID = mesh
// index), with Embree's linear motion blur over the mesh's vertex time steps. Meshes with
// cut-out materials (alpha masks) get a filter that lets rays through the holes.
#pragma once

#include "scene/camera.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace penumbra {

struct Scene;
struct Mesh;

struct Hit {
  float t = 0;
  uint32_t meshId = 0;
  uint32_t primId = 0;
  float u = 0, v = 0;  // barycentrics of vertices 1 and 2
};

class Accel {
 public:
  explicit Accel(const Scene& scene);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  // Nearest hit along the ray in (tMin, tMax); false on a miss.
  bool intersect(const Ray& ray, float tMin, float tMax, Hit& hit) const;
  // True if anything blocks the segment (tMin, tMax) along the ray.
  bool occluded(const Ray& ray, float tMin, float tMax) const;

  // The Embree scene (an RTCScene), for benchmarks that time raw Embree queries.
  void* embreeScene() const;

  struct Impl;

 private:
  // Copies what the cut-out filter of `mesh` needs; returns its user data for Embree.
  void* addCutouts(const Scene& scene, const Mesh& mesh, std::vector<int>& alphaImages);
  std::unique_ptr<Impl> impl_;
};

// Embree asks every thread that traces rays to flush denormals to zero.
void enableFlushToZero();

// Records the queries made on the calling thread (for bench/: replaying the path
// tracer's own rays through raw Embree). Pass nullptr to stop recording.
struct RecordedQuery {
  Ray ray;
  float tMin, tMax;
  bool shadow;
};
void recordQueriesOnThisThread(std::vector<RecordedQuery>* log);

}  // namespace penumbra
