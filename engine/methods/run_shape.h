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
  // Stopping rules, 0 = none. A run with a time limit stops after the round in which the
  // method's wall time reaches it (the one kind of run that need not be deterministic). With a
  // noise threshold, a method that estimates its error gives no more samples to a pixel whose
  // estimated relMSE (of the image the user gets: filtered, for a method that filters) is
  // below it, and the run stops once the image's mean estimated relMSE is below it.
  double timeLimit = 0;
  float noiseThreshold = 0;

  static RunShape batch(int spp, uint64_t seed = 0);
  static RunShape progressive(int roundSpp, uint64_t seed = 0, int maxSpp = 0);
  // Empty when valid, else a message naming the offending setting.
  std::string validate() const;
  bool hasStoppingRule() const { return timeLimit > 0 || noiseThreshold > 0; }
};

}  // namespace penumbra
