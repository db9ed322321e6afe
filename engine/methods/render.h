// Whole-image rendering: the LD method (ld.h) run to the end, every pixel drawing `spp`
// samples from its own sampler stream. Pixels are independent and each sums its samples in
// a fixed order, so an image depends only on the seed, never on the number of threads.
#pragma once

#include "core/image.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

namespace penumbra {

struct RenderOptions {
  SamplerKind sampler = SamplerKind::LowDiscrepancy;
  uint64_t seed = 0;
  int spp = 16;
  int threads = 0;  // 0 = all cores
  // Called between rounds with the fraction done; must be quick.
  std::function<void(double)> progress;
  const std::atomic<bool>* cancel = nullptr;
  // Not empty: only the pixels marked 1 are rendered (a shard, methods/shard.h); the others
  // stay zero, with zero variance.
  std::vector<uint8_t> pixelMask;
};

struct RenderResult {
  Image image;           // per-pixel mean of the finite samples (box filter)
  Image varianceOfMean;  // per channel: unbiased sample variance / sample count
  uint64_t rays = 0;
  uint64_t samples = 0;
  uint64_t nonFiniteSamples = 0;  // NaN or infinite samples, dropped and counted
  double seconds = 0;
  bool cancelled = false;
};

RenderResult renderImage(const PreparedScene& prepared, const RenderOptions& options);

}  // namespace penumbra
