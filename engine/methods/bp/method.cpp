#include "methods/bp/method.h"

#include "methods/common.h"

#include "core/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace penumbra {

namespace {

using namespace method;

// Salts that keep the random streams of different purposes apart.
constexpr uint64_t kNetSalt = 0x6e6574776f726bULL;
constexpr uint64_t kReservoirSalt = 0x7265736572766fULL;
constexpr uint64_t kPredictionSalt = 0x70726564696374ULL;

struct StoredSample {
  float dx, dy;  // centred offsets in [-0.5, 0.5)
  float u, v, t;
  vec3 radiance;  // linear
  float value;    // Y(T(L)), once the tone map is known
  uint8_t slice;
};

struct PixelState {
  uint32_t kept = 0;     // samples in the estimate
  uint32_t traced = 0;   // camera samples traced (kept, candidates, rejected, non-finite)
  uint32_t drawn = 0;    // sample indices used from the pixel's sampler stream
  glm::dvec3 sumL{0.0};  // linear radiance
  glm::dvec3 sumT{0.0};  // tone-mapped radiance, for eq. 12
  float bias = 0.0f;
  float er = 0.0f;
  vec3 prediction{0.0f};
  int8_t sliceB = -1, sliceC = -1;
  bool warped = false;
  uint8_t alpha = 0;
  uint32_t addedLastRound = 0;
  float contrast = 0.0f;
};

// One traced camera sample, for the sampling pass.
struct TracedSample {
  CameraSample camera;
  vec3 radiance;
};

float halton(uint32_t index, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  while (index > 0) {
    f /= float(base);
    r += f * float(index % base);
    index /= base;
  }
  return r;
}

class BpMethod final : public ProgressiveMethod {
 public:
  BpMethod(const PreparedScene& prepared, const BpConfig& config)
      : prepared_(prepared),
        config_(config),
        width_(prepared.scene.settings.width),
        height_(prepared.scene.settings.height),
        pixelCount_(size_t(width_) * height_),
        slicesPerPixel_(config.slicesPerSide * config.slicesPerSide),
        coarseSpp_(config.effectiveCoarseSpp()) {
    const std::string problem = config.validate();
    if (!problem.empty()) throw std::invalid_argument(problem);
    pixels_.resize(pixelCount_);
    samples_.resize(pixelCount_);
    slices_.resize(pixelCount_ * slicesPerPixel_);
    sliceSumL_.resize(pixelCount_ * slicesPerPixel_, glm::dvec3(0.0));
    nets_.resize(pixelCount_);
    selected_.assign(pixelCount_, 0);
    budget_ = config_.openEnded ? 0 : uint64_t(config_.spp) * pixelCount_;
    start_ = Clock::now();
  }

  void runRound(const std::atomic<bool>* cancel) override {
    if (done()) return;
    if (rounds_ == 0)
      coarsePass(cancel);
    else
      adaptiveRound(cancel);
    ++rounds_;
  }

  bool done() const override {
    if (rounds_ == 0) return false;
    if (config_.openEnded)
      return config_.maxSpp > 0 && spent_ >= uint64_t(config_.maxSpp) * pixelCount_;
    // Outlier rejections (predicted mode) can leave budget after maxRounds: up to as
    // many make-up rounds again, then stop.
    return spent_ >= budget_ || stalled_ || adaptiveRounds_ >= 2 * config_.maxRounds;
  }

  int roundsDone() const override { return rounds_; }

  size_t memoryBytes() const override {
    size_t bytes = pixels_.capacity() * sizeof(PixelState) +
                   samples_.capacity() * sizeof(std::vector<StoredSample>) +
                   slices_.capacity() * sizeof(SliceStats) +
                   sliceSumL_.capacity() * sizeof(glm::dvec3) +
                   nets_.capacity() * sizeof(PixelNet) + selected_.capacity();
    for (const auto& s : samples_) bytes += s.capacity() * sizeof(StoredSample);
    return bytes;
  }

