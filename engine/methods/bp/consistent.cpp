// BP's consistent algorithm (the `consistent` preset and the default of `--method bp`;
// RECONSTRUCTION.md):
//  - every traced sample goes into the film (methods/film.h): mean, variance, half buffers,
//    first-hit features and directly seen emission;
//  - the image is the film's consistent reconstruction (methods/recon/denoise.h), whose chosen
//    filter tends to the identity as samples accumulate;
//  - each round's samples go where the estimated relative error falls most
//    (methods/error_allocation.h): the raw mean's variance over its square, dilated 3x3, at
//    every spp, with a floor that keeps every pixel sampled;
//  - the per-pixel networks are trained on the pixel's reservoir, and retrained only once its
//    sample count has grown by `retrainGrowth`; where a network's prediction departs from the
//    pixel's mean (the bias of eq. 13, sub-pixel structure the filter must not smooth) the
//    pixel's error counts (1 + networkWeight x bias) times more.
// A pixel's samples are the next ones of its own low-discrepancy stream, uniform over the
// pixel, so its mean is unbiased whatever count the allocation gives it; with every pixel
// given the same count the samples are exactly LD's.
#include "methods/bp/consistent.h"

#include "core/rng.h"
#include "methods/bp/error_estimate.h"
#include "methods/bp/state.h"
#include "methods/bp/trainer.h"
#include "methods/factory.h"
#include "methods/film_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace penumbra::bp {

namespace {

using namespace method;

// The slices' histogram levels m, which this algorithm does not read (the paper's default).
constexpr int kHistogramLevels = 5;
// The reconstruction that steers allocation is redone once the samples grew this much.
constexpr double kReconstructionGrowth = 1.5;
// The absolute term ranks a pixel by its (2r + 1)^2 neighbourhood's mean MSE, not its own: a
// pixel whose own few samples missed a rare bright path does not look converged, and its count
// depends little on its own samples (the neighbourhood's bright edge still draws samples).
constexpr int kAbsoluteRadius = 3;

class ConsistentMethod final : public ProgressiveMethod {
 public:
  ConsistentMethod(const PreparedScene& prepared, const RunShape& shape,
                   const BpConsistentConfig& config)
      : ProgressiveMethod(shape),
        config_(config),
        // Without networks the film holds every sum the algorithm reads: no sample store.
        s_(prepared, shape, config, config.effectiveCoarseSpp(shape), kHistogramLevels,
           config.usesNetworks()),
        film_(s_.width, s_.height),
        drawn_(s_.pixelCount, 0),
        rays_(s_.pixelCount, 0),
        addedLastRound_(s_.pixelCount, 0),
        setSize_(shape.openEnded ? 64u : uint32_t(shape.spp)),
        coarseSteps_(coarseSteps(shape, s_.coarseSpp)) {
    if (usesNetworks()) trainedAt_.assign(s_.pixelCount, 0);
    if (config.correctsWithNetworks()) {
      NetReconConfig nc = config.netRecon;
      nc.hidden = config.network.hidden;
      nets_ =
          std::make_unique<NetRecon>(s_.width, s_.height, prepared.usesLens, prepared.usesTime, nc);
    }
    // Only the noise threshold refreshes the filtered image's error estimate.
    if (shape.noiseThreshold > 0) {
      errorAtReconstruction_.assign(s_.pixelCount, 0.0f);
      countAtReconstruction_.assign(s_.pixelCount, 0);
    }
    if (config.sliceSteering) {
      film_.enableSlices(config.slicesPerSide);
      sliceDrawn_.assign(s_.pixelCount * size_t(film_.slicesPerPixel()), 0);
    }
  }

  void runRound(const std::atomic<bool>* cancel) override {
    if (done()) return;
    if (!coarseComplete())
      coarsePass(cancel);
    else
      adaptiveRound(cancel);
    if (cancel && cancel->load()) return;
    ++s_.rounds;
  }

  int roundsDone() const override { return s_.rounds; }
  double budgetShare() const override { return s_.schedule.share(s_.spent); }
  Image rawVarianceOfMean() const override { return film_.varianceOfMeanImage(); }
  double estimatedError() const override {
    if (reconstructedAtRound_ < 0) return NAN;
    double sum = 0;
    for (size_t p = 0; p < s_.pixelCount; ++p) sum += currentError(p);
    return sum / double(s_.pixelCount);
  }
  size_t memoryBytes() const override;
  std::shared_ptr<Snapshot> snapshot(bool reconstructImage,
                                     const std::atomic<bool>* cancel) override;
  PixelInspection inspect(int x, int y) const override;

 protected:
  bool budgetSpent() const override {
    return coarseComplete() && (s_.schedule.finished(s_.spent) || s_.stalled);
  }

