// Small pieces the progressive methods (bp/, ld.cpp, allocation.cpp and the baselines) share:
// wall-clock timing, the grain of their pixel loops and their ray
// counters. Internal to engine/.
#pragma once

#include "core/image.h"
#include "methods/progressive.h"
#include "trace/accel.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace penumbra::method {

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Grain of the parallel loops over pixels: large enough to amortise a sampler's set-up.
constexpr size_t kPixelGrain = 64;

// Counted by the worker threads of a round.
struct Counters {
  std::atomic<uint64_t> rays{0}, nonFinite{0}, rejected{0};
};

// The start of every method's inspect(): valid with the pixel, round and method set, or
// invalid (nothing else set) outside the image or before the first round.
inline PixelInspection startInspection(int x, int y, int width, int height, int rounds,
                                       const std::string& method) {
  PixelInspection in;
  if (x < 0 || y < 0 || x >= width || y >= height || rounds == 0) return in;
  in.valid = true;
  in.x = x;
  in.y = y;
  in.round = rounds;
  in.method = method;
  return in;
}

// What one chunk of a parallel tracing loop holds: flush-to-zero set on its thread, its own
// sampler and its counts, which are added to the method's totals when the chunk ends.
class TraceChunk {
 public:
  TraceChunk(Counters& totals, SamplerKind kind, uint64_t seed, uint32_t setSize,
             BlockOrder order = BlockOrder::Nested)
      : sampler((enableFlushToZero(), kind), seed, setSize, order), totals_(totals) {}
  ~TraceChunk() {
    totals_.rays += counters.rays;
    totals_.nonFinite += nonFinite;
  }
  TraceChunk(const TraceChunk&) = delete;
  TraceChunk& operator=(const TraceChunk&) = delete;

  PixelSampler sampler;
  PathCounters counters;
  uint64_t nonFinite = 0;

 private:
  Counters& totals_;
};

}  // namespace penumbra::method
