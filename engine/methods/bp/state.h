// The BP method's state, which its phases (pixel_store, trainer, error_estimate, candidates)
// read and write and method.cpp drives round by round. Internal to methods/bp.
#pragma once

#include "core/clock.h"
#include "methods/bp/config.h"
#include "methods/bp/network.h"
#include "methods/bp/pixel_store.h"
#include "methods/progressive.h"
#include "methods/run_shape.h"
#include "methods/schedule.h"
#include "methods/trace_chunk.h"
#include "trace/integrator.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace penumbra::bp {

struct BpState {
  BpState(const PreparedScene& scene, const RunShape& runShape, const BpConfig& bpConfig);

  const PreparedScene& prepared;
  const RunShape shape;
  const BpConfig config;
  const int width, height;
  const size_t pixelCount;
  const int slicesPerPixel;
  const int coarseSpp;
  ToneMap tone;  // from the coarse pass

  PixelStore store;
  std::vector<PixelNet> nets;
  std::vector<uint8_t> selected;    // 1 where the last round added samples
  std::vector<uint32_t> lastOrder;  // the last round's ranking
  std::atomic<int64_t> inspected{-1};
  std::vector<InspectedCandidate> inspectedCandidates;

  const RoundSchedule schedule;

  int rounds = 0;
  int adaptiveRounds = 0;
  bool stalled = false;  // a round found no pixel to sample
  uint64_t spent = 0, kept = 0, traced = 0;
  uint64_t trainingFlops = 0;
  double trainingSeconds = 0;
  method::Counters counters;
  PhaseTimes times;
  Clock::time_point start;

  const PixelState& pixel(size_t p) const { return store.pixels[p]; }
  PixelState& pixel(size_t p) { return store.pixels[p]; }
  // The counts and times every BP snapshot reports (traced samples, rays, dropped samples,
  // phase times, training work, wall time).
  void reportCounts(Snapshot& snap) const {
    snap.tracedSamples = traced;
    snap.rays = counters.rays;
    snap.nonFiniteSamples = counters.nonFinite;
    snap.rejectedSamples = counters.rejected;
    snap.times = times;
    snap.trainingFlops = trainingFlops;
    snap.trainingKernelSeconds = trainingSeconds;
    snap.seconds = secondsSince(start);
  }
  bool cancelled(const std::atomic<bool>* cancel) const {
    return cancel && cancel->load(std::memory_order_relaxed);
  }
};

}  // namespace penumbra::bp