  std::shared_ptr<Snapshot> snapshot(bool reconstructImage,
                                     const std::atomic<bool>* cancel) override {
    auto snap = std::make_shared<Snapshot>();
    const auto start = Clock::now();
    snap->method = "bp";
    snap->round = rounds_;
    snap->final = done();
    snap->width = width_;
    snap->height = height_;
    snap->slicesPerSide = config_.slicesPerSide;
    snap->raw = estimate();
    snap->bias.resize(pixelCount_);
    snap->networkError.resize(pixelCount_);
    snap->prediction = Image(width_, height_);
    snap->sliceB.resize(pixelCount_);
    snap->sliceC.resize(pixelCount_);
    snap->keptCount.resize(pixelCount_);
    snap->tracedCount.resize(pixelCount_);
    for (size_t p = 0; p < pixelCount_; ++p) {
      const PixelState& s = pixels_[p];
      snap->bias[p] = s.bias;
      snap->networkError[p] = s.er;
      snap->prediction.pixels[p] = s.prediction;
      snap->sliceB[p] = s.sliceB;
      snap->sliceC[p] = s.sliceC;
      snap->keptCount[p] = s.kept;
      snap->tracedCount[p] = s.traced;
    }
    snap->selected = selected_;
    if (!reconstructImage) {
      snap->alphaIndex.clear();
    } else if (config_.reconstruct && rounds_ > 0) {
      const Reconstruction r = reconstruct(snap->raw, snap->bias, tone_, config_.filter, cancel);
      snap->reconstructed = r.output;
      snap->alphaIndex = r.alphaIndex;
    } else {
      snap->reconstructed = snap->raw;
      snap->alphaIndex.assign(pixelCount_, 0);
      for (size_t p = 0; p < pixelCount_; ++p)
        snap->alphaIndex[p] = uint8_t(alphaIndexForBias(snap->bias[p], config_.filter.phi));
    }
    if (reconstructImage) times_.reconstruct += secondsSince(start);
    snap->keptSamples = kept_;
    snap->tracedSamples = traced_;
    snap->rays = counters_.rays;
    snap->nonFiniteSamples = counters_.nonFinite;
    snap->rejectedSamples = counters_.rejected;
    snap->times = times_;
    snap->trainingFlops = trainingFlops_;
    snap->trainingKernelSeconds = trainingSeconds_;
    snap->seconds = secondsSince(start_);
    return snap;
  }

  void setInspectedPixel(int x, int y) override {
    inspected_ = (x >= 0 && y >= 0 && x < width_ && y < height_) ? int64_t(y) * width_ + x : -1;
  }

  PixelInspection inspect(int x, int y) const override {
    PixelInspection in = startInspection(x, y, width_, height_, rounds_, "bp");
    if (!in.valid) return in;
    const size_t p = size_t(y) * width_ + x;
    const PixelState& s = pixels_[p];
    in.estimate = pixelEstimate(p);
    in.meanMapped = s.kept ? vec3(s.sumT / double(s.kept)) : vec3(0.0f);
    in.prediction = s.prediction;
    in.bias = s.bias;
    in.networkError = s.er;
    in.psi = config_.psi;
    in.errorThreshold = config_.network.errorThreshold;
    in.kept = s.kept;
    in.traced = s.traced;
    in.addedLastRound = s.addedLastRound;
    in.slicesPerSide = config_.slicesPerSide;
    in.sliceB = s.sliceB;
    in.sliceC = s.sliceC;
    in.warped = s.warped;
    in.contrast = s.contrast;
    for (int i = 0; i < slicesPerPixel_; ++i) {
      const SliceStats& st = slices_[p * slicesPerPixel_ + i];
      in.slices.push_back({st.count, float(st.meanV()), float(fDivergence(st))});
    }
    for (const StoredSample& st : samples_[p])
      in.samples.push_back({st.dx + 0.5f, st.dy + 0.5f, st.value, st.radiance, st.slice});
    if (int64_t(p) == inspected_) in.candidates = inspectedCandidates_;
    const auto it = std::find(lastOrder_.begin(), lastOrder_.end(), uint32_t(p));
    in.rankedPixels = lastOrder_.size();
    if (it != lastOrder_.end()) in.rank = int(it - lastOrder_.begin());
    in.reason = reasonFor(in, s);
    return in;
  }

 private:
  // One line for the inspector: the test the pixel passed or failed and what it got.
  std::string reasonFor(const PixelInspection& in, const PixelState& s) const {
    char text[256];
    const bool converged = s.er <= config_.network.errorThreshold;
    const bool difficult = !converged && s.bias > config_.psi;
    const char* cls = difficult   ? "difficult (bias > psi, er > e)"
                      : converged ? "converged (er <= e), ranked by er after the others"
                                  : "not difficult (bias <= psi), topped up by bias";
    if (rounds_ == 1) {
      std::snprintf(text, sizeof text, "coarse pass: %u samples; now %s", s.kept, cls);
    } else if (in.addedLastRound > 0) {
      std::snprintf(text, sizeof text, "%s; rank %d of %zu got %u samples last round", cls,
                    in.rank + 1, in.rankedPixels, in.addedLastRound);
    } else {
      std::snprintf(text, sizeof text, "%s; rank %d of %zu: the round's budget ran out first", cls,
                    in.rank + 1, in.rankedPixels);
    }
    return text;
  }

  // --- Samples -----------------------------------------------------------------------

