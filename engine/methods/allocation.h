// The shared allocation framework of the adaptive baselines (ALGORITHM.md §10.2-§10.5,
// §11): a low-discrepancy initial pass of N0 = min(4, spp) samples per pixel, then rounds
// that each spend an equal share of the remaining budget on the pixels a criterion scores
// highest, a batch of `batch` samples (spp by default) per chosen pixel. With spp = N
// exactly N x #pixels samples are drawn. A criterion supplies the per-pixel statistics,
// the score and (GEM) its own sample placement and reconstruction; everything else (the
// schedule, the ranking, tracing, determinism, snapshots and inspection) is here.
//
// Sample placement: a pixel's k-th sample is sample k of its scrambled (0,2) sequence
// (the offset continues the pixel's LD sequence, as §10.2 asks), whichever round drew it.
//
// Determinism: the round's samples are planned serially in ranking order (ties broken by
// pixel index), then traced and accumulated pixel by pixel in sample order, so the image
// after each round is the same whatever the number of threads.
#pragma once

#include "core/clock.h"
#include "methods/method.h"
#include "methods/params.h"
#include "methods/progressive.h"
#include "methods/run_shape.h"
#include "methods/schedule.h"
#include "methods/trace_chunk.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace penumbra {

// The schedule every baseline shares; the run's shape is methods/run_shape.h.
struct AllocationConfig {
  int initialSpp = 0;  // N0; 0 = min(4, spp)
  int rounds = 8;      // adaptive rounds of the batch schedule
  int batch = 0;       // samples a chosen pixel gets per round; 0 = spp (8 open-ended)

  int effectiveInitialSpp(const RunShape& shape) const;
  int effectiveBatch(const RunShape& shape) const;
  // What the table's ranges cannot say: empty when valid for a run of this shape, else a
  // message naming the flags.
  std::string check(const RunShape& shape) const;
};

// The parameters every baseline shares, for its own table (params.h).
const ParamTable<AllocationConfig>& allocationParams();

// A baseline's descriptor (methods/method.h) for its AllocationMethod `Method`: the framework's
// maps (with `extraMaps`), its abilities (it keeps each pixel's variance, adapts and estimates
// its error; `filters` when the criterion reconstructs) and checks, with the criterion's name,
// description and table.
template <typename Method, typename Config>
MethodDefinition<Config> allocationDefinition(std::string name, std::string description,
                                              const ParamTable<Config>& params,
                                              bool filters = false,
                                              std::vector<const MapKind*> extraMaps = {}) {
  std::vector<const MapKind*> kinds = {&maps::ErrorEstimate, &maps::Selected, &maps::SampleCount,
                                       &maps::TracedCount};
  kinds.insert(kinds.end(), extraMaps.begin(), extraMaps.end());
  MethodDefinition<Config> d;
  d.name = std::move(name);
  d.description = std::move(description);
  d.params = &params;
  d.maps = std::move(kinds);
  d.abilities = [filters](const Config&) { return MethodAbilities{true, filters, true, true}; };
  d.check = [](const Config& c, const RunShape& shape) { return c.check(shape); };
  d.make = construct<Method, Config>;
  return d;
}

namespace adaptive {

// Running sums of a pixel's sample luminances (linear, clamped at 0): enough for all
// three f-divergences against the uniform distribution without storing the samples.
struct LuminanceSums {
  uint32_t n = 0;
  double sum = 0, sumSqrt = 0, sumSquares = 0, sumLLogL = 0;
  void add(double luminance);
};

}  // namespace adaptive

// ---- The framework, for the criteria (fdiv/, fuzzy/, gem/, cycles/) -----------------

struct PlannedSample {
  uint32_t pixel = 0;  // where it lands
  uint32_t index = 0;  // its index in that pixel's sample sequence
};

class AllocationMethod : public ProgressiveMethod {
 public:
  AllocationMethod(const PreparedScene& prepared, const RunShape& shape,
                   const AllocationConfig& config, std::string name);

  void runRound(const std::atomic<bool>* cancel) override;
  int roundsDone() const override { return rounds_; }
  size_t memoryBytes() const override;
  std::shared_ptr<Snapshot> snapshot(bool reconstructImage,
                                     const std::atomic<bool>* cancel) override;
  PixelInspection inspect(int x, int y) const override;
  // The noise threshold (RunShape::noiseThreshold) tests the shown image's estimated relMSE:
  // the mean of shownRelativeError().
  double estimatedError() const override;
  double budgetShare() const override { return schedule_.share(drawnTotal_); }
  Image rawVarianceOfMean() const override;
  // Per pixel, the estimated relMSE of the image the method shows; the default is the box
  // mean's (its variance of the mean over the mean's luminance squared + 0.01). A pixel
  // below the noise threshold gets no more samples.
  virtual std::vector<float> shownRelativeError() const;

 protected:
  bool budgetSpent() const override;
  // Adds a finite sample to the pixel's statistics. Called from worker threads, but for
  // one pixel by one thread at a time, in sample order.
  virtual void addSample(size_t pixel, uint32_t index, vec3 radiance) = 0;
  // Recomputes every pixel's score (higher = sample first) after a round.
  virtual void computeScores(std::vector<float>& scores) = 0;
  // Where the `count` samples a chosen pixel gets this round land; the default keeps them
  // in the pixel. Called serially, in ranking order.
  virtual void placeSamples(uint32_t pixel, int count, std::vector<uint32_t>& landing);
  // The per-pixel mean (linear RGB) the statistics hold.
  virtual vec3 pixelMean(size_t pixel) const = 0;
  // The reconstructed image and the method's maps; the default is the box mean.
  virtual void finishSnapshot(Snapshot& snap, bool reconstructImage,
                              const std::atomic<bool>* cancel);
  // The criterion's own values for the pixel inspector, after the score and the rank.
  virtual void addInspectedValues(size_t pixel, PixelInspection& in) const {}
  virtual size_t statisticsBytes() const = 0;
  virtual std::string scoreName() const { return "score"; }
  // The framework's own per-pixel statistics of every finite sample (Welford, in order).
  vec3 sampleMean(size_t p) const { return sampleMean_[p]; }
  vec3 sampleVarianceOfMean(size_t p) const;
  // Runs body(p) for every pixel p in [0, count), in parallel.
  static void forEachPixel(size_t count, const std::function<void(size_t)>& body);

  const PreparedScene& prepared_;
  AllocationConfig config_;
  std::string name_;
  int width_, height_;
  size_t pixelCount_;
  int rounds_ = 0;
  std::vector<float> scores_;
  uint64_t round() const { return uint64_t(rounds_); }

 private:
  void trace(std::vector<PlannedSample>& plan, const std::atomic<bool>* cancel);

  RoundSchedule schedule_;
  std::vector<uint32_t> drawn_;  // samples drawn per pixel (the next sequence index)
  std::vector<uint32_t> kept_;   // finite samples per pixel
  std::vector<vec3> sampleMean_, sampleM2_;
  // The last shownRelativeError(), when a noise threshold is set.
  std::vector<float> shownError_;
  std::vector<uint8_t> selected_;
  std::vector<int32_t> rank_;  // last round's place in the ranking, -1: not chosen
  std::vector<uint32_t> addedLastRound_;
  size_t rankedLastRound_ = 0;
  uint64_t drawnTotal_ = 0;
  method::Counters counters_;
  PhaseTimes times_;
};

}  // namespace penumbra