 private:
  bool usesNetworks() const { return config_.usesNetworks(); }
  // The coarse pass's steps, in samples per pixel: a batch run traces it in one round; an
  // open-ended one (the viewer) in rounds of 1, 1 and the rest, each of which publishes, so
  // that a full picture shows after one sample per pixel. The film receives the same samples
  // in the same order either way.
  static std::vector<int> coarseSteps(const RunShape& shape, int coarseSpp) {
    if (!shape.openEnded || coarseSpp < 2) return {coarseSpp};
    if (coarseSpp == 2) return {1, 1};
    return {1, 1, coarseSpp - 2};
  }
  bool coarseComplete() const { return coarseStepsDone_ == coarseSteps_.size(); }
  void coarsePass(const std::atomic<bool>* cancel);
  void adaptiveRound(const std::atomic<bool>* cancel);
  // Traces `count` more samples of pixel p into the film (and, once the tone map is known,
  // into its reservoir); the coarse pass keeps them in `coarse` instead.
  // With slice steering, `plan` says how many go to each slice (null: one slice after the
  // other). Returns the rays they cast.
  uint64_t tracePixel(size_t p, uint32_t count, TraceChunk& chunk,
                      std::vector<TracedSample>* coarse, const uint32_t* plan = nullptr);
  void trainDue(const std::atomic<bool>* cancel);
  void countKept() {
    s_.kept = 0;
    for (size_t p = 0; p < s_.pixelCount; ++p) s_.kept += film_[p].count;
  }
  // Refreshes the filtered image's error estimate (for the noise threshold), when the film
  // grew enough.
  void refreshErrors(const std::atomic<bool>* cancel);
  // The error each pixel is ranked by now.
  std::vector<float> allocationError() const;
  // The filtered pixel's estimated relMSE now: the last estimate, falling as 1/n since (0
  // without an estimate: only the noise threshold makes one).
  float currentError(size_t p) const {
    if (errorAtReconstruction_.empty()) return 0.0f;
    const uint32_t now = std::max<uint32_t>(1, film_[p].count);
    return errorAtReconstruction_[p] * float(std::max<uint32_t>(1, countAtReconstruction_[p])) /
           float(now);
  }
  float networkFactor(size_t p) const {
    return usesNetworks() ? 1.0f + config_.networkWeight * s_.pixel(p).bias : 1.0f;
  }

  // With slice steering: how `count` more samples of pixel p split over its slices
  // (plan[k] samples for slice k).
  void planSlices(size_t p, uint32_t count, uint32_t* plan) const;
  // Sample j of slice k of pixel (px, py), started in chunk's sampler.
  CameraSample sliceSample(int px, int py, int k, uint32_t j, TraceChunk& chunk) const;