  // Starts draw `index` of pixel (px, py) with its image offset placed at local position
  // (from the sampler's own offset) inside `target`, mirrored from `mirrorFrom` when >= 0.
  CameraSample drawCandidate(PixelSampler& sampler, int px, int py, uint32_t index, int target,
                             int mirrorFrom) const {
    sampler.startSample(px, py, index);
    CameraSample cs = sampler.cameraSample(prepared_.usesLens, prepared_.usesTime);
    glm::vec2 local(cs.imageX - float(px), cs.imageY - float(py));
    const int S = config_.slicesPerSide;
    if (mirrorFrom >= 0) local = mirrorIntoSlice(local, mirrorFrom, target, S);
    const glm::vec2 offset = sliceToPixel(local, target, S);
    // Offsets stay inside the pixel even where float rounding reaches 1.
    cs.imageX = float(px) + std::min(offset.x, 0x1.fffffep-1f);
    cs.imageY = float(py) + std::min(offset.y, 0x1.fffffep-1f);
    return cs;
  }

  StoredSample makeSample(const CameraSample& cs, int px, int py, vec3 radiance) const {
    StoredSample s;
    const float ox = cs.imageX - float(px), oy = cs.imageY - float(py);
    s.dx = ox - 0.5f;
    s.dy = oy - 0.5f;
    s.u = cs.lensU;
    s.v = cs.lensV;
    s.t = cs.time;
    s.radiance = radiance;
    s.value = tone_.value(radiance);
    s.slice = uint8_t(sliceOf(ox, oy, config_.slicesPerSide));
    return s;
  }

  // Adds a kept sample to the pixel's sums, slice statistics and reservoir.
  void keepSample(size_t p, const StoredSample& s) {
    PixelState& state = pixels_[p];
    ++state.kept;
    state.sumL += glm::dvec3(s.radiance);
    state.sumT += glm::dvec3(tone_.apply(s.radiance));
    slices_[p * slicesPerPixel_ + s.slice].add(s.value, config_.histogramLevels);
    sliceSumL_[p * slicesPerPixel_ + s.slice] += glm::dvec3(s.radiance);
    std::vector<StoredSample>& reservoir = samples_[p];
    const size_t limit = size_t(config_.reservoir);
    if (reservoir.size() < limit) {
      if (reservoir.size() == reservoir.capacity())
        reservoir.reserve(std::min(limit, std::max<size_t>(8, 2 * reservoir.size())));
      reservoir.push_back(s);
      return;
    }
    // Reservoir sampling (Algorithm R): the kept set is a uniform subsample of all.
    Pcg32 rng(hashValues(config_.seed, p, kReservoirSalt), state.kept);
    const uint64_t j = (uint64_t(rng.nextUint()) * state.kept) >> 32;
    if (j < limit) reservoir[j] = s;
  }

  // --- Coarse pass (§3) ----------------------------------------------------------------

