// The filter bank's sweep (methods/recon/sweep.h): RECONSTRUCTION.md §2 (colour weights), §3
// (feature weights) and §4 (SURE), for every scale of the bank at once.
//
// The spatial falloff of every scale is a box: all offsets of its square window count alike
// (as in the NL-means filter of Rousselle et al. 2012). The window of radius r_k is then the
// union of the rings r_{k-1} < max(|dx|, |dy|) <= r_k, so each offset's weight is added into
// the sums of its one ring, and a scale's sums are the centre's plus those of its rings.
//
// Work is split into blocks of rows. For each offset s of the largest window, a block computes
// the per-pixel colour distance of every pair (p, p + s) over its rows and patchRadius rows
// above and below, box-filters it over the patch (separable sums: the cost grows with the
// patch's radius, not its area; running sums would be O(1) but lose the small distances next
// to a huge one), turns it with the feature distance into one weight per pixel and adds that
// into its ring's sums. Every pixel's sums are taken in the same offset order whatever the
// block or thread, so the output does not depend on either.
#include "methods/recon/sweep.h"

#include "methods/recon/sweep_kernels.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <span>

#if defined(__SSE__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

namespace penumbra::recon::detail {
namespace {

// Rows per task, at most; each task recomputes patchRadius rows of distances above and below.
constexpr int kMaxBlockRows = 16;
constexpr int kMinBlockRows = 4;
// Bytes of a block's sums that should stay in a core's cache.
constexpr size_t kSumsBudget = size_t(1) << 20;
// Sums per stream, ring and pixel: sum w, sum w y_c (3), sum w^2 sigma^2_c (3).
constexpr int kSums = 7;

// Denormal numbers (products of tiny weights) are very slow on x86; the sweep flushes them to
// zero, the same in every thread, and restores the caller's mode afterwards.
class FlushDenormals {
 public:
#if defined(__SSE__) || defined(_M_X64)
  FlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ | DAZ
  ~FlushDenormals() { _mm_setcsr(saved_); }

 private:
  unsigned saved_;
#endif
};

// Floats between the starts of consecutive sums in a block: a whole number of cache lines
// plus 5 more, so that the 7 or 14 sums of a ring fall on different cache sets.
size_t paddedStride(size_t count) { return (count + 15) / 16 * 16 + 80; }

int chebyshev(int dx, int dy) { return std::max(std::abs(dx), std::abs(dy)); }

bool isSwept(int dx, int dy, int denseRadius) {
  return chebyshev(dx, dy) <= denseRadius || (dx % 2 == 0 && dy % 2 == 0);
}

struct Offset {
  int dx, dy;
  int ring;      // index of the smallest radius whose window holds the offset
  float factor;  // weight of the offset: 1, or the ring's factor beyond denseRadius
};

int ringOf(const SweepConfig& config, int norm) {
  int ring = 0;
  while (config.radii[size_t(ring)] < norm) ++ring;
  return ring;
}

// The offsets of the largest window in a fixed order (the centre excluded: it is added with
// weight 1 by itself). Beyond denseRadius only the offsets with even coordinates are taken,
// with the factor (offsets of the ring there) / (offsets kept), so that every window keeps its
// total spatial weight.
std::vector<Offset> sweepOffsets(const SweepConfig& config) {
  const int widest = config.radii.back();
  std::vector<int> all(config.radii.size(), 0), kept(config.radii.size(), 0);
  for (int dy = -widest; dy <= widest; ++dy) {
    for (int dx = -widest; dx <= widest; ++dx) {
      const int norm = chebyshev(dx, dy);
      if (norm <= config.denseRadius) continue;
      const int ring = ringOf(config, norm);
      all[size_t(ring)] += 1;
      kept[size_t(ring)] += isSwept(dx, dy, config.denseRadius) ? 1 : 0;
    }
  }
  std::vector<Offset> offsets;
  for (int dy = -widest; dy <= widest; ++dy) {
    for (int dx = -widest; dx <= widest; ++dx) {
      if ((dx == 0 && dy == 0) || !isSwept(dx, dy, config.denseRadius)) continue;
      const int norm = chebyshev(dx, dy), ring = ringOf(config, norm);
      const float factor =
          norm > config.denseRadius ? float(all[size_t(ring)]) / float(kept[size_t(ring)]) : 1.0f;
      offsets.push_back({dx, dy, ring, factor});
    }
  }
  return offsets;
}

class BlockSweep {
 public:
  BlockSweep(const SweepInput& in, const SweepConfig& config, std::span<const Offset> offsets,
             int blockRows)
      : in_(in),
        config_(config),
        offsets_(offsets),
        width_(in.width),
        patch_(config.patchRadius),
        rings_(int(config.radii.size())),
        blockPixels_(size_t(blockRows) * in.width),
        sumStride_(paddedStride(blockPixels_)) {
    const size_t haloRows = size_t(blockRows + 2 * patch_);
    for (Plane& row : temp_) row.assign(size_t(width_ + 2 * patch_), 0.0f);
    for (Plane& rows : horizontal_) rows.assign(haloRows * width_, 0.0f);
    for (Plane& row : vertical_) row.assign(width_, 0.0f);
    for (Plane& row : weight_) row.assign(width_, 0.0f);
    phi_.assign(width_, 0.0f);
    sums_.assign(size_t(rings_) * in_.streams * kSums * sumStride_, 0.0f);
  }

