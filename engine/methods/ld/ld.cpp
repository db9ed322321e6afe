#include "methods/ld/ld.h"

#include "methods/factory.h"
#include "methods/film_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

namespace penumbra {

using namespace method;

const ParamTable<LdConfig>& ldParams() {
  static const ParamTable<LdConfig> table = [] {
    ParamTable<LdConfig> t;
    t.group("Low discrepancy")
        .toggle(
            "filter", "filtered", "Show the consistent reconstruction of the film", "--filter",
            [](auto& c) -> auto& { return c.filter; })
        .include(
            recon::denoiseParams(), [](auto& c) -> auto& { return c.denoise; });
    return t;
  }();
  return table;
}

LdMethod::LdMethod(const PreparedScene& prepared, const RunShape& shape, const LdConfig& config)
    : ProgressiveMethod(shape),
      prepared_(prepared),
      config_(config),
      schedule_(shape, 1, 0, kLdBatchRounds),
      width_(prepared.scene.settings.width),
      height_(prepared.scene.settings.height),
      pixelCount_(size_t(width_) * height_),
      film_(width_, height_) {
  if (const std::string problem = shape.validate(); !problem.empty())
    throw std::invalid_argument(problem);
}

void LdMethod::runRound(const std::atomic<bool>* cancel) {
  if (done()) return;
  const auto start = Clock::now();
  const uint32_t first = drawn_;
  const uint32_t last = first + uint32_t(schedule_.roundBudget(drawn_, rounds_));
  // A batch run's set is its spp; the open-ended stream uses blocks of 64. Only a batch at a
  // power-of-two spp with no noise threshold draws every block whole: the other runs stop
  // pixels inside a block, where the nested order keeps them stratified.
  const uint32_t setSize = shape_.openEnded ? 64u : uint32_t(shape_.spp);
  const bool wholeBlocks =
      !shape_.openEnded && !(shape_.noiseThreshold > 0) && roundUpPowerOfTwo(setSize) == setSize;
  const BlockOrder order = wholeBlocks ? BlockOrder::Shuffled : BlockOrder::Nested;
  updatePixelErrors(cancel);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount_, kPixelGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (cancel && cancel->load(std::memory_order_relaxed)) return;
                      TraceChunk chunk(counters_, shape_.sampler, shape_.seed, setSize, order);
                      PixelSampler& sampler = chunk.sampler;
                      for (size_t p = range.begin(); p < range.end(); ++p) {
                        // Below the noise threshold: converged, no more samples.
                        if (!pixelError_.empty() && shape_.converged(pixelError_[p])) continue;
                        if (!pixelMask_.empty() && !pixelMask_[p]) continue;  // another shard's
                        const int px = int(p % width_), py = int(p / width_);
                        for (uint32_t i = first; i < last; ++i) {
                          sampler.startSample(px, py, i);
                          PathFeatures features;
                          const vec3 L = traceRadiance(
                              prepared_,
                              sampler.cameraSample(prepared_.usesLens, prepared_.usesTime), sampler,
                              chunk.counters, &features);
                          if (!isFinite(L)) {
                            ++chunk.nonFinite;
                            continue;
                          }
                          film_[p].add(L, features);  // in sample order
                        }
                      }
                    });
  if (cancel && cancel->load()) return;
  lastAdded_ = last - drawn_;
  drawn_ = last;
  ++rounds_;
  times_.trace += secondsSince(start);
}

void LdMethod::updatePixelErrors(const std::atomic<bool>* cancel) {
  if (!(shape_.noiseThreshold > 0) || !errorKnown()) return;
  if (!config_.filter) {
    pixelError_ = rawRelativeError(film_);
    return;
  }
  // The filtered estimate is redone once the samples grew 1.5x; in between it falls as 1/n.
  if (pixelError_.empty() || double(drawn_) >= 1.5 * double(drawnAtError_)) {
    const auto start = Clock::now();
    recon::DenoiseResult r = reconstructFilm(film_, config_.denoise, cancel);
    times_.reconstruct += secondsSince(start);
    if (cancel && cancel->load()) return;  // the round's method is being replaced
    errorAtReconstruction_ = relativeError(r, film_);
    countAtReconstruction_.resize(pixelCount_);
    for (size_t p = 0; p < pixelCount_; ++p) countAtReconstruction_[p] = film_[p].count;
    drawnAtError_ = drawn_;
  }
  pixelError_.resize(pixelCount_);
  for (size_t p = 0; p < pixelCount_; ++p)
    pixelError_[p] = errorAtReconstruction_[p] * float(std::max(1u, countAtReconstruction_[p])) /
                     float(std::max(1u, film_[p].count));
}

