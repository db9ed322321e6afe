// The shape of a run, the same for every method (ALGORITHM.md §11's fair comparison): the
// seed, the budget (a fixed number of kept samples per pixel, or open-ended rounds until
// stopped), the samples a round adds when open-ended, and the sample generator. What a
// method does with its budget is its own configuration (methods/<method>.h). Stopping rules
// that end a run early (a time limit, a noise threshold) belong here too.
#pragma once

#include "trace/sampler.h"

#include <cstdint>
#include <string>

namespace penumbra {

struct RunShape {
  uint64_t seed = 0;
  int spp = 16;            // batch: kept samples per pixel on average
  bool openEnded = false;  // rounds until stopped (the viewer, equal-time runs)
  int roundSpp = 1;        // open-ended: kept samples per pixel each round adds, on average
  int maxSpp = 0;          // open-ended: stop at this average kept spp (0 = never)
  SamplerKind sampler = SamplerKind::LowDiscrepancy;

  static RunShape batch(int spp, uint64_t seed = 0);
  static RunShape progressive(int roundSpp, uint64_t seed = 0, int maxSpp = 0);
  // Empty when valid, else a message naming the offending setting.
  std::string validate() const;
};

}  // namespace penumbra
