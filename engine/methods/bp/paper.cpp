// BP's paper algorithm, round by round: the coarse pass (§3), then adaptive rounds that rank
// the pixels by their error estimate, sample the chosen ones in their slices and retrain their
// networks; snapshots and the pixel inspector; its parameters, presets and descriptor. The
// phases are in pixel_store, trainer, error_estimate, candidates and reconstruct.
#include "methods/bp/paper.h"

#include "core/rng.h"
#include "methods/bp/candidates.h"
#include "methods/bp/error_estimate.h"
#include "methods/bp/state.h"
#include "methods/bp/trainer.h"
#include "methods/factory.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace penumbra {

namespace bp {

namespace {

using namespace method;

class PaperMethod final : public ProgressiveMethod {
 public:
  PaperMethod(const PreparedScene& prepared, const RunShape& shape, const BpPaperConfig& config)
      : ProgressiveMethod(shape),
        config_(config),
        s_(prepared, shape, config, config.effectiveCoarseSpp(shape), config.histogramLevels) {}

  void runRound(const std::atomic<bool>* cancel) override {
    if (done()) return;
    if (s_.rounds == 0)
      coarsePass(cancel);
    else
      adaptiveRound(cancel);
    ++s_.rounds;
  }

  int roundsDone() const override { return s_.rounds; }
  double budgetShare() const override { return s_.schedule.share(s_.spent); }

  size_t memoryBytes() const override { return s_.memoryBytes(); }

  std::shared_ptr<Snapshot> snapshot(bool reconstructImage,
                                     const std::atomic<bool>* cancel) override;

  void setInspectedPixel(int x, int y) override {
    s_.inspected =
        (x >= 0 && y >= 0 && x < s_.width && y < s_.height) ? int64_t(y) * s_.width + x : -1;
  }

  PixelInspection inspect(int x, int y) const override;

 protected:
  bool budgetSpent() const override {
    if (s_.rounds == 0) return false;
    if (s_.shape.openEnded) return s_.schedule.finished(s_.spent);
    // Outlier rejections (predicted mode) can leave budget after maxRounds: up to as
    // many make-up rounds again, then stop.
    return s_.schedule.finished(s_.spent) || s_.stalled ||
           s_.adaptiveRounds >= 2 * s_.config.maxRounds;
  }

 private:
  std::string reasonFor(const PixelInspection& in, const PixelState& s) const;
  void coarsePass(const std::atomic<bool>* cancel);
  void adaptiveRound(const std::atomic<bool>* cancel);
  void train(const std::vector<uint32_t>& pixels, const std::atomic<bool>* cancel) {
    const auto start = Clock::now();
    if (!trainNetworksOf(s_, pixels, cancel)) return;
    estimateErrors(s_, pixels, cancel);
    s_.times.train += secondsSince(start);
  }
  Image estimate() const {
    return s_.store.estimateImage(s_.width, s_.height, config_.stratifiedMean);
  }