  // Filters rows [y0, y1) at every scale into `out`; false when cancelled.
  bool run(int y0, int y1, std::vector<ScaleMaps>& out, const std::atomic<bool>* cancel) {
    y0_ = y0;
    rows_ = y1 - y0;
    std::fill(sums_.begin(), sums_.end(), 0.0f);
    for (const Offset& offset : offsets_) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return false;
      const int xa = std::max(0, -offset.dx), xb = std::min(width_, width_ - offset.dx);
      if (xa >= xb) continue;
      pixelDistances(offset, xa, xb);
      for (int row = 0; row < rows_; ++row) {
        const int qy = y0_ + row + offset.dy;
        if (qy < 0 || qy >= in_.height) continue;
        weightsOfRow(row, offset, xa, xb);
        accumulate(row, offset, xa, xb);
      }
    }
    finish(out);
    return true;
  }

 private:
  float* sums(int ring, int stream, int which) {
    return sums_.data() + ((size_t(ring) * in_.streams + stream) * kSums + which) * sumStride_;
  }
  const float* sums(int ring, int stream, int which) const {
    return sums_.data() + ((size_t(ring) * in_.streams + stream) * kSums + which) * sumStride_;
  }
  ptrdiff_t shiftOf(const Offset& offset) const {
    return ptrdiff_t(offset.dy) * width_ + offset.dx;
  }

  // Colour distances of the pairs (p, p + offset), box-filtered along the row, for the
  // block's rows and the halo, into horizontal_.
  void pixelDistances(const Offset& offset, int xa, int xb);
  // The patch's vertical sums for block row `row`, then the weights of that row (§2, §3).
  void weightsOfRow(int row, const Offset& offset, int xa, int xb);
  void accumulate(int row, const Offset& offset, int xa, int xb);
  // SURE and the outputs of every scale (§4).
  void finish(std::vector<ScaleMaps>& out) const;

