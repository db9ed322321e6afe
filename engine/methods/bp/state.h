// The state BP's two algorithms share, which the phases (pixel_store, trainer, error_estimate,
// candidates) read and write and paper.cpp and consistent.cpp drive round by round; the maps
// both publish. Internal to methods/bp.
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

namespace penumbra {

// BP's own maps, in the namespace of every map kind.
namespace maps {
// The network's error er per pixel (the paper's converged test).
inline constexpr MapKind NetworkError{"network_error", nullptr, "Network error er", 6};
// With --networks 1: what each pixel does for the networks (NetRecon::Role).
inline constexpr MapKind Networks{"networks", nullptr, "Networks (--networks 1)", 13};
// I', the network's prediction, tone-mapped RGB.
inline constexpr MapKind Prediction{"prediction", nullptr, "Network prediction I'", 0};
// The slices B and C the last round chose per pixel (-1: none), drawn inside the pixels.
inline constexpr MapKind SliceB{"slice_b", nullptr, "Slice B", 0, nullptr, SliceRole::First};
inline constexpr MapKind SliceC{"slice_c", nullptr, "Slice C", 0, nullptr, SliceRole::Second};
}  // namespace maps
}  // namespace penumbra

namespace penumbra::bp {

// Keeps the networks' initial weights apart from the method's other random streams.
constexpr uint64_t kNetSalt = 0x6e6574776f726bULL;

// One traced camera sample of the coarse pass, kept until the tone map is known.
struct TracedSample {
  CameraSample camera;
  vec3 radiance;
};

struct BpState {
  // `coarseSpp`: the algorithm's N0; `histogramLevels`: the slices' histogram levels m.
  // `perPixelSamples`: allocate the per-pixel store (sums, slices, reservoirs) and networks;
  // without them (the consistent algorithm with its networks off, whose film holds the sums)
  // `store.pixels` and `nets` stay empty and pixel() must not be called.
  BpState(const PreparedScene& scene, const RunShape& runShape, const BpCommonConfig& bpConfig,
          int coarseSpp, int histogramLevels, bool perPixelSamples = true);

  const PreparedScene& prepared;
  const RunShape shape;
  const BpCommonConfig config;
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

  // Bytes of the per-pixel vectors held here (the store, the networks, the selection and the
  // ranking).
  size_t memoryBytes() const;
  const PixelState& pixel(size_t p) const { return store.pixels[p]; }
  PixelState& pixel(size_t p) { return store.pixels[p]; }
  // The counts, times and figures every BP snapshot reports (traced samples, rays, dropped
  // samples, phase times, the coarse pass, the training kernel's speed); `seconds`: the
  // method's wall time.
  void reportCounts(Snapshot& snap, double seconds) const;
  bool cancelled(const std::atomic<bool>* cancel) const {
    return cancel && cancel->load(std::memory_order_relaxed);
  }
};

}  // namespace penumbra::bp