  const BpConsistentConfig config_;
  BpState s_;
  Film film_;
  std::vector<uint32_t> sliceDrawn_;  // with slice steering: samples drawn in each slice
  std::vector<uint32_t> trainedAt_;   // with networks: kept samples at the network's last training
  // Sample indices used from the pixel's stream: the camera samples it traced.
  std::vector<uint32_t> drawn_;
  std::vector<uint32_t> rays_;                // rays its samples cast: their cost
  uint64_t totalRays_ = 0, totalTraced_ = 0;  // their sums over the image
  std::vector<uint32_t> addedLastRound_;      // samples the last round added to the film
  // With the noise threshold: the filtered image's error estimate and the counts it was made at.
  std::vector<float> errorAtReconstruction_;
  std::vector<uint32_t> countAtReconstruction_;
  uint64_t spentAtReconstruction_ = 0;
  // The last reconstruction: whole after refreshErrors, for the round's snapshot; once a
  // snapshot has taken its output, only its scale (the inspector's filter window).
  std::optional<recon::DenoiseResult> lastReconstruction_;
  int reconstructedAtRound_ = -1;
  PictureReconstruction pictures_;  // the last picture, kept to update it
  uint32_t setSize_;
  std::vector<int> coarseSteps_;
  size_t coarseStepsDone_ = 0;
  int coarseSppDone_ = 0;
  // The coarse samples the reservoirs keep once the tone map is known (only with networks).
  std::vector<std::vector<TracedSample>> coarseTraced_;
  // With --networks 1: the networks that correct the samples.
  std::unique_ptr<NetRecon> nets_;
};

template <class T, class Allocator>
size_t bytesOf(const std::vector<T, Allocator>& v) {
  return v.capacity() * sizeof(T);
}

size_t ConsistentMethod::memoryBytes() const {
  size_t bytes = s_.memoryBytes() + film_.memoryBytes() + (nets_ ? nets_->memoryBytes() : 0) +
                 bytesOf(sliceDrawn_) + bytesOf(trainedAt_) + bytesOf(drawn_) + bytesOf(rays_) +
                 bytesOf(addedLastRound_) + bytesOf(errorAtReconstruction_) +
                 bytesOf(countAtReconstruction_) + pictures_.memoryBytes();
  if (lastReconstruction_) {
    const recon::DenoiseResult& r = *lastReconstruction_;
    bytes += bytesOf(r.output.pixels) + bytesOf(r.scale) + bytesOf(r.mseEstimate) +
             bytesOf(r.varianceRatio);
  }
  return bytes;
}

uint64_t ConsistentMethod::tracePixel(size_t p, uint32_t count, TraceChunk& chunk,
                                      std::vector<TracedSample>* coarse, const uint32_t* plan) {
  const PreparedScene& prepared = s_.prepared;
  const int px = int(p % s_.width), py = int(p / s_.width);
  const uint32_t raysBefore = rays_[p];
  const int slices = film_.slicesPerPixel();
  uint32_t left[kMaxSlicesPerSide * kMaxSlicesPerSide] = {};
  if (slices > 0)
    for (int k = 0; k < slices; ++k) left[k] = plan ? plan[k] : 0;
  int next = 0;
  for (uint32_t k = 0; k < count; ++k) {
    int slice = -1;
    CameraSample cs;
    if (slices > 0) {
      // Without a plan the slices take turns.
      if (plan) {
        while (left[next] == 0) next = (next + 1) % slices;
        --left[next];
      }
      slice = next;
      next = (next + 1) % slices;
      ++drawn_[p];
      cs = sliceSample(px, py, slice, sliceDrawn_[p * size_t(slices) + size_t(slice)]++, chunk);
    } else {
      chunk.sampler.startSample(px, py, drawn_[p]++);
      cs = chunk.sampler.cameraSample(prepared.usesLens, prepared.usesTime);
    }
    PathFeatures features;
    const uint64_t chunkRays = chunk.counters.rays;
    const vec3 L = traceRadiance(prepared, cs, chunk.sampler, chunk.counters, &features);
    rays_[p] += uint32_t(chunk.counters.rays - chunkRays);
    if (!isFinite(L)) {
      ++chunk.nonFinite;
      continue;
    }
    if (nets_) nets_->record(p, px, py, cs, L, features);
    // With a network, the film takes the sample less the network's part of it (a control
    // variate: methods/bp/net_recon.h).
    film_.add(p, nets_ ? L - nets_->correction(p, px, py, cs, features) : L, features, slice);
    pictures_.changed(p);
    if (!usesNetworks()) continue;  // the reservoirs only feed the networks
    if (coarse)
      coarse->push_back({cs, L});
    else
      s_.store.keep(p, makeStoredSample(cs, px, py, L, s_.tone, s_.config.slicesPerSide), s_.tone);
  }
  return rays_[p] - raysBefore;
}

CameraSample ConsistentMethod::sliceSample(int px, int py, int k, uint32_t j,
                                           TraceChunk& chunk) const {
  const PreparedScene& prepared = s_.prepared;
  const int side = film_.slicesPerSide();
  const uint32_t slices = uint32_t(side * side);
  PixelSampler& sampler = chunk.sampler;
  // In the pixel's own low-discrepancy sequence every aligned run of S^2 samples has exactly one
  // image point in each slice (a (0,2)-net, which the nested block order and the scrambles
  // keep), so the slice's j-th sample is the one of run j that falls in it: with every slice
  // sampled alike the samples are exactly the pixel's own, and a slice sampled more than the
  // others still takes points of the same stratified sequence.
  if (sampler.kind() == SamplerKind::LowDiscrepancy && sampler.setSize() % slices == 0) {
    for (uint32_t t = 0; t < slices; ++t) {
      const uint32_t index = j * slices + t;
      sampler.startSample(px, py, index);
      const CameraSample probe = sampler.cameraSample(false, false);
      const int sx = std::min(side - 1, int((probe.imageX - float(px)) * float(side)));
      const int sy = std::min(side - 1, int((probe.imageY - float(py)) * float(side)));
      if (sy * side + sx != k) continue;
      sampler.startSample(px, py, index);
      return sampler.cameraSample(prepared.usesLens, prepared.usesTime);
    }
  }
  // Otherwise (independent samples) the slice's own stream, its image point moved into the
  // slice: uniform over it.
  sampler.startSample(px, py, j, uint32_t(1 + k));
  CameraSample cs = sampler.cameraSample(prepared.usesLens, prepared.usesTime);
  const float fx = cs.imageX - float(px), fy = cs.imageY - float(py);
  cs.imageX = float(px) + (float(k % side) + fx) / float(side);
  cs.imageY = float(py) + (float(k / side) + fy) / float(side);
  return cs;
}

void ConsistentMethod::planSlices(size_t p, uint32_t count, uint32_t* plan) const {
  // Neyman allocation, greedily: each sample goes to the slice with the largest
  // v_k / (n_k (n_k + 1)), the drop in sum_k v_k / n_k it brings (the areas are equal). The
  // per-sample variance v_k is not the slice's own: ranking a slice by its own samples' spread
  // starves the slices whose few samples missed a rare bright path and biases the estimate low
  // (the z-test measured it). It is the same slice's in the 8 neighbouring pixels, pooled
  // (an edge or a penumbra crossing p crosses them too) and shrunk towards their whole
  // pixels' variance by kShrink samples' worth. An empty slice comes first.
  constexpr double kShrink = 2.0;
  const int slices = film_.slicesPerPixel();
  const int px = int(p % s_.width), py = int(p / s_.width);
  double m2[kMaxSlicesPerSide * kMaxSlicesPerSide] = {},
                                dof[kMaxSlicesPerSide * kMaxSlicesPerSide] = {};
  double pooledM2 = 0, pooledDof = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = px + dx, qy = py + dy;
      if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= s_.width || qy >= s_.height) continue;
      const size_t q = size_t(qy) * s_.width + size_t(qx);
      const FilmPixel& f = film_[q];
      if (f.count > 1) {
        pooledM2 += (f.m2.x + f.m2.y + f.m2.z) / 3.0;
        pooledDof += double(f.count - 1);
      }
      for (int k = 0; k < slices; ++k) {
        const FilmSlice& slice = film_.slice(q, k);
        if (slice.count < 2) continue;
        m2[k] += (double(slice.m2.x) + slice.m2.y + slice.m2.z) / 3.0;
        dof[k] += double(slice.count - 1);
      }
    }
  const double pooled = pooledDof > 0 ? pooledM2 / pooledDof : 0.0;
  double v[kMaxSlicesPerSide * kMaxSlicesPerSide];
  uint32_t n[kMaxSlicesPerSide * kMaxSlicesPerSide];
  for (int k = 0; k < slices; ++k) {
    v[k] = (m2[k] + kShrink * pooled) / (dof[k] + kShrink);
    n[k] = film_.slice(p, k).count;
    plan[k] = 0;
  }
  // A floor of half the even share keeps every slice's variance within twice what even
  // sampling gives, whatever the neighbours say (an emitter's edge may cross p alone).
  uint32_t total = count;
  for (int k = 0; k < slices; ++k) total += n[k];
  const double floor = 0.5 * double(total) / double(slices);
  for (uint32_t i = 0; i < count; ++i) {
    int best = 0;
    double bestGain = -1.0;
    for (int k = 0; k < slices; ++k) {
      const uint32_t have = n[k] + plan[k];
      // Ties go to the slice with fewer samples, then the lower index.
      const double gain =
          double(have) < floor ? HUGE_VAL : v[k] / (double(have) * double(have + 1));
      if (gain > bestGain || (gain == bestGain && have < n[best] + plan[best])) {
        best = k;
        bestGain = gain;
      }
    }
    ++plan[best];
  }
}