  void coarsePass(const std::atomic<bool>* cancel) {
    auto start = Clock::now();
    // Trace first: the tone map that histograms and targets use comes from this pass.
    std::vector<std::vector<TracedSample>> traced(pixelCount_);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, pixelCount_, kPixelGrain),
        [&](const tbb::blocked_range<size_t>& range) {
          if (cancel && cancel->load(std::memory_order_relaxed)) return;
          TraceChunk chunk(counters_, config_.sampler, config_.seed, uint32_t(coarseSpp_));
          PixelSampler& sampler = chunk.sampler;
          for (size_t p = range.begin(); p < range.end(); ++p) {
            // Here rather than in the constructor: in parallel, and a
            // restart can cancel it.
            initNetwork(nets_[p], config_.network, hashValues(config_.seed, p, kNetSalt));
            const int px = int(p % width_), py = int(p / width_);
            traced[p].reserve(coarseSpp_);
            for (int i = 0; i < coarseSpp_; ++i) {
              sampler.startSample(px, py, uint32_t(i));
              const CameraSample cs = sampler.cameraSample(prepared_.usesLens, prepared_.usesTime);
              const vec3 L = traceRadiance(prepared_, cs, sampler, chunk.counters);
              if (isFinite(L))
                traced[p].push_back({cs, L});
              else
                ++chunk.nonFinite;
            }
            pixels_[p].traced = pixels_[p].drawn = uint32_t(coarseSpp_);
          }
        });
    if (cancel && cancel->load()) return;
    Image coarse(width_, height_);
    for (size_t p = 0; p < pixelCount_; ++p) {
      glm::dvec3 sum(0.0);
      for (const TracedSample& s : traced[p]) sum += glm::dvec3(s.radiance);
      coarse.pixels[p] = traced[p].empty() ? vec3(0.0f) : vec3(sum / double(traced[p].size()));
    }
    tone_ = toneMapFor(coarse);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount_, kPixelGrain),
                      [&](const tbb::blocked_range<size_t>& range) {
                        if (cancel && cancel->load(std::memory_order_relaxed)) return;
                        for (size_t p = range.begin(); p < range.end(); ++p) {
                          const int px = int(p % width_), py = int(p / width_);
                          for (const TracedSample& s : traced[p])
                            keepSample(p, makeSample(s.camera, px, py, s.radiance));
                          std::vector<TracedSample>().swap(traced[p]);
                        }
                      });
    spent_ = uint64_t(coarseSpp_) * pixelCount_;
    traced_ = spent_;
    kept_ = 0;
    for (const PixelState& s : pixels_) kept_ += s.kept;
    times_.trace += secondsSince(start);

    std::vector<uint32_t> all(pixelCount_);
    std::iota(all.begin(), all.end(), 0u);
    std::fill(selected_.begin(), selected_.end(), uint8_t(1));
    train(all, cancel);
  }

  // --- Adaptive rounds (§6-§8) ---------------------------------------------------------

  uint64_t roundBudget() const {
    if (config_.openEnded) {
      uint64_t b = uint64_t(config_.roundSpp) * pixelCount_;
      if (config_.maxSpp > 0) {
        const uint64_t cap = uint64_t(config_.maxSpp) * pixelCount_;
        b = std::min(b, cap > spent_ ? cap - spent_ : 0);
      }
      return b;
    }
    const uint64_t remaining = budget_ > spent_ ? budget_ - spent_ : 0;
    const int roundsLeft = std::max(1, config_.maxRounds - adaptiveRounds_);
    return (remaining + roundsLeft - 1) / roundsLeft;
  }

  // Pixels in the order they get samples: the difficult ones (bias > Psi and er > e) by
  // descending bias; then, with top-up, the other unconverged ones (er > e) by descending
  // bias, and last the converged ones (er <= e) by descending er. Ties by pixel index.
  // Converged pixels are not ranked by bias: their training stopped as soon as er fell
  // below e, so their I' can still be far from the mean (a dark, constant background
  // keeps a bias above 1) and bias no longer measures their error, while er (the energy
  // the network cannot explain) still does. [A6]
  std::vector<uint32_t> rankPixels() const {
    std::vector<uint32_t> hard, open, converged;
    for (uint32_t p = 0; p < pixelCount_; ++p) {
      const PixelState& s = pixels_[p];
      if (s.er <= config_.network.errorThreshold)
        converged.push_back(p);
      else
        (s.bias > config_.psi ? hard : open).push_back(p);
    }
    auto byBias = [&](uint32_t a, uint32_t b) {
      if (pixels_[a].bias != pixels_[b].bias) return pixels_[a].bias > pixels_[b].bias;
      return a < b;
    };
    auto byError = [&](uint32_t a, uint32_t b) {
      if (pixels_[a].er != pixels_[b].er) return pixels_[a].er > pixels_[b].er;
      return a < b;
    };
    std::sort(hard.begin(), hard.end(), byBias);
    if (config_.topUp) {
      std::sort(open.begin(), open.end(), byBias);
      std::sort(converged.begin(), converged.end(), byError);
      hard.insert(hard.end(), open.begin(), open.end());
      hard.insert(hard.end(), converged.begin(), converged.end());
    }
    return hard;
  }

  void adaptiveRound(const std::atomic<bool>* cancel) {
    auto start = Clock::now();
    const uint64_t budget = roundBudget();
    std::vector<uint32_t> order = rankPixels();
    const std::vector<uint32_t> slots =
        bp::allocateSlots(order, pixelCount_, budget, slicesPerPixel_);
    lastOrder_ = std::move(order);
    inspectedCandidates_.clear();
    std::vector<uint32_t> chosen;
    for (uint32_t p = 0; p < pixelCount_; ++p) {
      selected_[p] = slots[p] > 0;
      if (slots[p] > 0) chosen.push_back(p);
    }
    ++adaptiveRounds_;
    if (chosen.empty()) {
      stalled_ = true;
      times_.select += secondsSince(start);
      return;
    }
    // Slice choice per pixel, fixed for the round (§6.3-§6.4).
    std::vector<SliceChoice> choices(pixelCount_);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, chosen.size(), kPixelGrain),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t i = range.begin(); i < range.end(); ++i) {
            const uint32_t p = chosen[i];
            SliceChoice c = chooseSlices(
                std::span<const SliceStats>(&slices_[p * slicesPerPixel_], slicesPerPixel_),
                config_.histogramLevels);
            if (!config_.warping) c.warp = false;
            choices[p] = c;
          }
        });
    for (size_t p = 0; p < pixelCount_; ++p) {
      pixels_[p].sliceB = slots[p] ? int8_t(choices[p].b) : int8_t(-1);
      pixels_[p].sliceC = slots[p] ? int8_t(choices[p].c) : int8_t(-1);
      pixels_[p].warped = slots[p] && choices[p].warp;
      pixels_[p].contrast = slots[p] ? float(choices[p].contrast) : 0.0f;
      pixels_[p].addedLastRound = 0;
    }
    times_.select += secondsSince(start);

    start = Clock::now();
    std::atomic<uint64_t> spent{0}, tracedCount{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chosen.size(), 16),
                      [&](const tbb::blocked_range<size_t>& range) {
                        if (cancel && cancel->load(std::memory_order_relaxed)) return;
                        enableFlushToZero();
                        PixelSampler sampler(config_.sampler, config_.seed, uint32_t(coarseSpp_));
                        PathCounters counters;
                        uint64_t localSpent = 0, localTraced = 0;
                        for (size_t i = range.begin(); i < range.end(); ++i) {
                          const uint32_t p = chosen[i];
                          const uint32_t before = pixels_[p].traced;
                          const uint32_t keptBefore = pixels_[p].kept;
                          localSpent += samplePixel(p, slots[p], choices[p], sampler, counters);
                          localTraced += pixels_[p].traced - before;
                          pixels_[p].addedLastRound = pixels_[p].kept - keptBefore;
                        }
                        counters_.rays += counters.rays;
                        spent += localSpent;
                        tracedCount += localTraced;
                      });
    if (cancel && cancel->load()) return;
    spent_ += spent;
    traced_ += tracedCount;
    kept_ = 0;
    for (const PixelState& s : pixels_) kept_ += s.kept;
    times_.trace += secondsSince(start);
    train(chosen, cancel);
  }

  // Order in which a pixel's slices receive this round's samples: with warping, C's own
  // sample, then B's sample mirrored into C, then the other slices; a partial group (the
  // budget's remainder) takes a prefix. Each entry: (target slice, mirrored-from or -1).
  std::vector<std::pair<int, int>> slotOrder(const SliceChoice& choice) const {
    std::vector<std::pair<int, int>> order;
    if (choice.warp && choice.b >= 0) {
      order.push_back({choice.c, -1});
      order.push_back({choice.c, choice.b});
      for (int s = 0; s < slicesPerPixel_; ++s)
        if (s != choice.b && s != choice.c) order.push_back({s, -1});
    } else {
      for (int s = 0; s < slicesPerPixel_; ++s) order.push_back({s, -1});
    }
    return order;
  }

  // Adds `slotCount` samples to pixel p; returns the budget they used (kept samples plus
  // slots lost to non-finite values; outlier rejections do not use budget).
  uint64_t samplePixel(uint32_t p, uint32_t slotCount, const SliceChoice& choice,
                       PixelSampler& sampler, PathCounters& counters) {
    const int px = int(p % width_), py = int(p / width_);
    PixelState& state = pixels_[p];
    const auto order = slotOrder(choice);
    uint64_t used = 0;
    std::vector<float> sliceValues;
    float x[kMaxNetInputs];
    // Only the inspected pixel records its candidates, and only one thread samples a pixel.
    const bool record = int64_t(p) == inspected_;
    auto recordCandidate = [&](const CameraSample& cs, float value, double score, int target,
                               int from) {
      if (!record) return;
      inspectedCandidates_.push_back(
          {cs.imageX - float(px), cs.imageY - float(py), value, float(score), target, from, false});
    };
    for (uint32_t slot = 0; slot < slotCount; ++slot) {
      const auto [target, from] = order[slot % order.size()];
      sliceValues.clear();
      for (const StoredSample& s : samples_[p])
        if (s.slice == target) sliceValues.push_back(s.value);
      const bool score = config_.outlierRemoval && !sliceValues.empty();
      const int candidates = score ? config_.candidates : 1;

      if (config_.candidateMode == CandidateMode::Traced || !score) {
        // (B): trace every candidate, keep the one closest to the slice (eq. 16).
        bool have = false;
        double best = 0.0;
        StoredSample bestSample{};
        size_t bestRecord = inspectedCandidates_.size();
        for (int c = 0; c < candidates; ++c) {
          const CameraSample cs = drawCandidate(sampler, px, py, state.drawn++, target, from);
          const vec3 L = traceRadiance(prepared_, cs, sampler, counters);
          ++state.traced;
          if (!isFinite(L)) {
            ++counters_.nonFinite;
            continue;
          }
          const StoredSample s = makeSample(cs, px, py, L);
          const double sc = candidateScore(sliceValues, s.value, config_.candidateEpsilon);
          if (!have || sc < best) {
            have = true;
            best = sc;
            bestSample = s;
            bestRecord = inspectedCandidates_.size();
          }
          recordCandidate(cs, s.value, sc, target, from);
        }
        if (have) keepSample(p, bestSample);
        if (record && have) inspectedCandidates_[bestRecord].kept = true;
        ++used;  // a slot whose candidates were all non-finite is spent and dropped
        continue;
      }
      // (A): score candidates by the network's prediction, trace only the best.
      double best = 0.0;
      uint32_t bestIndex = 0;
      for (int c = 0; c < candidates; ++c) {
        const uint32_t index = state.drawn++;
        const CameraSample cs = drawCandidate(sampler, px, py, index, target, from);
        bp::networkInputs(config_.network.inputs, cs.imageX - px - 0.5f, cs.imageY - py - 0.5f,
                          cs.lensU, cs.lensV, cs.time, x);
        const float v = luminance(predict(nets_[p], config_.network, x));
        const double sc = candidateScore(sliceValues, v, config_.candidateEpsilon);
        if (c == 0 || sc < best) {
          best = sc;
          bestIndex = index;
        }
        recordCandidate(cs, v, sc, target, from);
      }
      const size_t predictedFirst = inspectedCandidates_.size() - (record ? candidates : 0);
      const CameraSample cs = drawCandidate(sampler, px, py, bestIndex, target, from);
      const vec3 L = traceRadiance(prepared_, cs, sampler, counters);
      ++state.traced;
      if (!isFinite(L)) {
        ++counters_.nonFinite;
        ++used;
        continue;
      }
      const StoredSample s = makeSample(cs, px, py, L);
      double mean = 0.0;
      for (float v : sliceValues) mean += v;
      mean /= double(sliceValues.size());
      if (std::abs(s.value - mean) / (mean + config_.candidateEpsilon) > config_.outlierTau) {
        ++counters_.rejected;
        continue;
      }
      keepSample(p, s);
      if (record)
        inspectedCandidates_[predictedFirst + (bestIndex + candidates - state.drawn)].kept = true;
      ++used;
    }
    return used;
  }

  // --- Training and the error estimate (§4-§5) -----------------------------------------

  void train(const std::vector<uint32_t>& pixels, const std::atomic<bool>* cancel) {
    const auto start = Clock::now();
    const int ni = config_.network.inputs;
    TrainingBatch batch;
    batch.offsets.resize(pixels.size() + 1);
    batch.offsets[0] = 0;
    for (size_t i = 0; i < pixels.size(); ++i)
      batch.offsets[i + 1] = batch.offsets[i] + uint32_t(samples_[pixels[i]].size());
    batch.inputs.assign(size_t(batch.offsets.back()) * kMaxNetInputs, 0.0f);
    batch.targets.assign(size_t(batch.offsets.back()) * kNetOutputs, 0.0f);
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, pixels.size(), kPixelGrain),
        [&](const tbb::blocked_range<size_t>& range) {
          if (cancel && cancel->load(std::memory_order_relaxed)) return;
          for (size_t i = range.begin(); i < range.end(); ++i) {
            const uint32_t p = pixels[i];
            const PixelState& state = pixels_[p];
            const vec3 mean = state.kept ? vec3(state.sumT / double(state.kept)) : vec3(0.0f);
            size_t k = batch.offsets[i];
            for (const StoredSample& s : samples_[p]) {
              bp::networkInputs(ni, s.dx, s.dy, s.u, s.v, s.t, &batch.inputs[k * kMaxNetInputs]);
              const vec3 target =
                  config_.targets == TargetMode::PerSample ? tone_.apply(s.radiance) : mean;
              batch.targets[k * 3 + 0] = target.x;
              batch.targets[k * 3 + 1] = target.y;
              batch.targets[k * 3 + 2] = target.z;
              ++k;
            }
          }
        });
    std::vector<PixelNet*> nets(pixels.size());
    for (size_t i = 0; i < pixels.size(); ++i) nets[i] = &nets_[pixels[i]];
    if (cancel && cancel->load()) return;
    const auto kernelStart = Clock::now();
    trainingFlops_ += trainNetworks(config_.network, nets, batch, cancel);
    if (cancel && cancel->load()) return;
    trainingSeconds_ += secondsSince(kernelStart);

    // I' over K lens/time draws at the pixel centre, and the bias (§5).
    const int K = config_.predictionDraws;
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, pixels.size(), kPixelGrain),
        [&](const tbb::blocked_range<size_t>& range) {
          if (cancel && cancel->load(std::memory_order_relaxed)) return;
          std::vector<float> uvt(size_t(K) * 3);
          float x[kMaxNetInputs];
          for (size_t i = range.begin(); i < range.end(); ++i) {
            const uint32_t p = pixels[i];
            PixelState& state = pixels_[p];
            // K = 1 is the paper's single random draw, new every round.
            const uint64_t key =
                hashValues(config_.seed, p, K == 1 ? kPredictionSalt + rounds_ : kPredictionSalt);
            bp::predictionPoints(K, key, uvt.data());
            vec3 sum(0.0f);
            for (int j = 0; j < K; ++j) {
              const float u = prepared_.usesLens ? uvt[3 * j] : 0.5f;
              const float v = prepared_.usesLens ? uvt[3 * j + 1] : 0.5f;
              const float t = prepared_.usesTime ? uvt[3 * j + 2] : 0.5f;
              bp::networkInputs(ni, 0.0f, 0.0f, u, v, t, x);
              sum += predict(nets_[p], config_.network, x);
            }
            state.prediction = sum / float(K);
            state.er = nets_[p].er;
            const vec3 mean = state.kept ? vec3(state.sumT / double(state.kept)) : vec3(0.0f);
            state.bias = bp::biasOf(state.prediction, mean, config_.biasEpsilon);
          }
        });
    times_.train += secondsSince(start);
  }

  // --- Output (§7.4) -------------------------------------------------------------------

  Image estimate() const {
    Image image(width_, height_);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount_, 1024),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t p = range.begin(); p < range.end(); ++p)
                          image.pixels[p] = pixelEstimate(p);
                      });
    return image;
  }

  vec3 pixelEstimate(size_t p) const {
    const PixelState& s = pixels_[p];
    if (s.kept == 0) return vec3(0.0f);
    if (!config_.stratifiedMean) return vec3(s.sumL / double(s.kept));
    glm::dvec3 sum(0.0);
    int nonEmpty = 0;
    for (int i = 0; i < slicesPerPixel_; ++i) {
      const uint32_t n = slices_[p * slicesPerPixel_ + i].count;
      if (n == 0) continue;
      sum += sliceSumL_[p * slicesPerPixel_ + i] / double(n);
      ++nonEmpty;
    }
    return vec3(sum / double(nonEmpty));
  }

  const PreparedScene& prepared_;
  BpConfig config_;
  int width_, height_;
  size_t pixelCount_;
  int slicesPerPixel_;
  int coarseSpp_;
  ToneMap tone_;

  std::vector<PixelState> pixels_;
  std::vector<std::vector<StoredSample>> samples_;  // reservoirs
  std::vector<SliceStats> slices_;                  // pixel-major, S^2 per pixel
  std::vector<glm::dvec3> sliceSumL_;
  std::vector<PixelNet> nets_;
  std::vector<uint8_t> selected_;
  std::vector<uint32_t> lastOrder_;  // the last round's ranking
  std::atomic<int64_t> inspected_{-1};
  std::vector<InspectedCandidate> inspectedCandidates_;

  int rounds_ = 0;
  int adaptiveRounds_ = 0;
  bool stalled_ = false;
  uint64_t budget_ = 0;
  uint64_t spent_ = 0, kept_ = 0, traced_ = 0;
  uint64_t trainingFlops_ = 0;
  double trainingSeconds_ = 0;
  Counters counters_;
  PhaseTimes times_;
  Clock::time_point start_;
};

}  // namespace

