// Wall-clock time for the phases and stopping rules of a run.
#pragma once

#include <chrono>

namespace penumbra {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace penumbra
