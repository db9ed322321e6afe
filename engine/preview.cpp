#include "engine/preview.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

namespace penumbra {

namespace {

class PreviewMethod final : public ProgressiveMethod {
 public:
  PreviewMethod(const PreparedScene& prepared, uint64_t seed, int block)
      : prepared_(prepared), seed_(seed), block_(std::max(1, block)) {}

  void runRound(const std::atomic<bool>* cancel) override {
    if (done_) return;
    const auto start = std::chrono::steady_clock::now();
    const int w = prepared_.scene.settings.width, h = prepared_.scene.settings.height;
    const int bw = (w + block_ - 1) / block_, bh = (h + block_ - 1) / block_;
    image_ = Image(w, h);
    tbb::parallel_for(tbb::blocked_range<int>(0, bh), [&](const tbb::blocked_range<int>& rows) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      enableFlushToZero();
      PixelSampler sampler(SamplerKind::LowDiscrepancy, seed_, 1);
      PathCounters counters;
      for (int by = rows.begin(); by < rows.end(); ++by) {
        for (int bx = 0; bx < bw; ++bx) {
          const int x0 = bx * block_, y0 = by * block_;
          const int x1 = std::min(w, x0 + block_), y1 = std::min(h, y0 + block_);
          CameraSample cs;
          cs.imageX = 0.5f * float(x0 + x1);
          cs.imageY = 0.5f * float(y0 + y1);
          sampler.startSample(x0, y0, 0);
          vec3 L = traceRadiance(prepared_, cs, sampler, counters);
          if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z))) L = vec3(0.0f);
          for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) image_.at(x, y) = L;
        }
      }
      rays_ += counters.rays;
    });
    if (cancel && cancel->load()) return;
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    done_ = true;
  }

  bool done() const override { return done_; }
  int roundsDone() const override { return done_ ? 1 : 0; }
  size_t memoryBytes() const override { return image_.pixels.capacity() * sizeof(vec3); }

  std::shared_ptr<Snapshot> snapshot(bool) override {
    auto snap = std::make_shared<Snapshot>();
    snap->method = "preview";
    snap->round = roundsDone();
    snap->width = image_.width;
    snap->height = image_.height;
    snap->raw = image_;
    snap->reconstructed = image_;
    snap->rays = rays_;
    snap->times.trace = seconds_;
    snap->seconds = seconds_;
    return snap;
  }

  PixelInspection inspect(int, int) const override { return {}; }

 private:
  const PreparedScene& prepared_;
  uint64_t seed_;
  int block_;
  bool done_ = false;
  Image image_;
  std::atomic<uint64_t> rays_{0};
  double seconds_ = 0;
};

class ChainedMethod final : public ProgressiveMethod {
 public:
  ChainedMethod(std::unique_ptr<ProgressiveMethod> first,
                std::function<std::unique_ptr<ProgressiveMethod>()> next)
      : first_(std::move(first)), next_(std::move(next)) {}

  void runRound(const std::atomic<bool>* cancel) override {
    if (!first_->done()) {
      first_->runRound(cancel);
      return;
    }
    if (!second_) {
      second_ = next_();
      second_->setInspectedPixel(inspectedX_, inspectedY_);
    }
    second_->runRound(cancel);
  }
  bool done() const override { return second_ && second_->done(); }
  int roundsDone() const override {
    return first_->roundsDone() + (second_ ? second_->roundsDone() : 0);
  }
  size_t memoryBytes() const override {
    return first_->memoryBytes() + (second_ ? second_->memoryBytes() : 0);
  }
  std::shared_ptr<Snapshot> snapshot(bool reconstructImage) override {
    return current().snapshot(reconstructImage);
  }
  void setInspectedPixel(int x, int y) override {
    inspectedX_ = x;
    inspectedY_ = y;
    first_->setInspectedPixel(x, y);
    if (second_) second_->setInspectedPixel(x, y);
  }
  PixelInspection inspect(int x, int y) const override {
    return second_ ? second_->inspect(x, y) : first_->inspect(x, y);
  }

 private:
  ProgressiveMethod& current() const {
    return second_ && second_->roundsDone() > 0 ? *second_ : *first_;
  }
  std::unique_ptr<ProgressiveMethod> first_;
  std::function<std::unique_ptr<ProgressiveMethod>()> next_;
  std::unique_ptr<ProgressiveMethod> second_;
  int inspectedX_ = -1, inspectedY_ = -1;
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makePreviewMethod(const PreparedScene& prepared, uint64_t seed,
                                                     int block) {
  return std::make_unique<PreviewMethod>(prepared, seed, block);
}

std::unique_ptr<ProgressiveMethod> chainMethods(
    std::unique_ptr<ProgressiveMethod> first,
    std::function<std::unique_ptr<ProgressiveMethod>()> next) {
  return std::make_unique<ChainedMethod>(std::move(first), std::move(next));
}

}  // namespace penumbra