  const SweepInput& in_;
  const SweepConfig& config_;
  std::span<const Offset> offsets_;
  int width_, patch_, rings_;
  size_t blockPixels_, sumStride_;
  int y0_ = 0, rows_ = 0;
  // One row each of distances, with patch_ zeros before and after (stream 0, 1, pairs).
  std::array<Plane, 3> temp_;
  // (rows + 2 patch) rows of width_: the distances box-summed along x.
  std::array<Plane, 3> horizontal_;
  std::array<Plane, 3> vertical_;
  std::array<Plane, 2> weight_;
  Plane phi_;
  Plane sums_;
};

void BlockSweep::pixelDistances(const Offset& offset, int xa, int xb) {
  const float k2 = config_.k * config_.k, alpha = config_.alpha;
  const ptrdiff_t shift = shiftOf(offset);
  const int n = xb - xa, maps = in_.streams + 1;
  float* temp[3] = {temp_[0].data() + patch_, temp_[1].data() + patch_, temp_[2].data() + patch_};
  float* pairs = temp[in_.streams];  // temp[1] is the pairs' row when there is one stream
  for (int j = 0; j < rows_ + 2 * patch_; ++j) {
    const int y = y0_ - patch_ + j, qy = y + offset.dy;
    float* horizontal[3];
    for (int m = 0; m < maps; ++m) horizontal[m] = horizontal_[m].data() + size_t(j) * width_;
    // Pairs with a pixel outside the image count as missing from the patch.
    if (y < 0 || y >= in_.height || qy < 0 || qy >= in_.height) {
      for (int m = 0; m < maps; ++m) std::fill(horizontal[m], horizontal[m] + width_, 0.0f);
      continue;
    }
    for (int m = 0; m < maps; ++m) {
      std::fill(temp[m], temp[m] + xa, 0.0f);
      std::fill(temp[m] + xb, temp[m] + width_, 0.0f);
    }
    const size_t p = size_t(y) * width_ + xa;
    auto at = [&](const Plane& plane) { return plane.data() + p; };
    const Planes3& v = in_.variance;
    // Under cross-filtering stream 0 is weighted by the colours of stream 1 and the reverse.
    const Planes3& a = in_.value[in_.streams == 2 ? 1 : 0];
    const Planes3& b = in_.value[0];
    if (in_.streams == 2) {
      colourDistanceRow<true>(n, shift, k2, alpha, at(v[0]), at(v[1]), at(v[2]), at(a[0]), at(a[1]),
                              at(a[2]), at(b[0]), at(b[1]), at(b[2]), at(in_.valid), temp[0] + xa,
                              temp[1] + xa, pairs + xa);
    } else {
      colourDistanceRow<false>(n, shift, k2, alpha, at(v[0]), at(v[1]), at(v[2]), at(a[0]),
                               at(a[1]), at(a[2]), at(a[0]), at(a[1]), at(a[2]), at(in_.valid),
                               temp[0] + xa, nullptr, pairs + xa);
    }
    for (int m = 0; m < maps; ++m) boxRow(n, patch_, temp[m] + xa, horizontal[m] + xa);
  }
}

void BlockSweep::weightsOfRow(int row, const Offset& offset, int xa, int xb) {
  const int n = xb - xa, maps = in_.streams + 1, side = 2 * patch_ + 1;
  const ptrdiff_t shift = shiftOf(offset);
  const size_t p = size_t(y0_ + row) * width_ + xa;
  float* phi = phi_.data() + xa;
  std::fill(phi, phi + n, 0.0f);
  for (const FeaturePlanes& feature : in_.features) {
    const float* f0 = feature.value[0].data() + p;
    const float* variance = feature.variance.data() + p;
    const float* inverseScale = feature.inverseScale.data() + p;
    if (feature.components == 3) {
      featureRow<3>(n, shift, f0, feature.value[1].data() + p, feature.value[2].data() + p,
                    variance, inverseScale, phi);
    } else {
      featureRow<1>(n, shift, f0, f0, f0, variance, inverseScale, phi);
    }
  }
  // The patch's rows of row-boxed distances: summed inside the weight kernel for the common
  // 1x1, 3x3 and 5x5 patches, else first into vertical_.
  const float* h[3];
  for (int m = 0; m < maps; ++m) h[m] = horizontal_[m].data() + size_t(row) * width_ + xa;
  if (side > 5) {
    for (int m = 0; m < maps; ++m) {
      float* vertical = vertical_[m].data() + xa;
      std::copy(h[m], h[m] + n, vertical);
      for (int t = 1; t < side; ++t) addRow(n, h[m] + size_t(t) * width_, vertical);
      h[m] = vertical;
    }
  }
  const bool two = in_.streams == 2;
  const float* valid = in_.valid.data() + p;
  const float* pairs = h[maps - 1];
  float* w0 = weight_[0].data() + xa;
  float* w1 = weight_[1].data() + xa;
  const size_t stride = size_t(width_);
  auto run = [&]<int Side>() {
    if (two) {
      weightRow<true, Side>(n, shift, valid, h[0], h[1], pairs, stride, phi, w0, w1);
    } else {
      weightRow<false, Side>(n, shift, valid, h[0], h[0], pairs, stride, phi, w0, w1);
    }
  };
  if (side == 3) {
    run.template operator()<3>();
  } else if (side == 5) {
    run.template operator()<5>();
  } else {
    run.template operator()<1>();  // 1x1 patches, or sums already in vertical_
  }
}

void BlockSweep::accumulate(int row, const Offset& offset, int xa, int xb) {
  const size_t q = size_t(ptrdiff_t(size_t(y0_ + row) * width_ + xa) + shiftOf(offset));
  const size_t i = size_t(row) * width_ + xa;
  const bool two = in_.streams == 2;
  auto at = [&](const Plane& plane) { return plane.data() + q; };
  auto sum = [&](int stream, int which) { return sums(offset.ring, stream, which) + i; };
  const Planes3& yA = in_.value[0];
  const Planes3& yB = in_.value[two ? 1 : 0];
  const Planes3& v = in_.variance;
  const int b = two ? 1 : 0;
  const float* wA = weight_[0].data() + xa;
  const float* wB = weight_[size_t(b)].data() + xa;
  if (two) {
    accumulateRow<true>(xb - xa, offset.factor, wA, wB, at(yA[0]), at(yA[1]), at(yA[2]), at(yB[0]),
                        at(yB[1]), at(yB[2]), at(v[0]), at(v[1]), at(v[2]), sum(0, 0), sum(0, 1),
                        sum(0, 2), sum(0, 3), sum(0, 4), sum(0, 5), sum(0, 6), sum(b, 0), sum(b, 1),
                        sum(b, 2), sum(b, 3), sum(b, 4), sum(b, 5), sum(b, 6));
  } else {
    accumulateRow<false>(xb - xa, offset.factor, wA, wA, at(yA[0]), at(yA[1]), at(yA[2]), at(yA[0]),
                         at(yA[1]), at(yA[2]), at(v[0]), at(v[1]), at(v[2]), sum(0, 0), sum(0, 1),
                         sum(0, 2), sum(0, 3), sum(0, 4), sum(0, 5), sum(0, 6), nullptr, nullptr,
                         nullptr, nullptr, nullptr, nullptr, nullptr);
  }
}

void BlockSweep::finish(std::vector<ScaleMaps>& out) const {
  const int streams = in_.streams;
  for (int row = 0; row < rows_; ++row) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = size_t(y0_ + row) * width_ + x, i = size_t(row) * width_ + x;
      if (!(in_.valid[p] > 0.0f)) {
        for (ScaleMaps& maps : out) {
          maps.output[p] = vec3(0.0f);
          maps.mse[p] = std::numeric_limits<float>::infinity();
          maps.varianceRatio[p] = 1.0f;
        }
        continue;
      }
      // The centre's weight is 1 at every scale (zero distance in space, colour and
      // features); the rings are added to it one after the other.
      float acc[2][kSums];
      for (int s = 0; s < streams; ++s) {
        acc[s][0] = 1.0f;
        for (int c = 0; c < 3; ++c) {
          acc[s][1 + c] = in_.value[s][c][p];
          acc[s][4 + c] = in_.variance[c][p];
        }
      }
      float demod[3], meanVariance[3];
      for (int c = 0; c < 3; ++c) {
        demod[c] = in_.demod[c][p];
        meanVariance[c] = in_.variance[c][p] / float(streams);
      }
      const float before = toLinearSum(meanVariance[0], meanVariance[1], meanVariance[2], demod[0],
                                       demod[1], demod[2]);
      for (int ring = 0; ring < rings_; ++ring) {
        float filtered[3] = {0, 0, 0}, error[3] = {0, 0, 0}, variance[3] = {0, 0, 0};
        for (int s = 0; s < streams; ++s) {
          for (int k = 0; k < kSums; ++k) acc[s][k] += sums(ring, s, k)[i];
          const float w = acc[s][0];
          for (int c = 0; c < 3; ++c) {
            const float sigma2 = in_.variance[c][p];
            const float f = acc[s][1 + c] / w;
            const float diff = f - in_.value[s][c][p];
            // SURE (§4): w_pp = 1, so the divergence term is 2 sigma^2 / sum w.
            filtered[c] += f;
            error[c] += diff * diff + 2.0f * sigma2 / w - sigma2;
            variance[c] += acc[s][4 + c] / (w * w);
          }
        }
        for (int c = 0; c < 3; ++c) {
          filtered[c] /= float(streams);
          // The two filtered halves have independent noise, so the MSE of their average is
          // the mean of their MSEs less half the mean of their variances.
          if (streams == 2) error[c] = 0.5f * error[c] - 0.25f * variance[c];
          variance[c] /= float(streams * streams);
        }
        ScaleMaps& maps = out[size_t(ring)];
        maps.output[p] = vec3(filtered[0] * demod[0] + in_.emission[0][p],
                              filtered[1] * demod[1] + in_.emission[1][p],
                              filtered[2] * demod[2] + in_.emission[2][p]);
        maps.mse[p] = toLinearSum(error[0], error[1], error[2], demod[0], demod[1], demod[2]);
        const float after =
            toLinearSum(variance[0], variance[1], variance[2], demod[0], demod[1], demod[2]);
        const float ratio = before > 0.0f ? after / before : 1.0f;
        maps.varianceRatio[p] = ratio < 1.0f ? (ratio > 0.0f ? ratio : 0.0f) : 1.0f;
      }
    }
  }
}

}  // namespace