int BpConfig::effectiveCoarseSpp() const {
  if (coarseSpp > 0) return coarseSpp;
  if (openEnded) return 4;
  const int quarter = int(roundUpPowerOfTwo(uint32_t(std::max(1, spp / 4))));
  return std::min(spp, std::max(4, quarter));
}

std::string BpConfig::validate() const {
  auto bad = [](const std::string& what) { return what; };
  if (!openEnded && spp < 1) return bad("--spp must be at least 1");
  if (coarseSpp < 0) return bad("--coarse-spp must be at least 1 (or 0 for automatic)");
  if (!openEnded && coarseSpp > spp) return bad("--coarse-spp cannot exceed --spp");
  if (maxRounds < 1) return bad("--rounds must be at least 1");
  if (openEnded && roundSpp < 1) return bad("--round-spp must be at least 1");
  if (network.inputs != 4 && network.inputs != 5) return bad("--inputs must be 4 or 5");
  if (network.hidden < 1 || network.hidden > kMaxNetHidden)
    return bad("--hidden must be in 1.." + std::to_string(kMaxNetHidden));
  if (network.epochs < 0) return bad("--nit must be at least 0");
  if (!(network.muMin > 0 && network.muMin <= network.muStart && network.muStart <= network.muMax))
    return bad("learning rates must satisfy 0 < min <= start <= max");
  if (predictionDraws < 1) return bad("--prediction-draws must be at least 1");
  if (slicesPerSide < 1 || slicesPerSide > kMaxSlicesPerSide)
    return bad("--slices must be in 1.." + std::to_string(kMaxSlicesPerSide));
  if (histogramLevels < 1 || histogramLevels > kMaxHistogramLevels)
    return bad("--levels must be in 1.." + std::to_string(kMaxHistogramLevels));
  if (candidates < 1) return bad("--candidates must be at least 1");
  if (!(psi >= 0)) return bad("--psi must be at least 0");
  if (!(biasEpsilon > 0)) return bad("--bias-epsilon must be positive");
  if (!(outlierTau > 0)) return bad("--outlier-tau must be positive");
  if (reservoir < effectiveCoarseSpp())
    return bad("--reservoir must hold at least the coarse pass (" +
               std::to_string(effectiveCoarseSpp()) + " samples)");
  if (filter.alphas.size() < 1 || filter.phi.size() + 1 != filter.alphas.size())
    return bad("--phi needs exactly one threshold fewer than --alphas has values");
  if (!std::is_sorted(filter.phi.begin(), filter.phi.end()))
    return bad("--phi thresholds must be ascending");
  for (float a : filter.alphas)
    if (!(a > 0)) return bad("--alphas must be positive");
  if (filter.radius < 0 || filter.radius > 32) return bad("--radius must be in 0..32");
  if (!(filter.sigmaC > 0)) return bad("--sigma-c must be positive");
  if (filter.secondPassAlpha < 0 || filter.secondPassAlpha >= int(filter.alphas.size()))
    return bad("the second pass alpha index is out of range");
  return {};
}

