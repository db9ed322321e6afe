#include "methods/ld.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

namespace penumbra {

using namespace method;

LdMethod::LdMethod(const PreparedScene& prepared, const RunShape& shape)
    : prepared_(prepared),
      shape_(shape),
      schedule_(shape, 1, 0, kLdBatchRounds),
      width_(prepared.scene.settings.width),
      height_(prepared.scene.settings.height),
      pixelCount_(size_t(width_) * height_),
      mean_(pixelCount_, glm::dvec3(0.0)),
      m2_(pixelCount_, glm::dvec3(0.0)),
      count_(pixelCount_, 0) {
  if (const std::string problem = shape.validate(); !problem.empty())
    throw std::invalid_argument(problem);
  start_ = Clock::now();
}

void LdMethod::runRound(const std::atomic<bool>* cancel) {
  if (done()) return;
  const auto start = Clock::now();
  const uint32_t first = drawn_;
  const uint32_t last = first + uint32_t(schedule_.roundBudget(drawn_, rounds_));
  // A batch run's set is its spp; the open-ended stream uses blocks of 64.
  const uint32_t setSize = shape_.openEnded ? 64u : uint32_t(shape_.spp);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixelCount_, kPixelGrain),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (cancel && cancel->load(std::memory_order_relaxed)) return;
                      TraceChunk chunk(counters_, shape_.sampler, shape_.seed, setSize);
                      PixelSampler& sampler = chunk.sampler;
                      for (size_t p = range.begin(); p < range.end(); ++p) {
                        const int px = int(p % width_), py = int(p / width_);
                        for (uint32_t i = first; i < last; ++i) {
                          sampler.startSample(px, py, i);
                          const vec3 L = traceRadiance(
                              prepared_,
                              sampler.cameraSample(prepared_.usesLens, prepared_.usesTime), sampler,
                              chunk.counters);
                          if (!isFinite(L)) {
                            ++chunk.nonFinite;
                            continue;
                          }
                          // Welford's running mean and variance, in sample order.
                          ++count_[p];
                          const glm::dvec3 d = glm::dvec3(L) - mean_[p];
                          mean_[p] += d / double(count_[p]);
                          m2_[p] += d * (glm::dvec3(L) - mean_[p]);
                        }
                      }
                    });
  if (cancel && cancel->load()) return;
  lastAdded_ = last - drawn_;
  drawn_ = last;
  ++rounds_;
  times_.trace += secondsSince(start);
}

size_t LdMethod::memoryBytes() const {
  return (mean_.capacity() + m2_.capacity()) * sizeof(glm::dvec3) +
         count_.capacity() * sizeof(uint32_t);
}

Image LdMethod::varianceOfMean() const {
  Image v(width_, height_);
  for (size_t p = 0; p < pixelCount_; ++p) {
    const uint32_t n = count_[p];
    v.pixels[p] = n > 1 ? vec3(m2_[p] / (double(n - 1) * n)) : vec3(0.0f);
  }
  return v;
}

PixelInspection LdMethod::inspect(int x, int y) const {
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

std::shared_ptr<Snapshot> LdMethod::snapshot(bool, const std::atomic<bool>*) {
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

std::unique_ptr<ProgressiveMethod> makeLdMethod(const PreparedScene& prepared,
                                                const RunShape& shape, const LdConfig&) {
  return std::make_unique<LdMethod>(prepared, shape);
}

}  // namespace penumbra
