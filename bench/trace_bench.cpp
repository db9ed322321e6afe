// Path tracer throughput against raw Embree traversal, on the same rays.
//
// 1. Render the scene with the full path tracer (sampling, shading, NEE, MIS) and count
//    rays per second.
// 2. Record the exact queries the path tracer made for a subset of pixels, then replay
//    them through rtcIntersect1 / rtcOccluded1 alone, on the same threads.
// The ratio (1)/(2) is the fraction of raw traversal speed the path tracer keeps; the
// goal is at least 0.6. Runs are interleaved and the best of several is kept for each,
// so a noisy neighbour on the machine hurts both sides alike.
//
// Usage: penumbra_bench_trace [scene.json] [--spp N] [--size WxH] [--repeats R]
#include "methods/render.h"
#include "scene/scene_loader.h"
#include "trace/accel.h"
#include "trace/integrator.h"

#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace penumbra;

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<RecordedQuery> recordQueries(const PreparedScene& prepared, int spp) {
  // Every 7th pixel of the image, one thread: a representative, deterministic ray mix.
  std::vector<RecordedQuery> log;
  recordQueriesOnThisThread(&log);
  PixelSampler sampler(SamplerKind::LowDiscrepancy, 1, uint32_t(spp));
  PathCounters counters;
  const int w = prepared.scene.settings.width, h = prepared.scene.settings.height;
  for (int p = 0; p < w * h; p += 7)
    for (int i = 0; i < spp; ++i) {
      sampler.startSample(p % w, p / w, uint32_t(i));
      traceRadiance(prepared, sampler.cameraSample(prepared.usesLens, prepared.usesTime), sampler,
                    counters);
    }
  recordQueriesOnThisThread(nullptr);
  return log;
}

double replayRaw(const PreparedScene& prepared, const std::vector<RecordedQuery>& queries) {
  RTCScene scene = static_cast<RTCScene>(prepared.accel->embreeScene());
  const double start = now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, queries.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& r) {
                      enableFlushToZero();
                      RTCIntersectContext context;
                      rtcInitIntersectContext(&context);
                      unsigned sink = 0;
                      for (size_t i = r.begin(); i < r.end(); ++i) {
                        const RecordedQuery& q = queries[i];
                        RTCRayHit rh;
                        RTCRay& ray = rh.ray;
                        ray.org_x = q.ray.origin.x, ray.org_y = q.ray.origin.y,
                        ray.org_z = q.ray.origin.z;
                        ray.dir_x = q.ray.direction.x, ray.dir_y = q.ray.direction.y,
                        ray.dir_z = q.ray.direction.z;
                        ray.tnear = q.tMin, ray.tfar = q.tMax, ray.time = q.ray.time;
                        ray.mask = 0xFFFFFFFFu, ray.id = 0, ray.flags = 0;
                        if (q.shadow) {
                          rtcOccluded1(scene, &context, &ray);
                          sink += ray.tfar < 0;
                        } else {
                          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                          rtcIntersect1(scene, &context, &rh);
                          sink += rh.hit.geomID;
                        }
                      }
                      volatile unsigned keep = sink;
                      (void)keep;
                    });
  return double(queries.size()) / (now() - start);
}
}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/dragon.json";
  int spp = 8, repeats = 3, width = 0, height = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--spp" && i + 1 < argc)
      spp = std::max(1, std::atoi(argv[++i]));
    else if (a == "--repeats" && i + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++i]));
    else if (a == "--size" && i + 1 < argc)
      std::sscanf(argv[++i], "%dx%d", &width, &height);
    else if (a.rfind("--", 0) == 0) {
      std::fprintf(stderr,
                   "penumbra_bench_trace: unknown flag %s\nusage: %s [scene] [--spp N] [--size "
                   "WxH] [--repeats R]\n",
                   a.c_str(), argv[0]);
      return 2;
    } else
      scenePath = a;
  }
  try {
    Scene scene = loadScene(scenePath);
    if (width > 0 && height > 0) scene.settings.width = width, scene.settings.height = height;
    auto prepared = prepareScene(std::move(scene));
    const std::vector<RecordedQuery> queries = recordQueries(*prepared, spp);
    size_t shadow = 0;
    for (const auto& q : queries) shadow += q.shadow;

    double bestTracer = 0, bestRaw = 0;
    for (int r = 0; r < repeats; ++r) {
      RenderOptions options;
      options.spp = spp;
      options.seed = uint64_t(r);
      const RenderResult result = renderImage(*prepared, options);
      bestTracer = std::max(bestTracer, double(result.rays) / result.seconds);
      bestRaw = std::max(bestRaw, replayRaw(*prepared, queries));
    }
    std::printf("scene               %s (%dx%d, %d spp, %u threads)\n", scenePath.c_str(),
                prepared->scene.settings.width, prepared->scene.settings.height, spp,
                std::thread::hardware_concurrency());
    std::printf("replayed queries    %zu (%.0f%% shadow rays)\n", queries.size(),
                100.0 * double(shadow) / double(queries.size()));
    std::printf("path tracer         %.2f Mrays/s (best of %d)\n", bestTracer * 1e-6, repeats);
    std::printf("raw Embree          %.2f Mrays/s (rtcIntersect1/rtcOccluded1 on the same rays)\n",
                bestRaw * 1e-6);
    std::printf("ratio               %.2f (goal >= 0.60)\n", bestTracer / bestRaw);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_bench_trace: %s\n", e.what());
    return 1;
  }
  return 0;
}
