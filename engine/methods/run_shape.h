// The shape of a run, the same for every method (ALGORITHM.md §11's fair comparison): the
// seed, the budget (a fixed number of kept samples per pixel, or open-ended rounds until
// stopped), the samples a round adds when open-ended, the sample generator, and the stopping
// rules that may end a run early (a time limit, a noise threshold). What a method does with
// its budget is its own configuration (methods/<method>/).
//
// Its settings are described once, in runShapeParams(): the commands' flags and the viewer
// panel's widgets are made from that table, each command taking the entries whose scope has
// it.
#pragma once

#include "methods/params.h"
#include "trace/sampler.h"

#include <cstdint>
#include <string>

namespace penumbra {

struct RunShape {
  uint64_t seed = 0;
  // Kept samples per pixel on average: a batch run's whole budget; open-ended, the count at
  // which the run stops (0: never).
  int spp = 16;
  bool openEnded = false;  // rounds until stopped (the viewer, equal-time runs)
  int roundSpp = 1;        // open-ended: kept samples per pixel each round adds, on average
  SamplerKind sampler = SamplerKind::LowDiscrepancy;
  // Stopping rules, 0 = none (methods/progressive.h applies them). A run with a time limit stops
  // after the round in which the method's wall time reaches it (the one kind of run that need
  // not be deterministic). With a noise threshold, a method that estimates its error gives no
  // more samples to a pixel whose estimated relMSE (of the image the user gets: filtered, for a
  // method that filters) is below it, and the run stops once the image's mean estimated relMSE
  // is below it.
  double timeLimit = 0;
  float noiseThreshold = 0;

  static RunShape batch(int spp, uint64_t seed = 0);
  // Open-ended rounds of roundSpp, stopping at spp (0: never).
  static RunShape progressive(int roundSpp, uint64_t seed = 0, int spp = 0);
  // Empty when valid, else a message naming the offending flag: runShapeParams()'s ranges, then
  // what they cannot say (a batch run needs at least one sample).
  std::string validate() const;
  bool hasStoppingRule() const { return timeLimit > 0 || noiseThreshold > 0; }
  // Whether a pixel of this estimated relMSE has converged under the noise threshold: it gets
  // no more samples.
  bool converged(float pixelError) const {
    return noiseThreshold > 0 && pixelError < noiseThreshold;
  }
};

// The commands a run-shape setting applies to (Param::scope).
enum RunCommand : unsigned {
  kRenderCommand = 1,     // render: a batch, or open-ended under a stopping rule
  kViewCommand = 2,       // view: open-ended rounds, the panel too
  kCompareCommand = 4,    // compare: seeds and equal time are its own rules
  kReferenceCommand = 8,  // reference: its own spp and seed, always low discrepancy
};

// seed, spp, round-spp, sampler, time-limit, noise-threshold.
const ParamTable<RunShape>& runShapeParams();

}  // namespace penumbra
