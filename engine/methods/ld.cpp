#include "methods/ld.h"

#include "methods/common.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

namespace penumbra {

namespace {

using namespace method;

class LdMethod final : public ProgressiveMethod {
 public:
  LdMethod(const PreparedScene& prepared, const LdConfig& config)
      : prepared_(prepared),
        config_(config),
        width_(prepared.scene.settings.width),
        height_(prepared.scene.settings.height),
        pixelCount_(size_t(width_) * height_),
        mean_(pixelCount_, glm::dvec3(0.0)),
        count_(pixelCount_, 0) {
    if (!config.openEnded && config.spp < 1) throw std::invalid_argument("spp must be at least 1");
    if (config.roundSpp < 1) throw std::invalid_argument("round spp must be at least 1");
    start_ = Clock::now();
  }

  void runRound(const std::atomic<bool>* cancel) override {
    if (done()) return;
    const auto start = Clock::now();
    const uint32_t first = drawn_;
    uint32_t last = first + uint32_t(config_.roundSpp);
    const int target = config_.openEnded ? config_.maxSpp : config_.spp;
    if (target > 0) last = std::min(last, uint32_t(target));
    // renderImage uses the spp as set size; the open-ended stream uses blocks of 64.
    const uint32_t setSize = config_.openEnded ? 64u : uint32_t(config_.spp);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount_, kPixelGrain),
                      [&](const tbb::blocked_range<size_t>& range) {
                        if (cancel && cancel->load(std::memory_order_relaxed)) return;
                        TraceChunk chunk(counters_, config_.sampler, config_.seed, setSize);
                        PixelSampler& sampler = chunk.sampler;
                        for (size_t p = range.begin(); p < range.end(); ++p) {
                          const int px = int(p % width_), py = int(p / width_);
                          for (uint32_t i = first; i < last; ++i) {
                            sampler.startSample(px, py, i);
                            const vec3 L = traceRadiance(
                                prepared_,
                                sampler.cameraSample(prepared_.usesLens, prepared_.usesTime),
                                sampler, chunk.counters);
                            if (!isFinite(L)) {
                              ++chunk.nonFinite;
                              continue;
                            }
                            // Welford's running mean, in sample order, as renderImage does.
                            ++count_[p];
                            mean_[p] += (glm::dvec3(L) - mean_[p]) / double(count_[p]);
                          }
                        }
                      });
    if (cancel && cancel->load()) return;
    lastAdded_ = last - drawn_;
    drawn_ = last;
    ++rounds_;
    times_.trace += secondsSince(start);
  }

  bool done() const override {
    const int target = config_.openEnded ? config_.maxSpp : config_.spp;
    return target > 0 && drawn_ >= uint32_t(target);
  }
  int roundsDone() const override { return rounds_; }
  size_t memoryBytes() const override {
    return mean_.capacity() * sizeof(glm::dvec3) + count_.capacity() * sizeof(uint32_t);
  }

  PixelInspection inspect(int x, int y) const override {
    PixelInspection in = startInspection(x, y, width_, height_, rounds_, "ld");
    if (!in.valid) return in;
    const size_t p = size_t(y) * width_ + x;
    in.estimate = vec3(mean_[p]);
    in.kept = count_[p];
    in.traced = drawn_;
    in.addedLastRound = lastAdded_;
    in.reason = "low-discrepancy sampling: every pixel gets the same samples each round";
    return in;
  }

  std::shared_ptr<Snapshot> snapshot(bool, const std::atomic<bool>*) override {
    auto snap = std::make_shared<Snapshot>();
    snap->method = "ld";
    snap->round = rounds_;
    snap->final = done();
    snap->width = width_;
    snap->height = height_;
    snap->raw = Image(width_, height_);
    for (size_t p = 0; p < pixelCount_; ++p) snap->raw.pixels[p] = vec3(mean_[p]);
    snap->reconstructed = snap->raw;
    addSelectedMap(*snap, std::vector<uint8_t>(pixelCount_, 1));
    addSampleCountMaps(*snap, count_, std::vector<uint32_t>(pixelCount_, drawn_));
    for (uint32_t c : count_) snap->keptSamples += c;
    snap->tracedSamples = uint64_t(drawn_) * pixelCount_;
    snap->rays = counters_.rays;
    snap->nonFiniteSamples = counters_.nonFinite;
    snap->times = times_;
    snap->seconds = secondsSince(start_);
    return snap;
  }

 private:
  const PreparedScene& prepared_;
  LdConfig config_;
  int width_, height_;
  size_t pixelCount_;
  std::vector<glm::dvec3> mean_;
  std::vector<uint32_t> count_;
  uint32_t drawn_ = 0;
  uint32_t lastAdded_ = 0;
  int rounds_ = 0;
  Counters counters_;
  PhaseTimes times_;
  Clock::time_point start_;
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makeLdMethod(const PreparedScene& prepared,
                                                const LdConfig& config) {
  return std::make_unique<LdMethod>(prepared, config);
}

}  // namespace penumbra