  const BpPaperConfig config_;
  BpState s_;
};

std::shared_ptr<Snapshot> PaperMethod::snapshot(bool reconstructImage,
                                                const std::atomic<bool>* cancel) {
  const BpPaperConfig& config = config_;
  const size_t pixelCount = s_.pixelCount;
  auto snap = std::make_shared<Snapshot>();
  snap->withMaps = mapsWanted();
  const auto start = Clock::now();
  snap->method = "bp";
  snap->round = s_.rounds;
  snap->final = done();
  snap->width = s_.width;
  snap->height = s_.height;
  snap->raw = estimate();
  std::vector<float> bias(pixelCount), er(pixelCount), prediction(3 * pixelCount);
  std::vector<float> sliceB(pixelCount), sliceC(pixelCount);
  std::vector<uint32_t> kept(pixelCount), traced(pixelCount);
  for (size_t p = 0; p < pixelCount; ++p) {
    const PixelState& s = s_.pixel(p);
    bias[p] = s.bias;
    er[p] = s.er;
    for (int k = 0; k < 3; ++k) prediction[3 * p + size_t(k)] = s.prediction[k];
    sliceB[p] = s.sliceB;
    sliceC[p] = s.sliceC;
    kept[p] = s.kept;
    traced[p] = s.traced;
  }
  std::vector<uint8_t> alphaIndex;  // none without a reconstruction
  if (reconstructImage && config.reconstruct && s_.rounds > 0) {
    Reconstruction r = reconstruct(snap->raw, bias, s_.tone, config.filter, cancel);
    snap->reconstructed = std::move(r.output);
    alphaIndex = std::move(r.alphaIndex);
  } else if (reconstructImage) {
    snap->reconstructed = snap->raw;
    alphaIndex.assign(pixelCount, 0);
    for (size_t p = 0; p < pixelCount; ++p)
      alphaIndex[p] = uint8_t(alphaIndexForBias(bias[p], config.filter.phi));
  }

  // The maps, in the order --aov-dir has always written them.
  size_t difficult = 0;  // bias > psi and er > e: what the next round samples first
  for (size_t p = 0; p < pixelCount; ++p)
    difficult += bias[p] > config.psi && er[p] > config.network.errorThreshold;
  snap->addMap(maps::Prediction, "prediction I'", std::move(prediction), MapLegend::rgb());
  snap->addMap(maps::ErrorEstimate, "bias", std::move(bias), MapLegend::sequential(0.0f, 1.0f));
  const float erTop = std::max(1e-3f, finiteMax(er));
  snap->addMap(maps::NetworkError, "er", std::move(er), MapLegend::sequential(0.0f, erTop));
  addSelectedMap(*snap, s_.selected);
  const int S = config.slicesPerSide;
  std::vector<std::string> sliceLabels;
  for (int i = 0; i < S * S; ++i) {
    char label[32];
    std::snprintf(label, sizeof label, "(%d,%d)", i % S, i / S);
    sliceLabels.push_back(label);
  }
  const MapLegend slices = MapLegend::categorical(std::move(sliceLabels));
  snap->addMap(maps::SliceB, "slice B", std::move(sliceB), slices).slicesPerSide = S;
  snap->addMap(maps::SliceC, "slice C", std::move(sliceC), slices).slicesPerSide = S;
  addSampleCountMaps(*snap, kept, traced);
  if (!alphaIndex.empty()) {
    std::vector<std::string> alphaLabels;
    for (float a : config.filter.alphas) {
      char label[32];
      std::snprintf(label, sizeof label, "a=%g", double(a));
      alphaLabels.push_back(label);
    }
    snap->addMap(maps::FilterScale, "filter alpha", asFloats(alphaIndex),
                 MapLegend::categorical(std::move(alphaLabels)));
  }
  if (reconstructImage) s_.times.reconstruct += secondsSince(start);
  snap->keptSamples = s_.kept;
  s_.reportCounts(*snap, seconds());
  snap->addStat("difficult_pixels", double(difficult));
  return snap;
}

PixelInspection PaperMethod::inspect(int x, int y) const {
  const BpPaperConfig& config = config_;
  PixelInspection in = startInspection(x, y, s_.width, s_.height, s_.rounds, "bp");
  if (!in.valid) return in;
  const size_t p = size_t(y) * s_.width + x;
  const PixelState& s = s_.pixel(p);
  in.estimate = s_.store.estimate(p, config.stratifiedMean);
  in.kept = s.kept;
  in.traced = s.traced;
  in.addedLastRound = s.addedLastRound;

  char line[160];
  const vec3 mean = s.meanMapped(), net = s.prediction;
  std::snprintf(line, sizeof line, "mean I   %.3f %.3f %.3f (tone-mapped)", mean.x, mean.y, mean.z);
  in.addValue("mean I", {mean.x, mean.y, mean.z}, line);
  std::snprintf(line, sizeof line, "net  I'  %.3f %.3f %.3f", net.x, net.y, net.z);
  in.addValue("I'", {net.x, net.y, net.z}, line, maps::Prediction);
  // The thresholds bias and er are compared with follow their values.
  const float psi = config.psi, e = config.network.errorThreshold;
  std::snprintf(line, sizeof line, "bias %.3f %s psi %.3f", s.bias, s.bias > psi ? ">" : "<=", psi);
  in.addValue("bias", {s.bias, psi}, line, maps::ErrorEstimate);
  std::snprintf(line, sizeof line, "er   %.3f %s e %.3f", s.er, s.er > e ? ">" : "<=", e);
  in.addValue("er", {s.er, e}, line, maps::NetworkError);
  const int a = alphaIndexForBias(s.bias, config.filter.phi);
  const float alpha = size_t(a) < config.filter.alphas.size() ? config.filter.alphas[a] : -1.0f;
  std::snprintf(line, sizeof line, "filter alpha %g (index %d)", alpha, a + 1);
  in.addValue("filter alpha", {float(a), alpha}, line, maps::FilterScale);
  if (s.sliceB >= 0) {
    std::snprintf(line, sizeof line, "B = slice %d, C = slice %d, eq. 14 %.3f, %s", s.sliceB,
                  s.sliceC, s.contrast, s.warped ? "B's sample warped into C" : "no warping");
    in.addValue("slices B, C", {float(s.sliceB), float(s.sliceC), s.contrast}, line, maps::SliceB);
  }

  SubpixelInspection& sub = in.subpixel.emplace();
  sub.slicesPerSide = config.slicesPerSide;
  sub.sliceB = s.sliceB;
  sub.sliceC = s.sliceC;
  sub.warped = s.warped;
  sub.contrast = s.contrast;
  for (const SliceStats& st : s_.store.slicesOf(p))
    sub.slices.push_back({st.count, float(st.meanV()), float(fDivergence(st))});
  for (const StoredSample& st : s_.store.reservoirs[p])
    sub.samples.push_back({st.dx + 0.5f, st.dy + 0.5f, st.value, st.radiance, st.slice});
  if (int64_t(p) == s_.inspected) sub.candidates = s_.inspectedCandidates;
  const auto it = std::find(s_.lastOrder.begin(), s_.lastOrder.end(), uint32_t(p));
  in.rankedPixels = s_.lastOrder.size();
  if (it != s_.lastOrder.end()) in.rank = int(it - s_.lastOrder.begin());
  in.reason = reasonFor(in, s);
  return in;
}

// One line for the inspector: the test the pixel passed or failed and what it got.
std::string PaperMethod::reasonFor(const PixelInspection& in, const PixelState& s) const {
  char text[256];
  const bool converged = s.er <= config_.network.errorThreshold;
  const bool difficult = !converged && s.bias > config_.psi;
  const char* cls = difficult   ? "difficult (bias > psi, er > e)"
                    : converged ? "converged (er <= e), ranked by er after the others"
                                : "not difficult (bias <= psi), topped up by bias";
  if (s_.rounds == 1) {
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

// --- Coarse pass (§3) ------------------------------------------------------------------

void PaperMethod::coarsePass(const std::atomic<bool>* cancel) {
  const BpPaperConfig& config = config_;
  const PreparedScene& prepared = s_.prepared;
  const size_t pixelCount = s_.pixelCount;
  const int coarseSpp = s_.coarseSpp, width = s_.width;
  auto start = Clock::now();
  // Trace first: the tone map that histograms and targets use comes from this pass.
  std::vector<std::vector<TracedSample>> traced(pixelCount);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixelCount, kPixelGrain),
      [&](const tbb::blocked_range<size_t>& range) {
        if (s_.cancelled(cancel)) return;
        TraceChunk chunk(s_.counters, s_.shape.sampler, s_.shape.seed, uint32_t(coarseSpp));
        PixelSampler& sampler = chunk.sampler;
        for (size_t p = range.begin(); p < range.end(); ++p) {
          // Here rather than in the constructor: in parallel, and a restart can cancel it.
          initNetwork(s_.nets[p], config.network, hashValues(s_.shape.seed, p, kNetSalt));
          const int px = int(p % width), py = int(p / width);
          traced[p].reserve(coarseSpp);
          for (int i = 0; i < coarseSpp; ++i) {
            sampler.startSample(px, py, uint32_t(i));
            const CameraSample cs = sampler.cameraSample(prepared.usesLens, prepared.usesTime);
            const vec3 L = traceRadiance(prepared, cs, sampler, chunk.counters);
            if (isFinite(L))
              traced[p].push_back({cs, L});
            else
              ++chunk.nonFinite;
          }
          s_.pixel(p).traced = s_.pixel(p).drawn = uint32_t(coarseSpp);
        }
      });
  if (cancel && cancel->load()) return;
  Image coarse(width, s_.height);
  for (size_t p = 0; p < pixelCount; ++p) {
    glm::dvec3 sum(0.0);
    for (const TracedSample& s : traced[p]) sum += glm::dvec3(s.radiance);
    coarse.pixels[p] = traced[p].empty() ? vec3(0.0f) : vec3(sum / double(traced[p].size()));
  }
  s_.tone = toneMapFor(coarse);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixelCount, kPixelGrain),
      [&](const tbb::blocked_range<size_t>& range) {
        if (s_.cancelled(cancel)) return;
        for (size_t p = range.begin(); p < range.end(); ++p) {
          const int px = int(p % width), py = int(p / width);
          for (const TracedSample& s : traced[p])
            s_.store.keep(
                p, makeStoredSample(s.camera, px, py, s.radiance, s_.tone, config.slicesPerSide),
                s_.tone);
          std::vector<TracedSample>().swap(traced[p]);
        }
      });
  s_.spent = uint64_t(coarseSpp) * pixelCount;
  s_.traced = s_.spent;
  s_.kept = 0;
  for (const PixelState& s : s_.store.pixels) s_.kept += s.kept;
  s_.times.trace += secondsSince(start);