void ConsistentMethod::coarsePass(const std::atomic<bool>* cancel) {
  const size_t pixelCount = s_.pixelCount;
  const auto start = Clock::now();
  const int step = coarseSteps_[coarseStepsDone_];
  if (usesNetworks() && coarseTraced_.empty()) coarseTraced_.resize(pixelCount);
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount, kPixelGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (s_.cancelled(cancel)) return;
                      TraceChunk chunk(s_.counters, s_.shape.sampler, s_.shape.seed, setSize_);
                      uint64_t local = 0;
                      for (size_t p = range.begin(); p < range.end(); ++p) {
                        if (usesNetworks() && coarseSppDone_ == 0)
                          initNetwork(s_.nets[p], s_.config.network,
                                      hashValues(s_.shape.seed, p, kNetSalt));
                        local += tracePixel(p, uint32_t(step), chunk,
                                            coarseTraced_.empty() ? nullptr : &coarseTraced_[p]);
                      }
                      rays += local;
                    });
  if (cancel && cancel->load()) return;
  coarseSppDone_ += step;
  ++coarseStepsDone_;
  totalRays_ += rays;
  totalTraced_ += uint64_t(step) * pixelCount;
  s_.spent = s_.traced = uint64_t(coarseSppDone_) * pixelCount;
  countKept();
  std::fill(s_.selected.begin(), s_.selected.end(), uint8_t(1));
  s_.times.trace += secondsSince(start);
  if (!coarseComplete()) return;
  s_.tone = toneMapFor(film_.meanImage());
  if (!coarseTraced_.empty())
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount, kPixelGrain),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t p = range.begin(); p < range.end(); ++p) {
                          const int px = int(p % s_.width), py = int(p / s_.width);
                          for (const TracedSample& t : coarseTraced_[p])
                            s_.store.keep(p,
                                          makeStoredSample(t.camera, px, py, t.radiance, s_.tone,
                                                           s_.config.slicesPerSide),
                                          s_.tone);
                        }
                      });
  std::vector<std::vector<TracedSample>>().swap(coarseTraced_);
  trainDue(cancel);
}

