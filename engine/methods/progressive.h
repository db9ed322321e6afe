// Progressive rendering: a method runs in rounds (round 0 is the coarse pass) and, after
// each round, can publish a Snapshot: the current image, raw and reconstructed, plus the
// debug maps that explain its sampling decisions. RenderSession (session.h) drives a
// method on a worker thread; `penumbra render` runs the same rounds in the foreground.
#pragma once

#include "core/image.h"

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
  // How the maps are labelled: the bias map's name and range (0: up to its 99th
  // percentile, for criteria without a fixed scale) and, where the method has its own,
  // the filter scales' labels (else the caller's alphas label them).
  std::string biasLabel = "bias";
  float biasRange = 1.0f;
  std::vector<std::string> filterScaleLabels;
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

// Why one pixel got its samples: what the pixel inspector shows. Positions are offsets
// inside the pixel in [0,1)^2 (x right, y down); values are tone-mapped luminances v.
struct InspectedSample {
  float ox = 0, oy = 0;
  float value = 0;
  vec3 radiance{0.0f};  // linear
  int slice = 0;
};
struct InspectedCandidate {
  float ox = 0, oy = 0;
  float value = 0;        // traced (or, in predicted mode, predicted) v
  float score = 0;        // eq. 16
  int slice = 0;          // the slice it was drawn for
  int mirroredFrom = -1;  // slice B when warped from it, else -1
  bool kept = false;
};
struct InspectedSlice {
  uint32_t count = 0;
  float meanValue = 0;
  float fDivergence = 0;  // eq. 15
};
struct PixelInspection {
  bool valid = false;
  int x = -1, y = -1;
  int round = 0;  // rounds completed when it was taken
  std::string method;
  vec3 estimate{0.0f};                // the pixel's raw estimate, linear
  vec3 meanMapped{0.0f};              // I (eq. 12), tone-mapped
  vec3 prediction{0.0f};              // I', tone-mapped (BP)
  float bias = 0, networkError = 0;   // BP
  float psi = 0, errorThreshold = 0;  // the thresholds bias and er were compared with
  uint32_t kept = 0, traced = 0;
  uint32_t addedLastRound = 0;  // kept samples the last round added
  int rank = -1;                // place in the last round's ranking, from 0; -1: none
  size_t rankedPixels = 0;      // how many pixels that ranking held
  int slicesPerSide = 1;
  int sliceB = -1, sliceC = -1;
  bool warped = false;
  float contrast = 0;  // eq. 14 of the chosen pair
  std::vector<InspectedSlice> slices;
  std::vector<InspectedSample> samples;        // the stored samples (at most the reservoir)
  std::vector<InspectedCandidate> candidates;  // last round's, for this pixel
  std::string reason;                          // one line: why the pixel was (or was not) sampled
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
  // `cancel`, when set while it works, cuts the reconstruction short: the caller then
  // discards the snapshot.
  virtual std::shared_ptr<Snapshot> snapshot(bool reconstructImage = true,
                                             const std::atomic<bool>* cancel = nullptr) = 0;
  // Bytes held for per-pixel state (samples, networks, accumulators).
  virtual size_t memoryBytes() const = 0;
  // The pixel whose candidates the next rounds record for inspect(); -1, -1 for none.
  virtual void setInspectedPixel(int x, int y) {}
  // The state of pixel (x, y) after the last completed round; invalid outside the image.
  virtual PixelInspection inspect(int x, int y) const = 0;
};

}  // namespace penumbra
