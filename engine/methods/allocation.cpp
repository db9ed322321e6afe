#include "methods/allocation.h"

#include "methods/film_reconstruction.h"

#include "core/rng.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>
#include <stdexcept>

namespace penumbra {

using namespace method;

int AllocationConfig::effectiveInitialSpp(const RunShape& shape) const {
  if (initialSpp > 0) return initialSpp;
  return shape.openEnded ? 4 : std::min(4, shape.spp);
}

int AllocationConfig::effectiveBatch(const RunShape& shape) const {
  if (batch > 0) return batch;
  return shape.openEnded ? 8 : shape.spp;
}

std::string AllocationConfig::check(const RunShape& shape) const {
  if (!shape.openEnded && initialSpp > shape.spp) return "--initial-spp cannot exceed --spp";
  return {};
}

const ParamTable<AllocationConfig>& allocationParams() {
  static const ParamTable<AllocationConfig> table = [] {
    ParamTable<AllocationConfig> t;
    t.group("Baselines: fdiv, fuzzy, gem, cycles (ALGORITHM.md section 10)")
        .integer("initial-spp", "initial spp N0",
                 "Samples per pixel of the initial pass N0 (0 = min(4, spp))",
                 [](auto& c) -> auto& { return c.initialSpp; }, 0, 1 << 20, {0, 64})
        .integer("batch", "batch per chosen pixel (0: 8)",
                 "Samples a chosen pixel gets per round (0 = spp; 8 in the viewer)",
                 [](auto& c) -> auto& { return c.batch; }, 0, 1 << 20, {0, 64})
        .integer("rounds", "rounds",
                 "Adaptive rounds that spend the rest of the budget (BP and the baselines)",
                 [](auto& c) -> auto& { return c.rounds; }, 1, 1000, {1, 32});
    return t;
  }();
  return table;
}

namespace adaptive {

void LuminanceSums::add(double luminance) {
  const double l = std::max(0.0, luminance);
  ++n;
  sum += l;
  sumSqrt += std::sqrt(l);
  sumSquares += l * l;
  if (l > 0) sumLLogL += l * std::log(l);
}

}  // namespace adaptive

// ---- The framework -----------------------------------------------------------------

AllocationMethod::AllocationMethod(const PreparedScene& prepared, const RunShape& shape,
                                   const AllocationConfig& config, std::string name)
    : ProgressiveMethod(shape),
      prepared_(prepared),
      config_(config),
      name_(std::move(name)),
      width_(prepared.scene.settings.width),
      height_(prepared.scene.settings.height),
      pixelCount_(size_t(width_) * height_),
      scores_(pixelCount_, 0.0f),
      schedule_(shape, pixelCount_, config.effectiveInitialSpp(shape), config.rounds),
      drawn_(pixelCount_, 0),
      kept_(pixelCount_, 0),
      sampleMean_(pixelCount_, vec3(0.0f)),
      sampleM2_(pixelCount_, vec3(0.0f)),
      selected_(pixelCount_, 0),
      rank_(pixelCount_, -1),
      addedLastRound_(pixelCount_, 0) {}

bool AllocationMethod::budgetSpent() const { return schedule_.finished(drawnTotal_); }

vec3 AllocationMethod::sampleVarianceOfMean(size_t p) const {
  const uint32_t n = kept_[p];
  return n > 1 ? sampleM2_[p] / (float(n - 1) * float(n)) : vec3(0.0f);
}

std::vector<float> AllocationMethod::shownRelativeError() const {
  std::vector<float> e(pixelCount_);
  for (size_t p = 0; p < pixelCount_; ++p) {
    const vec3 v = sampleVarianceOfMean(p);
    e[p] = (v.x + v.y + v.z) / 3.0f / relativeErrorRegulariser(sampleMean_[p]);
  }
  return e;
}

double AllocationMethod::estimatedError() const {
  if (!shownError_.empty()) return meanOf(shownError_);
  return meanOf(shownRelativeError());
}

Image AllocationMethod::rawVarianceOfMean() const {
  Image out(width_, height_);
  for (size_t p = 0; p < pixelCount_; ++p) out.pixels[p] = sampleVarianceOfMean(p);
  return out;
}

void AllocationMethod::placeSamples(uint32_t pixel, int count, std::vector<uint32_t>& landing) {
  landing.assign(size_t(count), pixel);
}

void AllocationMethod::runRound(const std::atomic<bool>* cancel) {
  if (done()) return;
  auto start = Clock::now();
  std::vector<PlannedSample> plan;
  std::fill(selected_.begin(), selected_.end(), 0);
  std::fill(addedLastRound_.begin(), addedLastRound_.end(), 0);
  std::fill(rank_.begin(), rank_.end(), -1);
  rankedLastRound_ = 0;
  if (rounds_ == 0) {
    const uint32_t n0 = uint32_t(schedule_.initialSpp());
    plan.reserve(pixelCount_ * n0);
    for (uint32_t p = 0; p < pixelCount_; ++p)
      for (uint32_t i = 0; i < n0; ++i) plan.push_back({p, drawn_[p]++});
  } else {
    // Rank by score, highest first; ties (and NaN, treated as 0) by pixel index.
    std::vector<uint32_t> order(pixelCount_);
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](uint32_t p) {
      const float s = scores_[p];
      return std::isnan(s) ? 0.0f : s;
    };
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      const float ka = key(a), kb = key(b);
      return ka != kb ? ka > kb : a < b;
    });
    for (size_t r = 0; r < order.size(); ++r) rank_[order[r]] = int32_t(r);
    if (shape_.noiseThreshold > 0) {
      // Pixels whose shown value is already below the threshold get nothing.
      std::erase_if(order, [&](uint32_t p) { return shape_.converged(shownError_[p]); });
      for (int32_t& r : rank_) r = -1;
      for (size_t r = 0; r < order.size(); ++r) rank_[order[r]] = int32_t(r);
    }
    uint64_t budget = schedule_.growingRoundBudget(drawnTotal_, rounds_ - 1);
    const int batch = config_.effectiveBatch(shape_);
    plan.reserve(budget);
    std::vector<uint32_t> landing;
    size_t chosen = 0;
    while (budget > 0 && !order.empty()) {  // several passes only past one batch each
      const uint32_t p = order[chosen % order.size()];
      const int count = int(std::min<uint64_t>(uint64_t(batch), budget));
      placeSamples(p, count, landing);
      if (shape_.noiseThreshold > 0)  // GEM's spread samples stay out of converged pixels too
        for (uint32_t& l : landing)
          if (shape_.converged(shownError_[l])) l = p;
      for (uint32_t l : landing) plan.push_back({l, drawn_[l]++});
      budget -= uint64_t(count);
      ++chosen;
    }
    rankedLastRound_ = std::min(chosen, order.size());
    times_.select += secondsSince(start);
  }
  trace(plan, cancel);
  if (cancel && cancel->load()) return;
  drawnTotal_ += plan.size();
  ++rounds_;
  start = Clock::now();
  computeScores(scores_);
  if (shape_.noiseThreshold > 0) shownError_ = shownRelativeError();
  times_.select += secondsSince(start);
}