void Plane::assign(size_t count, float value) {
  // Successive planes start 5 cache lines apart modulo a page (5 is prime to the 64 lines of a
  // page, so 64 planes in a row all differ).
  static std::atomic<unsigned> next{0};
  skew_ = size_t(next.fetch_add(1, std::memory_order_relaxed) * 5u % 64u) * 16u;
  count_ = count;
  storage_.assign(count + skew_, value);
}

std::vector<ScaleMaps> sweepScales(const SweepInput& in, const SweepConfig& config,
                                   const std::atomic<bool>* cancel) {
  const size_t count = size_t(in.width) * in.height;
  std::vector<ScaleMaps> out(config.radii.size());
  for (ScaleMaps& maps : out) {
    maps.output.assign(count, vec3(0.0f));
    maps.mse.assign(count, std::numeric_limits<float>::infinity());
    maps.varianceRatio.assign(count, 1.0f);
  }
  if (config.radii.empty()) return out;
  const std::vector<Offset> offsets = sweepOffsets(config);
  const size_t rowBytes = config.radii.size() * in.streams * kSums * sizeof(float) * in.width;
  const int blockRows =
      std::clamp(int(kSumsBudget / std::max<size_t>(rowBytes, 1)), kMinBlockRows, kMaxBlockRows);
  const int blocks = (in.height + blockRows - 1) / blockRows;
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& r) {
    const FlushDenormals flush;
    BlockSweep sweep(in, config, offsets, blockRows);
    for (int b = r.begin(); b != r.end(); ++b) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      const int y0 = b * blockRows, y1 = std::min(in.height, y0 + blockRows);
      if (!sweep.run(y0, y1, out, cancel)) return;
    }
  });
  return out;
}

}  // namespace penumbra::recon::detail