void ConsistentMethod::trainDue(const std::atomic<bool>* cancel) {
  if (nets_) {
    const auto start = Clock::now();
    nets_->train(film_, totalRays_, cancel);
    s_.times.network += secondsSince(start);
  }
  if (!usesNetworks()) return;
  const auto start = Clock::now();
  // Every pixel due this round, in pixel order: one list, so the kernel fills its SIMD lanes
  // across the whole round.
  std::vector<uint32_t> due;
  for (uint32_t p = 0; p < s_.pixelCount; ++p) {
    const uint32_t kept = s_.pixel(p).kept;
    if (kept > 0 && (trainedAt_[p] == 0 || double(kept) >= config_.retrainGrowth * trainedAt_[p]))
      due.push_back(p);
  }
  if (!due.empty() && trainNetworksOf(s_, due, cancel)) {
    estimateErrors(s_, due, cancel);
    for (uint32_t p : due) trainedAt_[p] = s_.pixel(p).kept;
  }
  s_.times.train += secondsSince(start);
}

void ConsistentMethod::refreshErrors(const std::atomic<bool>* cancel) {
  if (!(s_.shape.noiseThreshold > 0)) return;  // only the noise threshold needs it
  if (reconstructedAtRound_ >= 0 &&
      double(s_.spent) < kReconstructionGrowth * double(spentAtReconstruction_))
    return;
  const auto start = Clock::now();
  lastReconstruction_.reset();  // not held with the new one
  recon::DenoiseResult r = reconstructFilm(film_, config_.denoise, cancel);
  if (cancel && cancel->load()) return;
  errorAtReconstruction_ = relativeError(r, film_);
  for (size_t p = 0; p < s_.pixelCount; ++p) countAtReconstruction_[p] = film_[p].count;
  spentAtReconstruction_ = s_.spent;
  lastReconstruction_ = std::move(r);
  reconstructedAtRound_ = s_.rounds;
  s_.times.reconstruct += secondsSince(start);
}

std::vector<float> ConsistentMethod::allocationError() const {
  const size_t n = s_.pixelCount;
  // The raw mean's relative variance ranks the pixels: measured on balls at 16 spp, ranking by
  // the filtered image's SURE estimate instead (RECONSTRUCTION.md §5 as written) gave a worse
  // filtered image than uniform sampling (1.1e-4 against 4.0e-5): SURE under-estimates the
  // error where it chose a wide filter, and those pixels starve; by the raw variance, 2.7e-5.
  // One pass over the film (it is the large array) gives each pixel's raw relMSE, its raw MSE
  // (for the absolute term) and its mean value.
  // Made afresh every round: huge pages, one fault per 2 MiB (core/large_pages.h).
  LargeVector<float> raw(n);
  LargeVector<double> value(n);
  std::vector<float> mse(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t p = range.begin(); p < range.end(); ++p) {
                        // The stratified estimate with slice steering, else the plain mean, bit for
                        // bit.
                        const vec3 v = film_.estimateVarianceOfMean(p);
                        const glm::dvec3 mean = film_.estimate(p);
                        const float m = (v.x + v.y + v.z) / 3.0f;
                        raw[p] = m / relativeErrorRegulariser(vec3(mean));
                        mse[p] = m;
                        value[p] = (mean.x + mean.y + mean.z) / 3.0;
                      }
                    });
  // The absolute term: + absoluteWeight x (the mean raw MSE around p) / (the image's mean
  // value)^2. The window makes a pixel's share depend on its region, not on whether its own
  // few samples met a rare bright path.
  const float w = config_.absoluteWeight;
  float absoluteScale = 0;
  if (w > 0) {
    double sum = 0;  // in pixel order: the same bits whatever the thread count
    for (double v : value) sum += v;
    const double mean = sum / double(n);
    if (mean > 0) {
      absoluteScale = float(double(w) / (mean * mean));
      mse = recon::boxMean(mse, s_.width, s_.height, kAbsoluteRadius);
    }
  }
  // A sample costs its rays: minimising the error at equal time rather than equal samples
  // divides each pixel's error by its cost per sample relative to the image's (the water-
  // filling then gives n ~ sqrt(e n / cost)), so a pixel of long paths is not over-sampled.
  // The totals are whole numbers, kept as the samples are traced.
  const double meanCost =
      totalTraced_ > 0 && totalRays_ > 0 ? double(totalRays_) / double(totalTraced_) : 1.0;
  LargeVector<float> e(n);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
          const uint32_t traced = drawn_[p];
          const double cost = traced && rays_[p] ? double(rays_[p]) / traced / meanCost : 1.0;
          const float error = absoluteScale > 0 ? raw[p] + absoluteScale * mse[p] : raw[p];
          e[p] = float(error * networkFactor(p) / cost);
        }
      });
  return dilate3x3(e, s_.width, s_.height);
}

