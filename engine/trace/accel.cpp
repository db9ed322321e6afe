#include "trace/accel.h"

#include "scene/scene.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra {

struct Accel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string firstError;  // Embree reports through a C callback: remember, throw later
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
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl_->scene, geom, unsigned(m));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->scene);
  if (!impl_->firstError.empty()) throw std::runtime_error(impl_->firstError);
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
