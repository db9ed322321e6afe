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

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <span>
#include <string>

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

// The widest instruction set the CPU has; PENUMBRA_RECON_SIMD=sse or avx2 caps it (all give
// the same bits; the tests compare them).
SweepBlocks sweepBlocksForThisCpu() {
  const char* forced = std::getenv("PENUMBRA_RECON_SIMD");
  const std::string cap = forced ? forced : "";
  if (cap == "sse") return sweep_sse::sweepBlocks;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  if (cap != "avx2" && __builtin_cpu_supports("avx512f")) return sweep_avx512::sweepBlocks;
  if (__builtin_cpu_supports("avx2")) return sweep_avx2::sweepBlocks;
#endif
  return sweep_sse::sweepBlocks;
}

int chebyshev(int dx, int dy) { return std::max(std::abs(dx), std::abs(dy)); }

bool isSwept(int dx, int dy, int denseRadius) {
  return chebyshev(dx, dy) <= denseRadius || (dx % 2 == 0 && dy % 2 == 0);
}

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
  const int rows = in.rowEnd() - in.firstRow;
  const size_t count = size_t(in.width) * size_t(std::max(rows, 0));
  std::vector<ScaleMaps> out(config.radii.size());
  for (ScaleMaps& maps : out) {
    maps.output.assign(count, vec3(0.0f));
    maps.mse.assign(count, std::numeric_limits<float>::infinity());
    maps.varianceRatio.assign(count, 1.0f);
  }
  if (config.radii.empty() || rows <= 0) return out;
  const std::vector<Offset> offsets = sweepOffsets(config);
  const size_t rowBytes =
      config.radii.size() * in.streams * kSumsPerStream * sizeof(float) * in.width;
  const int blockRows =
      std::clamp(int(kSumsBudget / std::max<size_t>(rowBytes, 1)), kMinBlockRows, kMaxBlockRows);
  const int blocks = (rows + blockRows - 1) / blockRows;
  const SweepBlocks sweep = sweepBlocksForThisCpu();
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& r) {
    const FlushDenormals flush;
    sweep(in, config, offsets, blockRows, r.begin(), r.end(), out, cancel);
  });
  return out;
}

}  // namespace penumbra::recon::detail