namespace {

// Puts the k first of `order` by the strict order `before` at its front, in that order: a
// selection, then a sort of those k only (for k much smaller than the image).
template <class Before>
void rankFirst(std::vector<uint32_t>& order, size_t k, Before before) {
  if (k == 0) return;
  const auto kth = order.begin() + std::ptrdiff_t(k);
  if (k < order.size()) std::nth_element(order.begin(), kth - 1, order.end(), before);
  std::sort(order.begin(), kth, before);
}

// The coins leave the total a few samples off the budget: settle the difference on the
// pixels of highest (to add) or lowest (to take) error, so a batch spends exactly its spp.
// Only those few pixels are ranked (by error, then index: a strict order, so the result is
// the same whatever the sort); a full sort of the image each round cost more than the rest.
void settleToBudget(std::vector<uint32_t>& slots, const std::vector<float>& error, uint64_t budget,
                    const std::vector<uint8_t>& converged) {
  uint64_t total = 0;
  for (uint32_t v : slots) total += v;
  if (total == budget) return;
  auto higher = [&](uint32_t a, uint32_t b) {
    return error[a] != error[b] ? error[a] > error[b] : a < b;
  };
  std::vector<uint32_t> order;
  if (total < budget) {
    for (uint32_t p = 0; p < slots.size(); ++p)
      if (converged.empty() || !converged[p]) order.push_back(p);
    if (order.empty()) return;
    const size_t k = std::min<size_t>(order.size(), budget - total);
    rankFirst(order, k, higher);
    for (size_t i = 0; total < budget; i = (i + 1) % k, ++total) ++slots[order[i]];
    return;
  }
  for (uint32_t p = 0; p < slots.size(); ++p)
    if (slots[p] > 0) order.push_back(p);
  // Lowest error first: the reverse of `higher`.
  auto lower = [&](uint32_t a, uint32_t b) { return higher(b, a); };
  while (total > budget && !order.empty()) {
    const size_t k = std::min<size_t>(order.size(), total - budget);
    rankFirst(order, k, lower);
    for (size_t i = 0; i < k; ++i) {
      --slots[order[i]];
      --total;
    }
    std::erase_if(order, [&](uint32_t p) { return slots[p] == 0; });
  }
}

}  // namespace

void ConsistentMethod::adaptiveRound(const std::atomic<bool>* cancel) {
  const size_t pixelCount = s_.pixelCount;
  refreshErrors(cancel);
  if (cancel && cancel->load()) return;
  auto start = Clock::now();
  const uint64_t budget = s_.schedule.growingRoundBudget(s_.spent, s_.adaptiveRounds);
  std::vector<uint32_t> counts(pixelCount);
  for (size_t p = 0; p < pixelCount; ++p) counts[p] = film_[p].count;
  std::vector<float> error = allocationError();
  // The threshold is on the filtered image: its converged pixels get nothing, as do those whose
  // error is already nil.
  std::vector<uint8_t> converged;
  if (s_.shape.noiseThreshold > 0 && reconstructedAtRound_ >= 0) {
    converged.resize(pixelCount);
    for (size_t p = 0; p < pixelCount; ++p)
      converged[p] =
          s_.shape.converged(currentError(p)) || (std::isfinite(error[p]) && error[p] < 1e-30f);
  }
  std::vector<uint32_t> slots = allocateByError(error, counts, budget, config_.allocation,
                                                s_.shape.seed, s_.adaptiveRounds, converged);
  settleToBudget(slots, error, budget, converged);
  std::vector<uint32_t> chosen;
  for (uint32_t p = 0; p < pixelCount; ++p) {
    s_.selected[p] = slots[p] > 0;
    addedLastRound_[p] = 0;
    if (slots[p] > 0) chosen.push_back(p);
  }
  ++s_.adaptiveRounds;
  s_.times.select += secondsSince(start);
  if (chosen.empty()) {
    s_.stalled = true;
    return;
  }
  // Slice plans from the film as it stands before the round's samples: every pixel's plan
  // reads its neighbours, so none may change while they are made.
  std::vector<uint32_t> plans;
  const size_t slices = size_t(film_.slicesPerPixel());
  if (slices > 0) {
    start = Clock::now();
    plans.assign(chosen.size() * slices, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chosen.size(), 256),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i < range.end(); ++i)
                          planSlices(chosen[i], slots[chosen[i]], &plans[i * slices]);
                      });
    s_.times.select += secondsSince(start);
  }
  start = Clock::now();
  std::atomic<uint64_t> spent{0}, rays{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chosen.size(), 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (s_.cancelled(cancel)) return;
                      TraceChunk chunk(s_.counters, s_.shape.sampler, s_.shape.seed, setSize_);
                      uint64_t local = 0, localRays = 0;
                      for (size_t i = range.begin(); i < range.end(); ++i) {
                        const uint32_t p = chosen[i];
                        const uint32_t before = film_[p].count;
                        localRays += tracePixel(p, slots[p], chunk, nullptr,
                                                slices > 0 ? &plans[i * slices] : nullptr);
                        addedLastRound_[p] = film_[p].count - before;
                        local += slots[p];
                      }
                      spent += local;
                      rays += localRays;
                    });
  if (cancel && cancel->load()) return;
  totalRays_ += rays;
  totalTraced_ += spent;
  s_.spent += spent;
  s_.traced += spent;
  countKept();
  s_.times.trace += secondsSince(start);
  trainDue(cancel);
}

