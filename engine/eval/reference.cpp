#include "eval/reference.h"

#include <utility>

namespace penumbra {

Reference renderReference(const PreparedScene& prepared, int spp, uint64_t seed, int threads,
                          std::function<void(double)> progress, std::vector<uint8_t> pixelMask) {
  RenderOptions options;
  options.spp = spp;
  options.seed = seed;
  options.threads = threads;
  options.progress = std::move(progress);
  options.pixelMask = std::move(pixelMask);
  Reference r;
  r.render = renderImage(prepared, options);
  r.convergence = convergenceOf(r.render.image, r.render.varianceOfMean);
  return r;
}

}  // namespace penumbra
