// What BP's two algorithms share (the paper's, paper.h, and the consistent one, consistent.h):
// the per-pixel networks (the paper's Table 1 and ALGORITHM.md's resolutions), their schedule
// and sub-pixel slices, and the shared parameters' table, which each algorithm's own table
// includes.
#pragma once

#include "methods/bp/network.h"
#include "methods/params.h"
#include "methods/run_shape.h"

#include <cstdint>
#include <string>

namespace penumbra {

enum class TargetMode { PerSample, PixelMean };  // §4.3 [A8]

struct BpCommonConfig {
  int coarseSpp = 0;  // N0; 0 = automatic (each algorithm's effectiveCoarseSpp)
  int maxRounds = 8;  // adaptive rounds of the batch schedule
  NetworkConfig network;
  TargetMode targets = TargetMode::PerSample;
  int predictionDraws = 8;  // K lens/time draws averaged for I' [A12]
  float biasEpsilon = 0.02f;
  int slicesPerSide = 2;  // S
  int reservoir = 64;     // samples kept per pixel for training (and the paper's eq. 16)
  bool reconstruct = true;

  // What the table's ranges cannot say, for a run of this shape and this coarse pass: empty when
  // valid, else a message naming the flags. `stores`: the reservoirs are used (they must hold
  // the coarse pass).
  std::string check(const RunShape& shape, int coarseSpp, bool stores) const;
};

// The shared parameters, for each algorithm's table.
const ParamTable<BpCommonConfig>& bpCommonParams();

}  // namespace penumbra
