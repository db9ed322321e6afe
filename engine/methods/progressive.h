// Progressive rendering: a method runs in rounds (round 0 is the coarse pass) and, after
// each round, can publish a Snapshot: the current image, raw and reconstructed, plus the
// debug maps that explain its sampling decisions. RenderSession (session.h) drives a
// method on a worker thread; `penumbra render` and `compare` run the same rounds in the
// foreground. A method is made from its descriptor (method.h) by the factory (factory.h).
#pragma once

#include "core/clock.h"
#include "core/image.h"
#include "methods/run_shape.h"
#include "methods/snapshot.h"

#include <glm/vec2.hpp>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

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
// A value a method explains a pixel with: one line of the inspector, formatted by the method.
struct InspectedValue {
  MapId map;                  // the map the value is this pixel's entry of, if any
  std::string label;          // what it is: "bias", "er", "mean I", the score's name
  std::vector<float> values;  // the number(s): one, or an RGB triple
  std::string line;           // what the inspector shows, e.g. "bias 0.412 > psi 0.050"
};
// The samples inside the pixel, for a method that places them in slices (BP): what the
// inspector draws of the pixel.
struct SubpixelInspection {
  int slicesPerSide = 1;
  int sliceB = -1, sliceC = -1;
  bool warped = false;
  float contrast = 0;  // eq. 14 of the chosen pair
  std::vector<InspectedSlice> slices;
  std::vector<InspectedSample> samples;        // the stored samples (at most the reservoir)
  std::vector<InspectedCandidate> candidates;  // last round's, for this pixel
};
// A pixel's network along the input that matters most (BP with --networks 1): its mean over
// the other inputs against the samples, all demodulated luminances.
struct InspectedFit {
  std::string input;               // "light s", "time", "lens u", ...
  float lo = 0, hi = 0;            // the input's range over the samples
  std::vector<float> curve;        // the network, evenly spaced from lo to hi
  std::vector<glm::vec2> samples;  // (input, value) of the neighbours' samples it was fitted on
  std::vector<glm::vec2> own;      // the pixel's own kept samples, which it never saw
};
struct PixelInspection {
  bool valid = false;
  int x = -1, y = -1;
  int round = 0;  // rounds completed when it was taken
  std::string method;
  vec3 estimate{0.0f};  // the pixel's raw estimate, linear
  uint32_t kept = 0, traced = 0;
  uint32_t addedLastRound = 0;         // kept samples the last round added
  int rank = -1;                       // place in the last round's ranking, from 0; -1: none
  size_t rankedPixels = 0;             // how many pixels that ranking held
  std::vector<InspectedValue> values;  // the method's own, in the order it shows them
  std::optional<SubpixelInspection> subpixel;  // BP: slices, samples and candidates
  std::optional<InspectedFit> fit;             // BP with --networks 1: the pixel's network
  std::string reason;                          // one line: why the pixel was (or was not) sampled

  // The first value of map `id` (or labelled `label`), or nullptr.
  const InspectedValue* value(MapId id) const {
    for (const InspectedValue& v : values)
      if (v.map == id && !id.none()) return &v;
    return nullptr;
  }
  const InspectedValue* value(std::string_view label) const {
    for (const InspectedValue& v : values)
      if (v.label == label) return &v;
    return nullptr;
  }
  InspectedValue& addValue(std::string label, std::vector<float> numbers, std::string line,
                           MapId map = {}) {
    return values.emplace_back(
        InspectedValue{map, std::move(label), std::move(numbers), std::move(line)});
  }
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

class ProgressiveMethod {
 public:
  // Starts the method's clock: its wall time, which the time limit and the snapshots' seconds
  // count from.
  explicit ProgressiveMethod(const RunShape& shape) : shape_(shape), start_(Clock::now()) {}
  virtual ~ProgressiveMethod() = default;
  // Runs the next round (nothing once done()). `cancel` is polled at safe points (between
  // pixels); after a cancelled round the method's state is unusable and the session discards it.
  virtual void runRound(const std::atomic<bool>* cancel) = 0;
  // Whether the run is over: the method's budget is spent, or a stopping rule of the run's shape
  // ends it (RunShape::timeLimit, noiseThreshold). The one place a run's end is decided: the
  // methods, the session, `render` and `compare` all ask it.
  bool done() const {
    if (budgetSpent()) return true;
    if (shape_.timeLimit > 0 && seconds() >= shape_.timeLimit) return true;
    if (shape_.noiseThreshold > 0 && roundsDone() > 0) {
      const double e = estimatedError();
      return e == e && e < shape_.noiseThreshold;
    }
    return false;
  }
  virtual int roundsDone() const = 0;
  // The state after the last completed round. The reconstruction is computed on demand
  // (its time counts in PhaseTimes::reconstruct); with reconstructImage false the
  // snapshot's reconstructed image is left empty, for cheap per-round statistics.
  // `cancel`, when set while it works, cuts the reconstruction short: the caller then
  // discards the snapshot.
  virtual std::shared_ptr<Snapshot> snapshot(bool reconstructImage = true,
                                             const std::atomic<bool>* cancel = nullptr) = 0;
  // Per channel, the variance of each pixel's raw estimate (before any filter), for methods
  // whose film knows it; empty otherwise.
  virtual Image rawVarianceOfMean() const { return {}; }
  // The mean over pixels of the estimated relMSE of the image the user gets (filtered, for a
  // method that filters), for the noise threshold; NaN for a method without an estimate.
  virtual double estimatedError() const { return NAN; }
  // The share of its budget spent, 0..1 (a progress bar's); NaN without a budget (open-ended,
  // no target spp).
  virtual double budgetShare() const { return NAN; }
  // Wall seconds since the method was made.
  double seconds() const { return secondsSince(start_); }
  const RunShape& shape() const { return shape_; }
  // Bytes held for per-pixel state (samples, networks, accumulators).
  virtual size_t memoryBytes() const = 0;
  // The pixel whose candidates the next rounds record for inspect(); -1, -1 for none.
  virtual void setInspectedPixel(int x, int y) {}
  // Whether the next snapshots carry the debug maps (Snapshot::withMaps; true by default).
  // A viewer that shows no overlay turns them off: a 1280x720 picture's maps cost about a
  // tenth of a second on two cores, at every picture. The images are the same either way.
  void setMapsWanted(bool wanted) { mapsWanted_ = wanted; }
  bool mapsWanted() const { return mapsWanted_; }
  // The state of pixel (x, y) after the last completed round; invalid outside the image.
  virtual PixelInspection inspect(int x, int y) const = 0;

 protected:
  // The budget is spent (never, open-ended without a target spp).
  virtual bool budgetSpent() const = 0;
  const RunShape shape_;

 private:
  Clock::time_point start_;
  bool mapsWanted_ = true;
};

}  // namespace penumbra