void AllocationMethod::trace(std::vector<PlannedSample>& plan, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  // Group by landing pixel; within a pixel the indices stay in increasing order.
  std::stable_sort(plan.begin(), plan.end(), [](const PlannedSample& a, const PlannedSample& b) {
    return a.pixel < b.pixel;
  });
  std::vector<size_t> groups;
  for (size_t i = 0; i < plan.size(); ++i)
    if (i == 0 || plan[i].pixel != plan[i - 1].pixel) groups.push_back(i);
  groups.push_back(plan.size());
  const uint32_t setSize = shape_.openEnded ? 64u : uint32_t(std::max(1, shape_.spp));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, groups.size() - 1, kPixelGrain / 4),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (cancel && cancel->load(std::memory_order_relaxed)) return;
                      TraceChunk chunk(counters_, shape_.sampler, shape_.seed, setSize);
                      PixelSampler& sampler = chunk.sampler;
                      for (size_t g = range.begin(); g < range.end(); ++g) {
                        const uint32_t p = plan[groups[g]].pixel;
                        const int px = int(p % width_), py = int(p / width_);
                        selected_[p] = 1;
                        for (size_t i = groups[g]; i < groups[g + 1]; ++i) {
                          sampler.startSample(px, py, plan[i].index);
                          const vec3 L = traceRadiance(
                              prepared_,
                              sampler.cameraSample(prepared_.usesLens, prepared_.usesTime), sampler,
                              chunk.counters);
                          ++addedLastRound_[p];
                          if (!isFinite(L)) {
                            ++chunk.nonFinite;
                            continue;
                          }
                          ++kept_[p];
                          const vec3 d = L - sampleMean_[p];
                          sampleMean_[p] += d / float(kept_[p]);
                          sampleM2_[p] += d * (L - sampleMean_[p]);
                          addSample(p, plan[i].index, L);
                        }
                      }
                    });
  times_.trace += secondsSince(start);
}

