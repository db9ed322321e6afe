#include "trace/accel.h"

#include "scene/scene.h"
#include "scene/textures.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra {

// Named, not anonymous: Accel::Impl holds CutoutMesh, and a type with external linkage must not
// hold one with internal linkage (-Wsubobject-linkage in a unity build).
namespace accel_detail {
// What a mesh with cut-out materials needs to test a hit's coverage, copied out of the scene so
// that the acceleration structure stands alone (views share it while scenes come and go).
struct CutoutMesh {
  struct Coverage {
    float alpha = 1.0f, cutoff = -1.0f;
    bool blend = false;  // the coverage is the chance of a stop, not tested against `cutoff`
    int image = -1;      // into Accel::Impl::cutoutImages; -1: the factor alone
    Texture mapping;     // the texture's wrap modes and uv transform
  };
  std::vector<uint32_t> indices;
  std::vector<vec2> uvs;
  std::vector<uint32_t> materialIds;
  std::vector<Coverage> coverage;  // per material id of the scene
  const std::vector<TextureImage>* images = nullptr;

  // A hole: the material's coverage at the hit's uv is below its cutoff or, blended, below
  // the ray's own number in [0, 1) (`chance`, asked for only then).
  template <typename Chance>
  bool isHole(uint32_t prim, float u, float v, Chance chance) const {
    const Coverage& c = coverage[materialIds[prim]];
    if (c.cutoff < 0 && !c.blend) return false;
    float a = c.alpha;
    if (c.image >= 0 && !uvs.empty()) {
      const uint32_t* idx = &indices[3 * size_t(prim)];
      const vec2 uv = (1 - u - v) * uvs[idx[0]] + u * uvs[idx[1]] + v * uvs[idx[2]];
      a *= sampleImageBilinear((*images)[size_t(c.image)], textureUv(c.mapping, uv), c.mapping.wrap)
               .x;
    }
    return c.blend ? !(chance() < a) : a < c.cutoff;
  }
};

// A number in [0, 1) that only the ray and the primitive decide, so that a ray meets a blended
// surface the same way in its intersection and its occlusion query, whatever the thread: the
// ray's origin, direction and time hashed with the primitive (Wellons' lowbias32 mixer).
float rayChance(const RTCFilterFunctionNArguments* args, unsigned i, uint32_t prim) {
  const unsigned n = args->N;
  const float values[] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i),
                          RTCRayN_org_z(args->ray, n, i), RTCRayN_dir_x(args->ray, n, i),
                          RTCRayN_dir_y(args->ray, n, i), RTCRayN_dir_z(args->ray, n, i),
                          RTCRayN_time(args->ray, n, i)};
  uint32_t h = prim * 0x9e3779b9u + 0x632be5abu;
  for (const float f : values) {
    h ^= std::bit_cast<uint32_t>(f);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
  }
  return float(h >> 8) * 0x1p-24f;
}

void cutoutFilter(const RTCFilterFunctionNArguments* args) {
  const auto* mesh = static_cast<const CutoutMesh*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    if (mesh->isHole(prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i),
                     [&] { return rayChance(args, i, prim); }))
      args->valid[i] = 0;
  }
}
}  // namespace accel_detail

using accel_detail::CutoutMesh;

struct Accel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string firstError;  // Embree reports through a C callback: remember, throw later
  std::vector<std::unique_ptr<CutoutMesh>> cutouts;
  std::vector<TextureImage> cutoutImages;  // copies share the texels
};

namespace {
thread_local std::vector<RecordedQuery>* tQueryLog = nullptr;

void recordEmbreeError(void* user, RTCError code, const char* message) {
  auto* impl = static_cast<Accel::Impl*>(user);
  if (code != RTC_ERROR_NONE && impl->firstError.empty())
    impl->firstError = std::string("Embree error: ") + (message ? message : "unknown");
}

void setRay(RTCRay& r, const Ray& ray, float tMin, float tMax) {
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = tMin;
  r.tfar = tMax;
  r.time = ray.time;
  r.mask = 0xFFFFFFFFu;  // Debian's Embree has ray masks on: mask 0 would miss everything
  r.id = 0;
  r.flags = 0;
}
}  // namespace

