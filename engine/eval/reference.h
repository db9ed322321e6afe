// References: a converged low-discrepancy render (the LD method run to the end) with its
// per-pixel variance and how converged it is, for `penumbra reference`, `compare` when no
// reference is given, and the tests.
#pragma once

#include "eval/metrics.h"
#include "methods/render.h"

#include <cstdint>
#include <functional>

namespace penumbra {

struct Reference {
  RenderResult render;      // the image and its variance of the mean
  Convergence convergence;  // its residual MSE and mean relative error
};

// `threads` 0 = all cores; `progress` (may be empty) gets the fraction done; `pixelMask` (may
// be empty) limits it to a shard's pixels (methods/shard.h).
Reference renderReference(const PreparedScene& prepared, int spp, uint64_t seed, int threads,
                          std::function<void(double)> progress = {},
                          std::vector<uint8_t> pixelMask = {});

}  // namespace penumbra
