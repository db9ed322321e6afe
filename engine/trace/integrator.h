// Unidirectional path tracer: next-event estimation on the lights (area, punctual and the
// environment) combined with BSDF sampling by multiple importance sampling (power
// heuristic), Russian roulette after the third vertex, and a maximum depth (pbrt-v4 convention: 0 =
// emitters seen directly, 1 = direct lighting, ...). `traceRadiance` is the one entry point every
// sampler calls: radiance (linear RGB) of the camera sample at a given 5D point.
#pragma once

#include "scene/lights.h"
#include "scene/scene.h"
#include "scene/textures.h"
#include "trace/accel.h"
#include "trace/sampler.h"

#include <cstdint>
#include <memory>

namespace penumbra {

// A scene ready to trace: acceleration structure, light sampler and camera frame.
struct PreparedScene {
  Scene scene;
  std::shared_ptr<const Accel> accel;  // shared by the views of one scene (prepareView)
  LightSampler lights;
  CameraFrame camera;
  bool usesLens = false;  // thin lens with a radius
  bool usesTime = false;  // something moves while the shutter is open
};

// Builds the BVH and light tables; throws SceneError on an unusable camera.
std::unique_ptr<PreparedScene> prepareScene(Scene scene);
// The same scene seen through another camera: shares base's BVH, copies the rest (no
// rebuild, so a viewer can restart on a camera move at once). Throws SceneError on an
// unusable camera.
std::unique_ptr<PreparedScene> prepareView(const PreparedScene& base, const Camera& camera);
// The same view rendering only a window of the image: its settings' size becomes the window's
// (regionW x regionH) and the camera sees the window at (regionX, regionY) of the full image.
// Throws SceneError when the window does not fit the base scene's image.
std::unique_ptr<PreparedScene> prepareView(const PreparedScene& base, const Camera& camera,
                                           int regionX, int regionY, int regionW, int regionH);

// The same geometry lit another way: `scene` is base's scene with only its lights, environment,
// background or transparency changed (the caller's promise); shares base's BVH and rebuilds the
// light sampler, so a viewer can change the environment and restart at once.
std::unique_ptr<PreparedScene> prepareLighting(const PreparedScene& base, Scene scene);

struct PathCounters {
  uint64_t rays = 0;  // every ray cast: camera, bounce and shadow rays
};

// What a camera path saw first, for a reconstruction's feature weights (RECONSTRUCTION.md
// §1), recorded at the first non-specular hit (through mirrors and glass): its reflectance
// times the specular chain's throughput, shading normal and distance along the path. A
// path that escapes has albedo 1, normal 0 and depth 0. `emission` is the part of the
// radiance seen along the camera's specular chain (emitters and background seen directly or
// in a mirror): a reconstruction adds it back after filtering. Recording them consumes no
// random numbers and leaves the radiance bit for bit as it is without them.
struct PathFeatures {
  vec3 albedo{1.0f};
  vec3 normal{0.0f};
  float depth = 0.0f;
  vec3 emission{0.0f};
  // The light sample of that first non-specular vertex's next-event estimate: its emitting
  // object (LightSample::object; -1: none, e.g. no light sampled there or the sample failed)
  // and where it landed in the object's chart (scene/lights.h; (0.5, 0.5) without one).
  int lightObject = -1;
  glm::vec2 lightChart{0.5f};
  // What that light sample added to the radiance (its next-event estimate, MIS-weighted, with
  // the camera's specular chain's throughput): the part the light chart explains.
  vec3 directLight{0.0f};
};

// Radiance arriving through `sample`; the integrator's own dimensions come from
// `dimensions` (already started on this pixel sample). May be non-finite on a
// numerical failure: callers must check before accumulating. `features`, when given,
// receives the path's first-hit features.
vec3 traceRadiance(const PreparedScene& prepared, const CameraSample& sample,
                   PixelSampler& dimensions, PathCounters& counters,
                   PathFeatures* features = nullptr);

// Geometry and material at a hit, at the ray's time.
struct SurfaceHit {
  vec3 point;
  vec3 geometricNormal;  // unit, counter-clockwise side
  vec3 shadingNormal;    // unit, same side as geometricNormal
  vec2 uv;
  vec3 vertexColor{1.0f};  // the mesh's vertex colours there (white without): scale the base colour
  bool vertexColored = false;
  UvFootprint footprint;  // uv across about one pixel; zero: textures' level 0
  // Of a material that is anisotropic (Material::needsTangents): the tangent frame's +u and +v
  // directions, orthonormal around shadingNormal; zero without.
  vec3 tangent{0.0f}, bitangent{0.0f};
  // Of a material whose coat has a normal of its own (Material::coatHasOwnNormal): that
  // normal, unit, on the side of geometricNormal; zero without.
  vec3 coatNormal{0.0f};
  uint32_t materialId = 0;
};
// Asks the cache for what surfaceAt(hit) will read: the triangle's vertices' positions,
// normals and uvs and its material (static meshes). Waits only for the triangle's indices;
// changes nothing. A caller with other work (a shadow ray) does it in between; traceRadiance
// does it for every hit as soon as Embree returns it.
void prefetchSurface(const Scene& scene, const Hit& hit);
// With a camera ray's differentials, the hit's footprint for its texture lookups; without
// them but with the camera, the footprint the camera would give the point
// (approximateRayDifferentials); with neither, none.
SurfaceHit surfaceAt(const Scene& scene, const Hit& hit, float time,
                     const RayDifferentials* differentials = nullptr,
                     const CameraFrame* approximateFrom = nullptr);

}  // namespace penumbra