Accel::Accel(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("threads=0");
  if (!impl_->device) throw std::runtime_error("cannot create an Embree device");
  rtcSetDeviceErrorFunction(impl_->device, recordEmbreeError, impl_.get());
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  std::vector<int> alphaImages(scene.textures.size(), -1);  // texture -> cutoutImages
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.triangleCount() == 0) continue;
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryTimeStepCount(geom, unsigned(mesh.timeSteps));
    for (int step = 0; step < mesh.timeSteps; ++step) {
      // rtcSetNewGeometryBuffer pads the buffer as Embree requires.
      auto* vertices = static_cast<float*>(
          rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, unsigned(step), RTC_FORMAT_FLOAT3,
                                  3 * sizeof(float), mesh.vertexCount));
      std::memcpy(vertices, &mesh.positions[size_t(step) * mesh.vertexCount],
                  sizeof(float) * 3 * mesh.vertexCount);
    }
    auto* indices = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), mesh.triangleCount()));
    std::memcpy(indices, mesh.indices.data(), sizeof(uint32_t) * mesh.indices.size());
    if (std::any_of(mesh.materialIds.begin(), mesh.materialIds.end(),
                    [&](uint32_t id) { return scene.materials[id].hasCutouts(); })) {
      rtcSetGeometryUserData(geom, addCutouts(scene, mesh, alphaImages));
      rtcSetGeometryIntersectFilterFunction(geom, accel_detail::cutoutFilter);
      rtcSetGeometryOccludedFilterFunction(geom, accel_detail::cutoutFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl_->scene, geom, unsigned(m));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->scene);
  if (!impl_->firstError.empty()) throw std::runtime_error(impl_->firstError);
}

void* Accel::addCutouts(const Scene& scene, const Mesh& mesh, std::vector<int>& alphaImages) {
  auto cut = std::make_unique<CutoutMesh>();
  cut->indices = mesh.indices;
  cut->uvs = mesh.uvs;
  cut->materialIds = mesh.materialIds;
  cut->coverage.resize(scene.materials.size());
  for (size_t id = 0; id < scene.materials.size(); ++id) {
    const Material& m = scene.materials[id];
    CutoutMesh::Coverage& c = cut->coverage[id];
    if (!m.hasCutouts()) continue;
    c.alpha = m.alpha;
    c.cutoff = m.alphaCutoff;
    c.blend = m.alphaBlend;
    if (m.alphaTexture < 0) continue;
    int& image = alphaImages[size_t(m.alphaTexture)];
    const Texture& t = scene.textures[size_t(m.alphaTexture)];
    if (image < 0 && t.kind == Texture::Kind::Image) {
      impl_->cutoutImages.push_back(scene.images[size_t(t.imageIndex)]);
      image = int(impl_->cutoutImages.size() - 1);
    }
    c.image = image;
    c.mapping = t;
  }
  cut->images = &impl_->cutoutImages;
  impl_->cutouts.push_back(std::move(cut));
  return impl_->cutouts.back().get();
}

Accel::~Accel() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

bool Accel::intersect(const Ray& ray, float tMin, float tMax, Hit& hit) const {
  if (tQueryLog) tQueryLog->push_back({ray, tMin, tMax, false});
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  setRay(rh.ray, ray, tMin, tMax);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.meshId = rh.hit.geomID;
  hit.primId = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  return true;
}

bool Accel::occluded(const Ray& ray, float tMin, float tMax) const {
  if (tQueryLog) tQueryLog->push_back({ray, tMin, tMax, true});
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  setRay(r, ray, tMin, tMax);
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar == -std::numeric_limits<float>::infinity();
}

void* Accel::embreeScene() const { return impl_->scene; }

void recordQueriesOnThisThread(std::vector<RecordedQuery>* log) { tQueryLog = log; }

void enableFlushToZero() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

}  // namespace penumbra
