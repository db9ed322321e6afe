#include "methods/schedule.h"

#include <algorithm>

namespace penumbra {

RoundSchedule::RoundSchedule(const RunShape& shape, size_t pixelCount, int initialSpp, int rounds)
    : shape_(shape), pixelCount_(pixelCount), initialSpp_(initialSpp), rounds_(rounds) {}

uint64_t RoundSchedule::totalBudget() const { return uint64_t(shape_.spp) * pixelCount_; }

uint64_t RoundSchedule::roundBudget(uint64_t spent, int round) const {
  const uint64_t total = totalBudget();
  const uint64_t remaining = total > spent ? total - spent : 0;
  if (shape_.openEnded) {
    const uint64_t budget = uint64_t(shape_.roundSpp) * pixelCount_;
    return shape_.spp > 0 ? std::min(budget, remaining) : budget;
  }
  const int roundsLeft = std::max(1, rounds_ - round);
  return (remaining + roundsLeft - 1) / roundsLeft;
}

uint64_t RoundSchedule::growingRoundBudget(uint64_t spent, int round) const {
  const uint64_t budget = roundBudget(spent, round);
  if (!shape_.openEnded) return budget;
  const uint64_t grown = std::max(budget, spent / 8);
  const uint64_t total = totalBudget();
  return total > 0 ? std::min(grown, total - std::min(spent, total)) : grown;
}

bool RoundSchedule::finished(uint64_t spent) const {
  if (shape_.openEnded && shape_.spp == 0) return false;
  return spent >= totalBudget();
}

}  // namespace penumbra