std::shared_ptr<Snapshot> ConsistentMethod::snapshot(bool reconstructImage,
                                                     const std::atomic<bool>* cancel) {
  auto snap = std::make_shared<Snapshot>();
  snap->withMaps = mapsWanted();
  snap->method = "bp";
  snap->round = s_.rounds;
  snap->final = done();
  snap->width = s_.width;
  snap->height = s_.height;
  // The reconstruction first, while no image of the snapshot is held: it is the peak of the
  // method's memory.
  if (reconstructImage && s_.config.reconstruct && s_.rounds > 0) {
    // Its output moves into the snapshot: a second snapshot of the round reconstructs again.
    if (!lastReconstruction_ || reconstructedAtRound_ != s_.rounds ||
        lastReconstruction_->output.empty()) {
      lastReconstruction_.reset();  // not held with the new one
      const auto start = Clock::now();
      recon::DenoiseResult r = pictures_.reconstruct(
          film_, config_.denoise, double(s_.spent) / double(s_.pixelCount), snap->final, cancel);
      s_.times.reconstruct += secondsSince(start);
      if (cancel && cancel->load()) return snap;  // the method is being replaced: dropped
      lastReconstruction_ = std::move(r);
      reconstructedAtRound_ = s_.rounds;
    }
    recon::DenoiseResult& r = *lastReconstruction_;
    // Its error estimate map is not made: the allocation error below takes the same kind (a
    // pass over the film and a percentile, for a map that would be replaced).
    addFilterScaleMap(*snap, r, config_.denoise);
    // The output moves into the snapshot; of the rest only the scale (for inspect) is read
    // again.
    snap->reconstructed = std::move(r.output);
    r.output = Image{};
    std::vector<float>().swap(r.mseEstimate);
    std::vector<float>().swap(r.varianceRatio);
  }
  snap->raw = film_.meanImage();
  if (snap->reconstructed.empty()) snap->reconstructed = snap->raw;
  if (s_.rounds > 0 && snap->withMaps) {
    // What ranks the pixels: the raw relMSE estimate scaled by the network's bias.
    std::vector<float> e = allocationError();
    const float top = std::max(1e-6f, percentileOf(e, 0.99f));
    snap->addMap(maps::ErrorEstimate, "allocation error (raw relMSE x (1 + w bias))", std::move(e),
                 MapLegend::sequential(0.0f, top));
  }
  addFilmMaps(*snap, film_);
  if (usesNetworks() && snap->withMaps) {
    std::vector<float> er(s_.pixelCount), prediction(3 * s_.pixelCount);
    for (size_t p = 0; p < s_.pixelCount; ++p) {
      const PixelState& px = s_.pixel(p);
      er[p] = px.er;
      for (int k = 0; k < 3; ++k) prediction[3 * p + size_t(k)] = px.prediction[k];
    }
    snap->addMap(maps::Prediction, "prediction I'", std::move(prediction), MapLegend::rgb());
    const float erTop = std::max(1e-3f, finiteMax(er));
    snap->addMap(maps::NetworkError, "er", std::move(er), MapLegend::sequential(0.0f, erTop));
  }
  if (nets_) {
    snap->addStat("network_pixels", double(nets_->correctingPixels()));
    snap->addStat("network_fits", double(nets_->fits()));
    if (snap->withMaps && !usesNetworks()) {
      // Where a network corrects: its held-out error over the pixel's variance (0: none).
      std::vector<float> heldOut = nets_->heldOutMap(), corrects = nets_->trainedMap();
      for (size_t p = 0; p < s_.pixelCount; ++p) heldOut[p] *= corrects[p];
      snap->addMap(maps::NetworkError, "network held-out error / variance (0: no network)",
                   std::move(heldOut), MapLegend::sequential(0.0f, 1.0f));
      snap->addMap(maps::Networks, "networks", nets_->roleMap(),
                   MapLegend::categorical(NetRecon::roleLabels()));
    }
  }
  addSelectedMap(*snap, s_.selected);
  std::vector<uint32_t> kept(s_.pixelCount);
  for (size_t p = 0; p < s_.pixelCount; ++p) kept[p] = film_[p].count;
  addSampleCountMaps(*snap, kept, drawn_);
  for (uint32_t c : kept) snap->keptSamples += c;
  s_.reportCounts(*snap, seconds());
  return snap;
}