  std::vector<uint32_t> all(pixelCount);
  std::iota(all.begin(), all.end(), 0u);
  std::fill(s_.selected.begin(), s_.selected.end(), uint8_t(1));
  train(all, cancel);
}

// --- Adaptive rounds (§6-§8) -----------------------------------------------------------

void PaperMethod::adaptiveRound(const std::atomic<bool>* cancel) {
  const BpPaperConfig& config = config_;
  const size_t pixelCount = s_.pixelCount;
  auto start = Clock::now();
  const uint64_t budget = s_.schedule.roundBudget(s_.spent, s_.adaptiveRounds);
  std::vector<uint32_t> order = rankPixels(s_, config_);
  const std::vector<uint32_t> slots = allocateSlots(order, pixelCount, budget, s_.slicesPerPixel);
  s_.lastOrder = std::move(order);
  s_.inspectedCandidates.clear();
  std::vector<uint32_t> chosen;
  for (uint32_t p = 0; p < pixelCount; ++p) {
    s_.selected[p] = slots[p] > 0;
    if (slots[p] > 0) chosen.push_back(p);
  }
  ++s_.adaptiveRounds;
  if (chosen.empty()) {
    s_.stalled = true;
    s_.times.select += secondsSince(start);
    return;
  }
  // Slice choice per pixel, fixed for the round (§6.3-§6.4).
  std::vector<SliceChoice> choices(pixelCount);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chosen.size(), kPixelGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i < range.end(); ++i) {
                        const uint32_t p = chosen[i];
                        SliceChoice c = chooseSlices(s_.store.slicesOf(p), config.histogramLevels);
                        if (!config.warping) c.warp = false;
                        choices[p] = c;
                      }
                    });
  for (size_t p = 0; p < pixelCount; ++p) {
    PixelState& pixel = s_.pixel(p);
    pixel.sliceB = slots[p] ? int8_t(choices[p].b) : int8_t(-1);
    pixel.sliceC = slots[p] ? int8_t(choices[p].c) : int8_t(-1);
    pixel.warped = slots[p] && choices[p].warp;
    pixel.contrast = slots[p] ? float(choices[p].contrast) : 0.0f;
    pixel.addedLastRound = 0;
  }
  s_.times.select += secondsSince(start);

  start = Clock::now();
  std::atomic<uint64_t> spent{0}, tracedCount{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chosen.size(), 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (s_.cancelled(cancel)) return;
                      TraceChunk chunk(s_.counters, s_.shape.sampler, s_.shape.seed,
                                       uint32_t(s_.coarseSpp));
                      uint64_t localSpent = 0, localTraced = 0;
                      for (size_t i = range.begin(); i < range.end(); ++i) {
                        const uint32_t p = chosen[i];
                        PixelState& pixel = s_.pixel(p);
                        const uint32_t before = pixel.traced;
                        const uint32_t keptBefore = pixel.kept;
                        localSpent += samplePixel(s_, config_, p, slots[p], choices[p],
                                                  chunk.sampler, chunk.counters, chunk.nonFinite);
                        localTraced += pixel.traced - before;
                        pixel.addedLastRound = pixel.kept - keptBefore;
                      }
                      spent += localSpent;
                      tracedCount += localTraced;
                    });
  if (cancel && cancel->load()) return;
  s_.spent += spent;
  s_.traced += tracedCount;
  s_.kept = 0;
  for (const PixelState& s : s_.store.pixels) s_.kept += s.kept;
  s_.times.trace += secondsSince(start);
  train(chosen, cancel);
}

}  // namespace

}  // namespace bp

std::unique_ptr<ProgressiveMethod> makeBpPaperMethod(const PreparedScene& prepared,
                                                     const RunShape& shape,
                                                     const BpPaperConfig& config) {
  requireValid({shape, MethodConfig(bpPaperMethod(), config)});
  return std::make_unique<bp::PaperMethod>(prepared, shape, config);
}

}  // namespace penumbra
