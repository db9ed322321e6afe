// What the progressive methods' parallel tracing loops share: the grain of their pixel loops,
// their ray counters and one chunk's sampler. Internal to engine/methods.
#pragma once

#include "trace/accel.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <atomic>
#include <cstddef>
#include <cstdint>

namespace penumbra::method {

// Grain of the parallel loops over pixels: large enough to amortise a sampler's set-up.
constexpr size_t kPixelGrain = 64;

// Counted by the worker threads of a round.
struct Counters {
  std::atomic<uint64_t> rays{0}, nonFinite{0}, rejected{0};
};

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