PixelInspection ConsistentMethod::inspect(int x, int y) const {
  PixelInspection in = startInspection(x, y, s_.width, s_.height, s_.rounds, "bp");
  if (!in.valid) return in;
  const size_t p = size_t(y) * s_.width + x;
  const FilmPixel& f = film_[p];
  in.estimate = vec3(film_.estimate(p));
  in.kept = f.count;
  in.traced = drawn_[p];
  in.addedLastRound = addedLastRound_[p];
  char line[200];
  const vec3 v = f.varianceOfMean();
  std::snprintf(line, sizeof line, "variance of the mean %.3g %.3g %.3g", v.x, v.y, v.z);
  in.addValue("variance of the mean", {v.x, v.y, v.z}, line);
  // (Without the noise threshold no estimate is kept: 0 at 0 samples.)
  const bool estimated = !errorAtReconstruction_.empty();
  const float e = estimated ? errorAtReconstruction_[p] : 0.0f;
  std::snprintf(line, sizeof line, "filtered relMSE %.3g (estimated at %u samples)", e,
                estimated ? countAtReconstruction_[p] : 0u);
  in.addValue("filtered relMSE", {e}, line, maps::ErrorEstimate);
  if (lastReconstruction_) {
    const int scale = lastReconstruction_->scale[p];
    const int radius = scale == 0 ? 0 : config_.denoise.radii[size_t(scale - 1)];
    std::snprintf(line, sizeof line, "filter window %s%d",
                  scale == 0 ? "identity, r=" : "r=", radius);
    in.addValue("filter window", {float(scale), float(radius)}, line, maps::FilterScale);
  }
  if (usesNetworks()) {
    const PixelState& px = s_.pixel(p);
    std::snprintf(line, sizeof line, "network bias %.3f: error x %.2f; er %.3f", px.bias,
                  networkFactor(p), px.er);
    in.addValue("bias", {px.bias, networkFactor(p)}, line);
    const vec3 net = px.prediction;
    std::snprintf(line, sizeof line, "net  I'  %.3f %.3f %.3f", net.x, net.y, net.z);
    in.addValue("I'", {net.x, net.y, net.z}, line, maps::Prediction);
  }
  if (nets_) {
    const NetRecon::PixelNetwork net = nets_->pixelNetwork(p);
    if (!net.trained)
      std::snprintf(line, sizeof line, "no network (%u samples kept for the neighbours')",
                    net.kept);
    else
      std::snprintf(line, sizeof line, "network %s: held-out error %.2f of the variance",
                    net.corrects ? "corrects" : "does not correct", net.heldOut);
    in.addValue("network", {float(net.corrects), net.heldOut}, line, maps::NetworkError);
    if (net.trained) {
      std::snprintf(line, sizeof line, "  fitted on %u neighbours' samples, tested on its %u",
                    net.samples, net.kept);
      in.addValue("network samples", {float(net.samples), float(net.kept)}, line);
      std::string inputs = "  inputs:";
      for (const char* name : nets_->inputNames()) inputs += std::string(" ") + name + ",";
      inputs.back() = ' ';
      inputs += "(each centred on 0)";
      in.addValue("network inputs", {float(nets_->inputs())}, inputs);
      std::snprintf(line, sizeof line, "  its mean %.3g %.3g %.3g (demodulated)", net.mean.x,
                    net.mean.y, net.mean.z);
      in.addValue("network mean", {net.mean.x, net.mean.y, net.mean.z}, line);
    }
    in.fit = nets_->fitAlong(p);
  }
  char reason[200];
  if (s_.rounds <= int(coarseSteps_.size()))
    std::snprintf(reason, sizeof reason, "coarse pass: %u samples", f.count);
  else if (in.addedLastRound > 0)
    std::snprintf(reason, sizeof reason,
                  "got %u samples last round: its estimated error x samples ranks it",
                  in.addedLastRound);
  else
    std::snprintf(reason, sizeof reason,
                  "no samples last round: its estimated error is low enough for now");
  in.reason = reason;
  return in;
}

}  // namespace

}  // namespace penumbra::bp

namespace penumbra {

std::unique_ptr<ProgressiveMethod> makeBpConsistentMethod(const PreparedScene& prepared,
                                                          const RunShape& shape,
                                                          const BpConsistentConfig& config) {
  requireValid({shape, MethodConfig(bpConsistentMethod(), config)});
  return std::make_unique<bp::ConsistentMethod>(prepared, shape, config);
}

}  // namespace penumbra
