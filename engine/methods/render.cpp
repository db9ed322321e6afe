#include "methods/render.h"

#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <memory>

namespace penumbra {

namespace {
constexpr int kTileSize = 16;

}  // namespace

RenderResult renderImage(const PreparedScene& prepared, const RenderOptions& options) {
  const int width = prepared.scene.settings.width, height = prepared.scene.settings.height;
  const auto start = std::chrono::steady_clock::now();
  RenderResult result;
  result.image = Image(width, height);
  result.varianceOfMean = Image(width, height);

  std::unique_ptr<tbb::global_control> limit;
  if (options.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(options.threads));

  std::atomic<uint64_t> rays{0}, nonFinite{0}, pixelsDone{0};
  const uint64_t pixelCount = uint64_t(width) * height;
  const int spp = std::max(1, options.spp);

  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, height, kTileSize, 0, width, kTileSize),
      [&](const tbb::blocked_range2d<int>& tile) {
        enableFlushToZero();
        if (options.cancel && options.cancel->load(std::memory_order_relaxed)) return;
        PixelSampler sampler(options.sampler, options.seed, uint32_t(spp));
        PathCounters counters;
        uint64_t tileNonFinite = 0;
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
            // Welford's running mean and variance, in sample order.
            glm::dvec3 mean(0.0), m2(0.0);
            int kept = 0;
            for (int i = 0; i < spp; ++i) {
              sampler.startSample(x, y, uint32_t(i));
              const vec3 L = traceRadiance(
                  prepared, sampler.cameraSample(prepared.usesLens, prepared.usesTime), sampler,
                  counters);
              if (!isFinite(L)) {
                ++tileNonFinite;
                continue;
              }
              ++kept;
              const glm::dvec3 d = glm::dvec3(L) - mean;
              mean += d / double(kept);
              m2 += d * (glm::dvec3(L) - mean);
            }
            result.image.at(x, y) = vec3(mean);
            result.varianceOfMean.at(x, y) =
                kept > 1 ? vec3(m2 / (double(kept - 1) * kept)) : vec3(0.0f);
          }
        }
        rays += counters.rays;
        nonFinite += tileNonFinite;
        const uint64_t done = pixelsDone += uint64_t(tile.rows().size()) * tile.cols().size();
        if (options.progress) options.progress(double(done) / double(pixelCount));
      },
      tbb::simple_partitioner());

  result.rays = rays;
  result.nonFiniteSamples = nonFinite;
  result.samples = pixelCount * uint64_t(spp);
  result.cancelled = options.cancel && options.cancel->load();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace penumbra
