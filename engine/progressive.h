// Progressive rendering: a method runs in rounds (round 0 is the coarse pass) and, after
// each round, can publish a Snapshot: the current image, raw and reconstructed, plus the
// debug maps that explain its sampling decisions. RenderSession (session.h) drives a
// method on a worker thread; `penumbra render` runs the same rounds in the foreground.
#pragma once

#include "engine/image.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

// Wall time per phase, summed over the rounds so far (seconds).
struct PhaseTimes {
  double trace = 0;        // path tracing, including candidate samples
  double train = 0;        // network (re)training and the bias estimate
  double select = 0;       // ranking pixels, slice choice, candidate scoring
  double reconstruct = 0;  // pixel estimates and the filter
  double total() const { return trace + train + select + reconstruct; }
};

struct Snapshot {
  int round = 0;  // rounds completed; 1 after the coarse pass
  bool final = false;
  int width = 0, height = 0;
  Image raw;            // per-pixel estimate, linear RGB
  Image reconstructed;  // after the method's filter (equals raw without one)

  // Debug maps, one value per pixel (empty where a method has none).
  std::vector<float> bias;             // error estimate that drives sampling
  std::vector<float> networkError;     // er of the pixel's network
  Image prediction;                    // I', tone-mapped RGB
  std::vector<uint8_t> selected;       // 1 where the last round added samples
  std::vector<int8_t> sliceB, sliceC;  // slices chosen in the last round, -1 for none
  std::vector<uint32_t> keptCount;     // kept samples per pixel
  std::vector<uint32_t> tracedCount;   // traced camera samples per pixel
  std::vector<uint8_t> alphaIndex;     // filter scale chosen per pixel
  int slicesPerSide = 0;

  uint64_t keptSamples = 0, tracedSamples = 0, rays = 0;
  uint64_t nonFiniteSamples = 0;  // NaN or infinite samples dropped
  uint64_t rejectedSamples = 0;   // traced but removed as outliers
  PhaseTimes times;
  uint64_t trainingFlops = 0;        // multiply-add flops spent in network training
  double trainingKernelSeconds = 0;  // time inside the training kernel alone
  double seconds = 0;                // wall time since the method started
  std::string method;
};

class ProgressiveMethod {
 public:
  virtual ~ProgressiveMethod() = default;
  // Runs the next round. `cancel` is polled at safe points (between pixels); after a
  // cancelled round the method's state is unusable and the session discards it.
  virtual void runRound(const std::atomic<bool>* cancel) = 0;
  virtual bool done() const = 0;  // budget spent (never true in open-ended mode)
  virtual int roundsDone() const = 0;
  // The state after the last completed round. The reconstruction is computed on demand
  // (its time counts in PhaseTimes::reconstruct); with reconstructImage false the
  // snapshot's reconstructed image is left empty, for cheap per-round statistics.
  virtual std::shared_ptr<Snapshot> snapshot(bool reconstructImage = true) = 0;
  // Bytes held for per-pixel state (samples, networks, accumulators).
  virtual size_t memoryBytes() const = 0;
};

}  // namespace penumbra
