#include "methods/render.h"

#include "methods/ld/ld.h"

#include <tbb/global_control.h>

#include <chrono>
#include <memory>

namespace penumbra {

RenderResult renderImage(const PreparedScene& prepared, const RenderOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<tbb::global_control> limit;
  if (options.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(options.threads));
  RunShape shape = RunShape::batch(std::max(1, options.spp), options.seed);
  shape.sampler = options.sampler;
  LdMethod method(prepared, shape);
  if (!options.pixelMask.empty()) method.renderOnly(options.pixelMask);
  RenderResult result;
  while (!method.done()) {
    method.runRound(options.cancel);
    if (options.cancel && options.cancel->load()) break;
    if (options.progress) options.progress(double(method.samplesPerPixel()) / double(shape.spp));
  }
  const auto snap = method.snapshot(false, nullptr);
  result.image = std::move(snap->raw);
  result.varianceOfMean = method.varianceOfMean();
  result.rays = snap->rays;
  result.nonFiniteSamples = snap->nonFiniteSamples;
  result.samples = snap->tracedSamples;
  result.cancelled = options.cancel && options.cancel->load();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace penumbra
