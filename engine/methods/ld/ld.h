// The plain low-discrepancy renderer as a progressive method: every round adds the same
// number of samples to every pixel (box filter, per-pixel mean in sample order). It is the
// baseline the adaptive methods are compared with, the viewer's `--method ld`, and, run to
// the end, `renderImage` (render.h) and the references.
#pragma once

#include "core/clock.h"
#include "methods/film.h"
#include "methods/method.h"
#include "methods/params.h"
#include "methods/progressive.h"
#include "methods/recon/denoise.h"
#include "methods/run_shape.h"
#include "methods/schedule.h"
#include "methods/trace_chunk.h"
#include "trace/integrator.h"

#include <glm/vec3.hpp>

#include <memory>
#include <vector>

namespace penumbra {

// LD samples every pixel alike; its one choice is whether the image it shows is the box
// filter's mean or the consistent reconstruction of its film (`ld:filtered`, the ablation
// that separates what adaptive sampling adds from what the filter adds).
struct LdConfig {
  bool filter = false;
  recon::DenoiseConfig denoise;
};
const ParamTable<LdConfig>& ldParams();
// The method's descriptor (methods/method.h): `ld`, its `filtered` preset, its maps.
const MethodDescriptor& ldMethod();

// A batch run spreads its spp over this many rounds (fewer when spp is smaller), so that a
// long render reports progress and can be cancelled between rounds; the image does not
// depend on it, as each pixel sums its samples in sequence order.
constexpr int kLdBatchRounds = 16;

class LdMethod final : public ProgressiveMethod {
 public:
  // Throws std::invalid_argument on a bad shape; the scene must outlive the method.
  LdMethod(const PreparedScene& prepared, const RunShape& shape, const LdConfig& config = {});

  void runRound(const std::atomic<bool>* cancel) override;
  int roundsDone() const override { return rounds_; }
  double budgetShare() const override { return schedule_.share(drawn_); }
  size_t memoryBytes() const override;
  PixelInspection inspect(int x, int y) const override;
  std::shared_ptr<Snapshot> snapshot(bool reconstructImage,
                                     const std::atomic<bool>* cancel) override;
  double estimatedError() const override;
  Image rawVarianceOfMean() const override { return varianceOfMean(); }
  // Samples every pixel has drawn so far.
  uint32_t samplesPerPixel() const { return drawn_; }
  // Per channel: the unbiased sample variance of each pixel over its sample count.
  Image varianceOfMean() const;
  // Renders only the pixels marked 1 (one per pixel, row-major); the others get no samples.
  // Each rendered pixel is exactly what it is in a run of every pixel.
  void renderOnly(std::vector<uint8_t> mask);

 protected:
  bool budgetSpent() const override { return schedule_.finished(drawn_); }

 private:
  const PreparedScene& prepared_;
  LdConfig config_;
  RoundSchedule schedule_;  // per pixel: every pixel gets the same samples
  int width_, height_;
  size_t pixelCount_;
  Film film_;
  // With a noise threshold: each pixel's estimated relMSE, and the filtered estimate it
  // follows (made at drawnAtError_ samples).
  std::vector<float> pixelError_, errorAtReconstruction_;
  std::vector<uint32_t> countAtReconstruction_;
  std::vector<uint8_t> pixelMask_;  // empty: every pixel
  uint32_t drawnAtError_ = 0;
  void updatePixelErrors(const std::atomic<bool>* cancel);
  // A pixel's error has an estimate once it has two samples: until every pixel has been drawn
  // twice (no pixel stops before that), a noise threshold cannot call it converged. One sample
  // has no variance, and its zero estimate once stopped every such run after its first round.
  bool errorKnown() const { return drawn_ >= 2; }
  uint32_t drawn_ = 0;
  uint32_t lastAdded_ = 0;
  int rounds_ = 0;
  method::Counters counters_;
  PhaseTimes times_;
};

std::unique_ptr<ProgressiveMethod> makeLdMethod(const PreparedScene& prepared,
                                                const RunShape& shape, const LdConfig& config = {});

}  // namespace penumbra