void applyBpPreset(BpConfig& config, BpPreset preset) {
  const BpConfig paper;
  const bool tuned = preset == BpPreset::Tuned;
  config.outlierRemoval = tuned ? false : paper.outlierRemoval;
  config.warping = tuned ? false : paper.warping;
  config.stratifiedMean = tuned ? false : paper.stratifiedMean;
  config.filter.sigmaC = tuned ? 0.05f : paper.filter.sigmaC;
}

const char* toString(BpPreset preset) { return preset == BpPreset::Tuned ? "tuned" : "paper"; }

std::unique_ptr<ProgressiveMethod> makeBpMethod(const PreparedScene& prepared,
                                                const BpConfig& config) {
  return std::make_unique<BpMethod>(prepared, config);
}

namespace bp {

void networkInputs(int inputs, float dx, float dy, float u, float v, float t, float* x) {
  if (inputs == 5) {
    x[0] = 2.0f * dx;
    x[1] = 2.0f * dy;
    x[2] = u;
    x[3] = v;
    x[4] = t;
    return;
  }
  x[0] = std::sqrt(2.0f) * std::sqrt(dx * dx + dy * dy);
  x[1] = u;
  x[2] = v;
  x[3] = t;
  x[4] = 0.0f;
}

float biasOf(vec3 prediction, vec3 mean, float eps) {
  const float total = mean.x + mean.y + mean.z;
  if (total == 0.0f) return 0.0f;
  const vec3 d = glm::abs(prediction - mean);
  return (d.x + d.y + d.z) / (total + eps);
}

void predictionPoints(int count, uint64_t pixelKey, float* uvt) {
  Pcg32 rng(pixelKey, 0x9e3779b9u);
  const float shift[3] = {rng.nextFloat(), rng.nextFloat(), rng.nextFloat()};
  static constexpr uint32_t kBases[3] = {2, 3, 5};
  for (int j = 0; j < count; ++j)
    for (int d = 0; d < 3; ++d) {
      // Halton index j + 1 skips the all-zero first point before the rotation.
      float value = (count == 1 ? 0.0f : halton(uint32_t(j + 1), kBases[d])) + shift[d];
      if (value >= 1.0f) value -= 1.0f;
      uvt[3 * j + d] = std::min(value, 0x1.fffffep-1f);
    }
}

std::vector<uint32_t> allocateSlots(std::span<const uint32_t> order, size_t pixelCount,
                                    uint64_t budget, int slotsPerPixel) {
  std::vector<uint32_t> slots(pixelCount, 0);
  if (order.empty() || budget == 0) return slots;
  const uint64_t perPass = uint64_t(order.size()) * slotsPerPixel;
  const uint64_t passes = budget / perPass;
  uint64_t rest = budget - passes * perPass;
  for (uint32_t p : order) {
    uint64_t n = passes * slotsPerPixel;
    const uint64_t extra = std::min<uint64_t>(rest, slotsPerPixel);
    n += extra;
    rest -= extra;
    slots[p] = uint32_t(n);
  }
  return slots;
}

}  // namespace bp

}  // namespace penumbra
