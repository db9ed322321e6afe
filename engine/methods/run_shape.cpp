#include "methods/run_shape.h"

#include <cmath>

namespace penumbra {

RunShape RunShape::batch(int spp, uint64_t seed) {
  RunShape s;
  s.spp = spp;
  s.seed = seed;
  return s;
}

RunShape RunShape::progressive(int roundSpp, uint64_t seed, int maxSpp) {
  RunShape s;
  s.openEnded = true;
  s.roundSpp = roundSpp;
  s.seed = seed;
  s.maxSpp = maxSpp;
  return s;
}

std::string RunShape::validate() const {
  if (!openEnded && spp < 1) return "--spp must be at least 1";
  if (openEnded && roundSpp < 1) return "--round-spp must be at least 1";
  if (maxSpp < 0) return "the maximum spp must not be negative";
  if (!(timeLimit >= 0) || std::isinf(timeLimit))
    return "--time-limit must be a finite number of seconds, at least 0";
  if (!(noiseThreshold >= 0) || std::isinf(noiseThreshold))
    return "--noise-threshold must be a finite relMSE, at least 0";
  return {};
}

}  // namespace penumbra
