#include "trace/integrator.h"

#include "scene/materials.h"
#include "scene/tangents.h"
#include "scene/textures.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {
// Origins of secondary rays move off the surface by a distance relative to its scale.
vec3 offsetOrigin(vec3 p, vec3 n, vec3 direction) {
  const float scale = std::max({1.0f, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const float eps = 2e-4f * scale;
  return p + (glm::dot(direction, n) > 0 ? eps : -eps) * n;
}

float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

// glTF's KHR_materials_anisotropy on the specular lobes of `b` (whose alpha is set): alpha
// mix(alpha, 1, strength^2) along the direction, alpha across it, in a frame whose s is the
// direction. Isotropic where the strength comes to 0 or the direction is lost.
void applyAnisotropy(const Scene& scene, const Material& m, const SurfaceHit& s, SurfaceBsdf& b) {
  float strength = m.anisotropyStrength;
  glm::vec2 direction(1.0f, 0.0f);
  if (m.anisotropyTexture >= 0) {
    const vec3 t =
        evalTexture(scene, scene.textures[size_t(m.anisotropyTexture)], s.uv, s.footprint);
    direction = 2.0f * glm::vec2(t.x, t.y) - glm::vec2(1.0f);
    strength *= std::clamp(t.z, 0.0f, 1.0f);
  }
  const float c = std::cos(m.anisotropyRotation), sn = std::sin(m.anisotropyRotation);
  const glm::vec2 turned(c * direction.x - sn * direction.y, sn * direction.x + c * direction.y);
  const vec3 along = turned.x * s.tangent + turned.y * s.bitangent;
  const float length = glm::length(along);
  if (!(strength > 0) || !(length > 1e-6f)) return;
  b.anisotropic = true;
  b.alphaY = b.alpha;
  b.alpha = b.alpha + (1.0f - b.alpha) * std::min(strength * strength, 1.0f);
  b.frame.n = s.shadingNormal;
  b.frame.s = along / length;
  b.frame.t = glm::cross(b.frame.n, b.frame.s);
}

SurfaceBsdf makeBsdf(const Scene& scene, const SurfaceHit& s) {
  const Material& m = scene.materials[s.materialId];
  SurfaceBsdf b;
  b.type = m.type;
  b.color = m.albedoTexture >= 0
                ? evalTexture(scene, scene.textures[size_t(m.albedoTexture)], s.uv, s.footprint)
                : m.albedo;
  if (s.vertexColored) b.color *= s.vertexColor;
  float metallic = m.metallic, roughness = m.roughness;
  if (m.metallicRoughnessTexture >= 0) {
    const vec3 t =
        evalTexture(scene, scene.textures[size_t(m.metallicRoughnessTexture)], s.uv, s.footprint);
    roughness *= t.y;
    metallic *= std::clamp(t.z, 0.0f, 1.0f);
  }
  const auto texel = [&](int texture) {
    return evalTexture(scene, scene.textures[size_t(texture)], s.uv, s.footprint);
  };
  if (m.type == Material::Type::Pbr) {
    float transmission = m.transmission;
    if (m.transmissionTexture >= 0 && transmission > 0)
      transmission *= std::clamp(texel(m.transmissionTexture).x, 0.0f, 1.0f);
    b.conductorWeight = metallic;
    b.dielectricWeight = (1.0f - metallic) * transmission;
    b.diffuseWeight = std::max(0.0f, 1.0f - b.conductorWeight - b.dielectricWeight);
    if (m.sheenColor != vec3(0.0f)) {
      b.sheen = m.sheenColor;
      float sheenRoughness = m.sheenRoughness;
      if (m.sheenColorTexture >= 0) b.sheen *= texel(m.sheenColorTexture);
      if (m.sheenRoughnessTexture >= 0) sheenRoughness *= texel(m.sheenRoughnessTexture).x;
      b.sheen = glm::clamp(b.sheen, vec3(0.0f), vec3(1.0f));
      b.sheenAlpha = std::clamp(sheenRoughness * sheenRoughness, kMinSheenAlpha, 1.0f);
    }
    if (m.iridescence > 0) {
      b.iridescence = m.iridescence;
      if (m.iridescenceTexture >= 0)
        b.iridescence *= std::clamp(texel(m.iridescenceTexture).x, 0.0f, 1.0f);
      b.iridescenceIor = m.iridescenceIor;
      b.iridescenceThickness =
          m.iridescenceThicknessTexture >= 0
              ? glm::mix(m.iridescenceThicknessMin, m.iridescenceThicknessMax,
                         std::clamp(texel(m.iridescenceThicknessTexture).y, 0.0f, 1.0f))
              : m.iridescenceThicknessMax;
    }
  }
  const float alpha = roughness * roughness;
  b.alpha = std::clamp(alpha, 1e-3f, 1.0f);
  if (m.type == Material::Type::Pbr && m.anisotropyStrength > 0 && s.tangent != vec3(0.0f))
    applyAnisotropy(scene, m, s, b);
  b.ior = m.ior;
  b.specular = m.specular;
  b.specularColor = m.specularColor;
  b.coat = m.clearcoat;
  float coatRoughness = m.clearcoatRoughness;
  if (m.specularTexture >= 0) b.specular *= std::clamp(texel(m.specularTexture).x, 0.0f, 1.0f);
  if (m.specularColorTexture >= 0) b.specularColor *= texel(m.specularColorTexture);
  if (m.clearcoatTexture >= 0) b.coat *= std::clamp(texel(m.clearcoatTexture).x, 0.0f, 1.0f);
  if (m.clearcoatRoughnessTexture >= 0) coatRoughness *= texel(m.clearcoatRoughnessTexture).y;
  b.coatAlpha = std::clamp(coatRoughness * coatRoughness, 1e-3f, 1.0f);
  if (!b.anisotropic) b.frame = makeFrame(s.shadingNormal);
  if (b.coat > 0 && s.coatNormal != vec3(0.0f) && s.coatNormal != s.shadingNormal) {
    b.coatFrame = makeFrame(s.coatNormal);
    b.coatHasOwnFrame = true;
  }
  b.geometricNormal = s.geometricNormal;
  return b;
}

// Per bounce: light choice (1D), light point (2D), BSDF direction (2D), lobe (1D), roulette (1D).
}  // namespace

namespace {

// Camera frame and the flags that follow from the camera.
void setCamera(PreparedScene& prepared) {
  const Scene& s = prepared.scene;
  try {
    prepared.camera = makeCameraFrame(s.camera, s.settings.width, s.settings.height);
  } catch (const std::invalid_argument& e) {
    throw SceneError(s.sourcePath + ": camera: " + e.what());
  }
  prepared.usesLens = prepared.camera.lensRadius > 0;
  prepared.usesTime =
      s.camera.shutterClose > s.camera.shutterOpen &&
      std::any_of(s.meshes.begin(), s.meshes.end(), [](const Mesh& m) { return m.timeSteps > 1; });
}

}  // namespace

std::unique_ptr<PreparedScene> prepareScene(Scene scene) {
  auto prepared = std::make_unique<PreparedScene>();
  prepared->scene = std::move(scene);
  setCamera(*prepared);  // first: a bad camera fails before the BVH is built
  prepared->accel = std::make_shared<const Accel>(prepared->scene);
  prepared->lights = buildLightSampler(prepared->scene);
  return prepared;
}

std::unique_ptr<PreparedScene> prepareView(const PreparedScene& base, const Camera& camera) {
  auto prepared = std::make_unique<PreparedScene>();
  prepared->scene = base.scene;
  prepared->scene.camera = camera;
  setCamera(*prepared);
  prepared->accel = base.accel;
  prepared->lights = base.lights;
  return prepared;
}

std::unique_ptr<PreparedScene> prepareLighting(const PreparedScene& base, Scene scene) {
  auto prepared = std::make_unique<PreparedScene>();
  prepared->scene = std::move(scene);
  setCamera(*prepared);
  prepared->accel = base.accel;
  prepared->lights = buildLightSampler(prepared->scene);
  return prepared;
}

std::unique_ptr<PreparedScene> prepareView(const PreparedScene& base, const Camera& camera,
                                           int regionX, int regionY, int regionW, int regionH) {
  Camera cropped = camera;
  cropped.regionX = regionX;
  cropped.regionY = regionY;
  cropped.fullWidth = base.scene.settings.width;
  cropped.fullHeight = base.scene.settings.height;
  auto prepared = std::make_unique<PreparedScene>();
  prepared->scene = base.scene;
  prepared->scene.camera = cropped;
  prepared->scene.settings.width = regionW;
  prepared->scene.settings.height = regionH;
  setCamera(*prepared);
  prepared->accel = base.accel;
  prepared->lights = base.lights;
  return prepared;
}

namespace {
// The tangent frame at a hit, around its shading normal: the mesh's vertex tangents' there
// (scene/tangents.h), else the triangle's (dp/du, dp/dv) made orthonormal; false when the
// triangle's dp/du lies along the normal.
bool hitTangentFrame(const Mesh& mesh, const uint32_t* idx, const Hit& hit, vec3 dpdu, vec3 dpdv,
                     const SurfaceHit& s, vec3& t, vec3& b) {
  const vec3 n = s.shadingNormal;
  if (vertexTangentFrame(mesh, idx, 1 - hit.u - hit.v, hit.u, hit.v, n, t, b)) return true;
  t = dpdu - n * glm::dot(n, dpdu);
  const float tLength = glm::length(t);
  if (!(tLength > 1e-12f)) return false;
  t /= tLength;
  b = glm::cross(n, t);
  if (glm::dot(b, dpdv) < 0) b = -b;
  return true;
}

// The normal n tilted by the tangent-space normal map `texture` (its x and y scaled by
// `scale`) read in the frame (t, b); the map's +y runs along +v (up the image: OpenGL's and
// glTF's convention). A map pointing under the surface (or a broken texel) leaves n as it is.
vec3 mappedNormal(const Scene& scene, int texture, float scale, vec3 n, vec3 t, vec3 b,
                  const SurfaceHit& s) {
  vec3 c =
      2.0f * evalTexture(scene, scene.textures[size_t(texture)], s.uv, s.footprint) - vec3(1.0f);
  c.x *= scale;
  c.y *= scale;
  const vec3 mapped = c.x * t + c.y * b + c.z * n;
  const float length = glm::length(mapped);
  return length > 1e-6f && glm::dot(mapped, s.geometricNormal) > 0 ? mapped / length : n;
}

// The hit's tangent frame made orthonormal around its (possibly mapped) shading normal, for
// anisotropy: t keeps its direction in the tangent plane, b the side it was on.
void keepTangentFrame(vec3 t, vec3 b, SurfaceHit& s) {
  const vec3 n = s.shadingNormal;
  t -= n * glm::dot(n, t);
  const float length = glm::length(t);
  if (!(length > 1e-12f)) return;
  s.tangent = t / length;
  s.bitangent = glm::cross(n, s.tangent);
  if (glm::dot(s.bitangent, b) < 0) s.bitangent = -s.bitangent;
}
}  // namespace

void prefetchSurface(const Scene& scene, const Hit& hit) {
  // The hit's vertices are read at random (a cache miss each on a large mesh): ask for the
  // positions, normals, uvs, tangents and material together rather than one after the other.
  const Mesh& mesh = scene.meshes[hit.meshId];
  if (mesh.timeSteps > 1) return;
  __builtin_prefetch(&mesh.materialIds[hit.primId]);
  const uint32_t* idx = &mesh.indices[3 * size_t(hit.primId)];
  for (int k = 0; k < 3; ++k) {
    __builtin_prefetch(&mesh.positions[idx[k]]);
    if (!mesh.normals.empty()) __builtin_prefetch(&mesh.normals[idx[k]]);
    if (!mesh.uvs.empty()) __builtin_prefetch(&mesh.uvs[idx[k]]);
    if (!mesh.tangents.empty()) __builtin_prefetch(&mesh.tangents[idx[k]]);
  }
}

namespace {
// A vertex's shadow ray, traced after the ray that continues the path, while the data of that
// ray's hit (its triangle's vertices, or the environment's texels) arrive in cache. Its
// contribution joins the radiance at the same place in the sum as if traced at once.
struct PendingShadow {
  bool active = false;
  Ray ray;
  float tMax = 0;
  vec3 contribution{0.0f};
  vec3* record = nullptr;  // also adds the contribution here (a path feature)
  void trace(const Accel& accel, PathCounters& counters, vec3& radiance) {
    if (!active) return;
    active = false;
    ++counters.rays;
    if (accel.occluded(ray, 0.0f, tMax)) return;
    radiance += contribution;
    if (record) *record += contribution;
  }
};

// Along the camera's specular chain, its length so far; at its first non-specular vertex the
// path's features there (throughput times albedo, normal, the chain's length), the chain
// ended, and true.
bool recordCameraChain(PathFeatures* features, bool& cameraChain, float& chainLength, float t,
                       const SurfaceBsdf& bsdf, vec3 throughput, const SurfaceHit& surface) {
  if (!features || !cameraChain) return false;
  chainLength += t;
  if (bsdf.isSpecular()) return false;
  features->albedo = throughput * bsdf.color;
  features->normal = surface.shadingNormal;
  features->depth = chainLength;
  cameraChain = false;
  return true;
}

// Russian roulette once the path has a few vertices (before them its dimension is skipped):
// false ends the path; a survivor's throughput is divided by its chance.
bool survivesRoulette(int depth, vec3& throughput, PixelSampler& dimensions) {
  if (depth < 2) {
    dimensions.skip(1);
    return true;
  }
  const float survive = std::min(0.95f, std::max({throughput.x, throughput.y, throughput.z}));
  if (dimensions.next1D() >= survive) return false;
  throughput /= survive;
  return true;
}
}  // namespace

SurfaceHit surfaceAt(const Scene& scene, const Hit& hit, float time,
                     const RayDifferentials* differentials, const CameraFrame* approximateFrom) {
  const Mesh& mesh = scene.meshes[hit.meshId];
  const uint32_t* idx = &mesh.indices[3 * size_t(hit.primId)];
  vec3 p0, p1, p2;
  trianglePositions(mesh, hit.primId, time, p0, p1, p2);
  const float b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;
  SurfaceHit s;
  s.point = b0 * p0 + b1 * p1 + b2 * p2;
  s.geometricNormal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  s.shadingNormal = s.geometricNormal;
  if (!mesh.normals.empty()) {
    const vec3 n = b0 * vertexAtTime(mesh.normals, mesh, idx[0], time) +
                   b1 * vertexAtTime(mesh.normals, mesh, idx[1], time) +
                   b2 * vertexAtTime(mesh.normals, mesh, idx[2], time);
    const float len = glm::length(n);
    if (len > 1e-6f) {
      s.shadingNormal = n / len;
      if (glm::dot(s.shadingNormal, s.geometricNormal) < 0) s.shadingNormal = -s.shadingNormal;
    }
  }
  s.uv = mesh.uvs.empty() ? vec2(0.0f)
                          : b0 * mesh.uvs[idx[0]] + b1 * mesh.uvs[idx[1]] + b2 * mesh.uvs[idx[2]];
  if (!mesh.colors.empty()) {
    s.vertexColor = b0 * mesh.colors[idx[0]] + b1 * mesh.colors[idx[1]] + b2 * mesh.colors[idx[2]];
    s.vertexColored = true;
  }
  s.materialId = mesh.materialIds[hit.primId];
  // The triangle's tangents orient a normal map and turn differentials into a uv footprint:
  // only a textured material needs them.
  const Material& material = scene.materials[s.materialId];
  const bool textured = material.textured() || material.needsTangents();
  vec3 dpdu, dpdv, dpdx, dpdy;
  if (!textured || mesh.uvs.empty() ||
      !triangleTangents(p1 - p0, p2 - p0, mesh.uvs[idx[1]] - mesh.uvs[idx[0]],
                        mesh.uvs[idx[2]] - mesh.uvs[idx[0]], dpdu, dpdv))
    return s;
  RayDifferentials approximate;
  if (!differentials && approximateFrom &&
      approximateRayDifferentials(*approximateFrom, s.point, approximate))
    differentials = &approximate;
  if (differentials && differentialOffsets(*differentials, s.point, s.geometricNormal, dpdx, dpdy))
    s.footprint = uvFootprint(dpdx, dpdy, dpdu, dpdv);
  vec3 t, b;
  if (!material.needsTangents() || !hitTangentFrame(mesh, idx, hit, dpdu, dpdv, s, t, b)) return s;
  const vec3 interpolated = s.shadingNormal;
  if (material.normalTexture >= 0)
    s.shadingNormal =
        mappedNormal(scene, material.normalTexture, material.normalScale, interpolated, t, b, s);
  if (material.coatHasOwnNormal())
    s.coatNormal = material.clearcoatNormalTexture >= 0
                       ? mappedNormal(scene, material.clearcoatNormalTexture,
                                      material.clearcoatNormalScale, interpolated, t, b, s)
                       : interpolated;
  if (material.anisotropyStrength > 0) keepTangentFrame(t, b, s);
  return s;
}

vec3 traceRadiance(const PreparedScene& prepared, const CameraSample& sample,
                   PixelSampler& dimensions, PathCounters& counters, PathFeatures* features) {
  const Scene& scene = prepared.scene;
  const Accel& accel = *prepared.accel;
  const int maxDepth = scene.settings.maxDepth;
  Ray ray = generateRay(prepared.camera, sample);
  // A footprint of one pixel chooses the mip levels of the first hit's image textures; the
  // hits of later rays take the footprint the camera would give them if it saw them directly
  // (pbrt-v4's approximation): coarser levels for far hits, which are smoother and stay in
  // cache, where level 0 read at random missed it at every lookup.
  const bool footprints = !scene.images.empty();
  RayDifferentials differentials;  // the camera ray's, made while its hit's data arrive
  vec3 radiance(0.0f), throughput(1.0f);
  bool specularBounce = false;
  float previousBsdfPdf = 0;
  vec3 previousPoint = ray.origin;
  // Features: still on the camera's specular chain, and its length so far.
  bool cameraChain = true;
  float chainLength = 0;
  if (features) *features = PathFeatures{};

  const EnvironmentLight* environment = prepared.lights.environment.get();
  if (environment && environment->constant()) environment = nullptr;  // nothing to prefetch
  PendingShadow shadow;
  auto traceShadow = [&] { shadow.trace(accel, counters, radiance); };
  for (int depth = 0;; ++depth) {
    // The environment's sampling tables are large and read at random: ask for what the next
    // event estimate at this ray's hit will read (its light point is the dimension after the
    // light choice) while Embree traces the ray; for a camera ray, of which many escape, only
    // once it hit something, while that hit's data arrive.
    glm::vec2 uNextLightPoint;
    auto prefetchNextEvent = [&] {
      if (environment && dimensions.peek2D(1, uNextLightPoint, Scrambling::Owen))
        environment->prefetch(uNextLightPoint);
    };
    if (depth > 0) prefetchNextEvent();
    Hit hit;
    ++counters.rays;
    const bool found = accel.intersect(ray, 0.0f, INFINITY, hit);
    if (found) {
      prefetchSurface(scene, hit);
      if (depth == 0) prefetchNextEvent();
    } else if (environment && shadow.active) {
      environment->prefetchDirection(ray.direction);
    }
    if (depth == 0 && found && footprints)
      differentials = cameraRayDifferentials(prepared.camera, sample);
    traceShadow();
    if (!found) {
      // The environment, weighted against its own light sampling (a camera ray sees the
      // backdrop, which nothing light-samples).
      const bool weighted = depth > 0 && !specularBounce && prepared.lights.environment;
      float lightPdf = 0;
      const vec3 seen = escapedRadiance(scene, prepared.lights, ray.direction, depth == 0,
                                        weighted ? &lightPdf : nullptr);
      const float weight = weighted ? powerHeuristic(previousBsdfPdf, lightPdf) : 1.0f;
      radiance += throughput * seen * weight;
      if (features && cameraChain) features->emission += throughput * seen * weight;
      break;
    }
    const SurfaceHit surface =
        surfaceAt(scene, hit, ray.time, depth == 0 && footprints ? &differentials : nullptr,
                  depth > 0 && footprints ? &prepared.camera : nullptr);
    const Material& material = scene.materials[surface.materialId];
    const vec3 wo = -ray.direction;
    // A ray that reached the back of an absorbing object's surface travelled inside it.
    if (material.absorbs() && glm::dot(wo, surface.geometricNormal) < 0)
      throughput *= glm::pow(material.attenuationColor, vec3(hit.t / material.attenuationDistance));

    // Emission, on the counter-clockwise side only, weighted against light sampling.
    if (material.isEmissive() && glm::dot(wo, surface.geometricNormal) > 0) {
      float weight = 1.0f;
      if (depth > 0 && !specularBounce && !prepared.lights.empty()) {
        const float pl = lightPdf(scene, prepared.lights, hit.meshId, hit.primId, previousPoint,
                                  surface.point, surface.geometricNormal, ray.time);
        weight = powerHeuristic(previousBsdfPdf, pl);
      }
      const vec3 emitted = emittedRadiance(scene, material, surface.uv, surface.footprint);
      radiance += throughput * emitted * weight;
      if (features && cameraChain) features->emission += throughput * emitted * weight;
    }
    // Unlit (glTF's KHR_materials_unlit): its colour to every ray, and nothing reflected.
    if (material.unlit) {
      const vec3 shown = throughput * makeBsdf(scene, surface).color;
      radiance += shown;
      if (features && cameraChain) features->emission += shown;
      break;
    }
    if (depth >= maxDepth) break;

    const SurfaceBsdf bsdf = makeBsdf(scene, surface);
    // The first non-specular vertex: its light sample is a feature too.
    const bool recordLight =
        recordCameraChain(features, cameraChain, chainLength, hit.t, bsdf, throughput, surface);

    // Every bounce owns five dimensions (above), drawn only when used and skipped
    // otherwise, so each dimension means the same thing in every path of the pixel. The light's
    // two are Owen-scrambled: their fine digits choose an emitter among many and an environment
    // texel through its alias tables (Scrambling in trace/sampler.h).
    const bool nextEvent = !bsdf.isSpecular() && !prepared.lights.empty();
    if (nextEvent) {
      const float uLight = dimensions.next1D(Scrambling::Owen);
      const glm::vec2 uLightPoint = dimensions.next2D(Scrambling::Owen);
      LightSample ls;
      if (sampleLight(scene, prepared.lights, surface.point, ray.time, uLight, uLightPoint, ls)) {
        if (recordLight) {
          features->lightObject = ls.object;
          features->lightChart = lightChart(prepared.lights, ls);
        }
        const vec3 wi = ls.wi;
        const vec3 f = evalBsdfCos(bsdf, wo, wi);
        if (f.x > 0 || f.y > 0 || f.z > 0) {
          shadow.active = true;
          shadow.ray = Ray{offsetOrigin(surface.point, surface.geometricNormal, wi), wi, ray.time};
          shadow.tMax = ls.distance * (1.0f - 1e-3f);
          // A punctual light cannot be hit by a BSDF sample: its sample takes all the weight.
          const float weight = ls.delta ? 1.0f : powerHeuristic(ls.pdf, bsdfPdf(bsdf, wo, wi));
          shadow.contribution = throughput * f * ls.radiance * (weight / ls.pdf);
          shadow.record = recordLight ? &features->directLight : nullptr;
        }
      }
    } else {
      dimensions.skip(2);
    }

    // Continue the path by sampling the BSDF.
    const glm::vec2 uBsdf = dimensions.next2D();
    float uLobe = 0.5f;
    if (bsdf.choosesLobe())
      uLobe = dimensions.next1D();
    else
      dimensions.skip(1);
    BsdfSample bs;
    if (!sampleBsdf(bsdf, wo, uBsdf, uLobe, bs)) break;
    throughput *= bs.weight;
    specularBounce = bs.specular;
    previousBsdfPdf = bs.pdf;
    previousPoint = surface.point;
    ray = Ray{offsetOrigin(surface.point, surface.geometricNormal, bs.wi), bs.wi, ray.time};

    if (!survivesRoulette(depth, throughput, dimensions)) break;
  }
  traceShadow();  // the last vertex's, when the path ended there
  return radiance;
}

}  // namespace penumbra
