// How every method spreads its budget over rounds (ALGORITHM.md §8, §10.2, §15): an
// initial pass of N0 samples per pixel, then, in a batch run, each adaptive round spends an
// equal share of what is left over the rounds left, so that exactly spp x #pixels samples
// are spent; open-ended, each round spends roundSpp x #pixels until the target spp is reached.
// Budgets count samples over the whole image (or per pixel, with pixelCount 1).
#pragma once

#include "methods/run_shape.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace penumbra {

class RoundSchedule {
 public:
  // `initialSpp`: N0 of the initial pass; `rounds`: the adaptive rounds of a batch run.
  RoundSchedule(const RunShape& shape, size_t pixelCount, int initialSpp, int rounds);

  uint64_t initialBudget() const { return uint64_t(initialSpp_) * pixelCount_; }
  // Batch: spp x #pixels; open-ended: the target spp x #pixels (0 = no end).
  uint64_t totalBudget() const;
  // What adaptive round `round` (from 0) may spend when `spent` samples are spent.
  uint64_t roundBudget(uint64_t spent, int round) const;
  // The same, but open-ended a round adds at least an eighth of what is spent (still capped
  // by the target spp): for the adaptive methods, whose per-round ranking and statistics then cost
  // a bounded share of the time however long the run (the session publishes a few snapshots a
  // second whatever the round length). Batch runs are as roundBudget.
  uint64_t growingRoundBudget(uint64_t spent, int round) const;
  // The share of the whole budget `spent` is, 0..1; NaN without a budget (open-ended, no target).
  double share(uint64_t spent) const {
    const uint64_t total = totalBudget();
    return total > 0 ? std::min(1.0, double(spent) / double(total)) : NAN;
  }
  // The whole budget is spent (never, open-ended without the target spp).
  bool finished(uint64_t spent) const;
  int initialSpp() const { return initialSpp_; }
  int rounds() const { return rounds_; }

 private:
  RunShape shape_;
  size_t pixelCount_;
  int initialSpp_, rounds_;
};

}  // namespace penumbra