size_t AllocationMethod::memoryBytes() const {
  return statisticsBytes() + scores_.capacity() * sizeof(float) +
         (sampleMean_.capacity() + sampleM2_.capacity()) * sizeof(vec3) +
         shownError_.capacity() * sizeof(float) +
         (drawn_.capacity() + kept_.capacity() + addedLastRound_.capacity()) * sizeof(uint32_t) +
         rank_.capacity() * sizeof(int32_t) + selected_.capacity();
}

void AllocationMethod::finishSnapshot(Snapshot& snap, bool, const std::atomic<bool>*) {
  snap.reconstructed = snap.raw;
}

std::shared_ptr<Snapshot> AllocationMethod::snapshot(bool reconstructImage,
                                                     const std::atomic<bool>* cancel) {
  auto snap = std::make_shared<Snapshot>();
  snap->withMaps = mapsWanted();
  snap->method = name_;
  snap->round = rounds_;
  snap->final = done();
  snap->width = width_;
  snap->height = height_;
  snap->raw = Image(width_, height_);
  for (size_t p = 0; p < pixelCount_; ++p) snap->raw.pixels[p] = pixelMean(p);
  // A score has no fixed scale: its colour range ends at its 99th percentile.
  if (snap->withMaps)
    snap->addMap(maps::ErrorEstimate, scoreName(), scores_,
                 MapLegend::sequential(0.0f, percentileOf(scores_, 0.99f)));
  addSelectedMap(*snap, selected_);
  addSampleCountMaps(*snap, kept_, drawn_);
  for (uint32_t k : kept_) snap->keptSamples += k;
  snap->tracedSamples = drawnTotal_;
  snap->rays = counters_.rays;
  snap->nonFiniteSamples = counters_.nonFinite;
  const auto start = Clock::now();
  finishSnapshot(*snap, reconstructImage, cancel);
  times_.reconstruct += secondsSince(start);
  snap->times = times_;
  snap->seconds = seconds();
  return snap;
}

PixelInspection AllocationMethod::inspect(int x, int y) const {
  PixelInspection in = startInspection(x, y, width_, height_, rounds_, name_);
  if (!in.valid) return in;
  const size_t p = size_t(y) * width_ + x;
  in.estimate = pixelMean(p);
  in.kept = kept_[p];
  in.traced = drawn_[p];
  in.addedLastRound = addedLastRound_[p];
  in.rank = rank_[p];
  in.rankedPixels = rankedLastRound_;
  char line[200];
  std::snprintf(line, sizeof line, "%s %.4g", scoreName().c_str(), double(scores_[p]));
  in.addValue(scoreName(), {scores_[p]}, line, maps::ErrorEstimate);
  if (in.rank >= 0) {
    std::snprintf(line, sizeof line, "rank %d; the last round sampled the top %zu", in.rank + 1,
                  in.rankedPixels);
    in.addValue("rank", {float(in.rank + 1), float(in.rankedPixels)}, line);
  }
  addInspectedValues(p, in);
  if (rounds_ == 1) {
    std::snprintf(line, sizeof line, "initial pass: %d samples in every pixel",
                  schedule_.initialSpp());
  } else if (rank_[p] >= 0 && size_t(rank_[p]) < rankedLastRound_) {
    std::snprintf(line, sizeof line, "%s %.3g ranked %d of %zu: among the %zu pixels sampled",
                  scoreName().c_str(), double(scores_[p]), rank_[p] + 1, pixelCount_,
                  rankedLastRound_);
  } else if (addedLastRound_[p] > 0) {
    std::snprintf(line, sizeof line, "got %u samples placed by a neighbour's filter",
                  addedLastRound_[p]);
  } else {
    std::snprintf(line, sizeof line, "%s %.3g ranked %d of %zu: below the cut of %zu pixels",
                  scoreName().c_str(), double(scores_[p]), rank_[p] + 1, pixelCount_,
                  rankedLastRound_);
  }
  in.reason = line;
  return in;
}

void AllocationMethod::forEachPixel(size_t count, const std::function<void(size_t)>& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kPixelGrain * 4),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t p = r.begin(); p < r.end(); ++p) body(p);
                    });
}

}  // namespace penumbra
