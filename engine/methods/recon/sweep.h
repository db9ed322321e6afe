// The filter bank of methods/recon/denoise.h in one sweep over the offsets of its largest
// window: each offset's weight is computed once per pixel and accumulated into every scale
// whose window holds it; then SURE per scale. Internal to methods/recon.
#pragma once

#include "core/image.h"
#include "core/large_pages.h"

#include <array>
#include <atomic>
#include <cstddef>
#include <span>
#include <vector>

namespace penumbra::recon::detail {

// A plane of floats, one per pixel (or a row buffer). Each plane starts at its own offset
// within a 4 KiB page: planes of a power-of-two size would otherwise all start at the same
// offset, and the sweep, which streams through a dozen of them at once, would keep evicting
// its own cache lines (4K aliasing). The offset changes only addresses, never results.
class Plane {
 public:
  void assign(size_t count, float value);
  size_t size() const { return count_; }
  float* data() { return storage_.data() + skew_; }
  const float* data() const { return storage_.data() + skew_; }
  float& operator[](size_t i) { return data()[i]; }
  const float& operator[](size_t i) const { return data()[i]; }
  float* begin() { return data(); }
  float* end() { return data() + count_; }
  const float* begin() const { return data(); }
  const float* end() const { return data() + count_; }

 private:
  std::vector<float, LargePageAllocator<float>> storage_;  // (core/large_pages.h)
  size_t skew_ = 0, count_ = 0;
};
using Planes3 = std::array<Plane, 3>;

// A first-hit feature as the sweep reads it, per pixel: its components, the variance of their
// mean summed over the components, and 1 / (k_f^2 max(tau, Var_p, |grad_p|^2)) (§3).
struct FeaturePlanes {
  int components = 0;
  Planes3 value;
  Plane variance;
  Plane inverseScale;
};

// What the sweep filters, in the filtered domain ((mean - emission) / demod); every plane has
// width * height entries and a pixel that is not valid holds zeros.
struct SweepInput {
  int width = 0, height = 0;
  // The rows filtered, [firstRow, lastRow) (lastRow 0: to the last); the others are read only
  // as neighbours. The maps sweepScales returns hold these rows only.
  int firstRow = 0, lastRow = 0;
  int rowEnd() const { return lastRow > 0 ? lastRow : height; }
  // 1: stream 0 is the mean, weighted by its own colours. 2: cross-filtering, stream 0 is half
  // A weighted by the colours of half B and stream 1 the reverse.
  int streams = 1;
  std::array<Planes3, 2> value;
  Planes3 variance;  // of one stream's values: V of the mean, or 2V for a half
  Plane valid;       // 1 or 0
  std::vector<FeaturePlanes> features;
  Planes3 demod, emission;  // back to linear units: output = filtered * demod + emission
};

struct SweepConfig {
  std::vector<int> radii;
  float k = 0.7f, alpha = 1.0f;
  int patchRadius = 1;
  int denseRadius = 4;
};

// One candidate's per-pixel results in linear units.
struct ScaleMaps {
  LargeVector<vec3> output;
  LargeVector<float> mse;            // estimated squared error, summed over channels
  LargeVector<float> varianceRatio;  // variance of the output / variance of the mean, in [0, 1]
};

// sum_c x_c d_c^2: a per-channel squared error or variance in the filtered domain, in linear
// units. The identity's estimate goes through the same arithmetic as the filters', so that a
// filter which keeps only the centre pixel ties with it exactly.
inline float toLinearSum(float x0, float x1, float x2, float d0, float d1, float d2) {
  return x0 * d0 * d0 + x1 * d1 * d1 + x2 * d2 * d2;
}

// A block's sums per stream, ring and pixel: sum w, sum w y_c (3), sum w^2 sigma^2_c (3).
inline constexpr int kSumsPerStream = 7;

// One offset of the sweep (methods/recon/sweep.cpp).
struct Offset {
  int dx, dy;
  int ring;      // index of the smallest radius whose window holds the offset
  float factor;  // weight of the offset: 1, or the ring's factor beyond denseRadius
};

// The block sweep of rows [first * blockRows, last * blockRows) (clipped to the image), once
// per instruction set (sweep_block.inc); false when cancelled.
using SweepBlocks = bool (*)(const SweepInput& in, const SweepConfig& config,
                             std::span<const Offset> offsets, int blockRows, int first, int last,
                             std::vector<ScaleMaps>& out, const std::atomic<bool>* cancel);
namespace sweep_sse {
bool sweepBlocks(const SweepInput&, const SweepConfig&, std::span<const Offset>, int, int, int,
                 std::vector<ScaleMaps>&, const std::atomic<bool>*);
}
namespace sweep_avx2 {
bool sweepBlocks(const SweepInput&, const SweepConfig&, std::span<const Offset>, int, int, int,
                 std::vector<ScaleMaps>&, const std::atomic<bool>*);
}
namespace sweep_avx512 {
bool sweepBlocks(const SweepInput&, const SweepConfig&, std::span<const Offset>, int, int, int,
                 std::vector<ScaleMaps>&, const std::atomic<bool>*);
}

// One map per radius, of the rows [in.firstRow, in.rowEnd()). Pixels that are not valid get
// output 0, mse +inf and ratio 1.
std::vector<ScaleMaps> sweepScales(const SweepInput& in, const SweepConfig& config,
                                   const std::atomic<bool>* cancel);

}  // namespace penumbra::recon::detail