double LdMethod::estimatedError() const {
  if (!errorKnown()) return NAN;
  if (!pixelError_.empty()) return meanOf(pixelError_);
  return config_.filter ? NAN : meanOf(rawRelativeError(film_));
}

size_t LdMethod::memoryBytes() const { return film_.memoryBytes(); }

Image LdMethod::varianceOfMean() const { return film_.varianceOfMeanImage(); }

void LdMethod::renderOnly(std::vector<uint8_t> mask) {
  if (mask.size() != pixelCount_)
    throw std::invalid_argument("LdMethod::renderOnly: the mask is not one value per pixel");
  pixelMask_ = std::move(mask);
}

PixelInspection LdMethod::inspect(int x, int y) const {
  PixelInspection in = startInspection(x, y, width_, height_, rounds_, "ld");
  if (!in.valid) return in;
  const size_t p = size_t(y) * width_ + x;
  in.estimate = vec3(film_[p].mean);
  in.kept = film_[p].count;
  in.traced = drawn_;
  in.addedLastRound = lastAdded_;
  in.reason = "low-discrepancy sampling: every pixel gets the same samples each round";
  return in;
}

std::shared_ptr<Snapshot> LdMethod::snapshot(bool reconstructImage,
                                             const std::atomic<bool>* cancel) {
  auto snap = std::make_shared<Snapshot>();
  snap->withMaps = mapsWanted();
  snap->method = config_.filter ? "ld:filtered" : "ld";
  snap->round = rounds_;
  snap->final = done();
  snap->width = width_;
  snap->height = height_;
  snap->raw = film_.meanImage();
  snap->reconstructed = snap->raw;
  if (config_.filter && reconstructImage && rounds_ > 0) {
    const auto start = Clock::now();
    recon::DenoiseResult r =
        reconstructPicture(film_, config_.denoise, double(drawn_), snap->final, cancel);
    times_.reconstruct += secondsSince(start);
    if (!(cancel && cancel->load())) {  // (cancelled: the snapshot is dropped)
      if (snap->withMaps) addReconstructionMaps(*snap, r, config_.denoise, relativeError(r, film_));
      snap->reconstructed = std::move(r.output);
    }
  }
  addFilmMaps(*snap, film_);
  std::vector<uint32_t> kept(pixelCount_);
  for (size_t p = 0; p < pixelCount_; ++p) kept[p] = film_[p].count;
  if (snap->withMaps) {  // (the constant maps are not even made without)
    addSelectedMap(*snap, std::vector<uint8_t>(pixelCount_, 1));
    addSampleCountMaps(*snap, kept, std::vector<uint32_t>(pixelCount_, drawn_));
  }
  for (uint32_t c : kept) snap->keptSamples += c;
  snap->tracedSamples = uint64_t(drawn_) * pixelCount_;
  snap->rays = counters_.rays;
  snap->nonFiniteSamples = counters_.nonFinite;
  snap->times = times_;
  snap->seconds = seconds();
  return snap;
}

std::unique_ptr<ProgressiveMethod> makeLdMethod(const PreparedScene& prepared,
                                                const RunShape& shape, const LdConfig& config) {
  return makeValidated<LdMethod>(ldMethod(), prepared, shape, config);
}

const MethodDescriptor& ldMethod() {
  static const MethodDescriptor descriptor([] {
    MethodDefinition<LdConfig> d;
    d.name = "ld";
    d.description = "Low discrepancy (box filter)";
    d.params = &ldParams();
    d.presets = {{"filtered",
                  "the consistent reconstruction of the film: the ablation that separates what "
                  "adaptive sampling adds from what the filter adds",
                  [](LdConfig& c) { c.filter = true; }}};
    d.maps = {&maps::ErrorEstimate, &maps::Selected, &maps::FilterScale, &maps::SampleCount,
              &maps::TracedCount,   &maps::Albedo,   &maps::Normal,      &maps::Depth,
              &maps::Emission,      &maps::RawError};
    d.abilities = [](const LdConfig& c) { return MethodAbilities{true, c.filter, false, true}; };
    d.check = [](const LdConfig& c, const RunShape&) { return recon::validate(c.denoise); };
    d.make = construct<LdMethod, LdConfig>;
    return d;
  }());
  return descriptor;
}

}  // namespace penumbra
