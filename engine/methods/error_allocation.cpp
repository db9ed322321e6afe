#include "methods/error_allocation.h"

#include "core/large_pages.h"
#include "core/rng.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace penumbra {

namespace {
constexpr uint64_t kAllocationSalt = 0x616c6c6f63617465ULL;

// Pixels per chunk of the deterministic reductions: the chunks, and so the sums' rounding,
// do not depend on the thread count.
constexpr size_t kChunk = 4096;

// (sum_p f(p).first, sum_p f(p).second) over [0, n), chunked and joined in a fixed order.
struct SumPair {
  double a = 0, b = 0;
};
template <class F>
SumPair deterministicSums(size_t n, F f) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, n, kChunk), SumPair{},
      [&](const tbb::blocked_range<size_t>& r, SumPair sum) {
        // Two partial sums of each: independent chains the compiler can keep in lanes.
        double a[2] = {0, 0}, b[2] = {0, 0};
        size_t p = r.begin();
        for (; p + 2 <= r.end(); p += 2)
          for (size_t k = 0; k < 2; ++k) {
            const SumPair v = f(p + k);
            a[k] += v.a;
            b[k] += v.b;
          }
        for (; p < r.end(); ++p) {
          const SumPair v = f(p);
          a[0] += v.a;
          b[0] += v.b;
        }
        return SumPair{sum.a + (a[0] + a[1]), sum.b + (b[0] + b[1])};
      },
      [](SumPair x, SumPair y) {
        return SumPair{x.a + y.a, x.b + y.b};
      });
}

}  // namespace

std::vector<uint32_t> allocateByError(std::span<const float> error, std::span<const uint32_t> count,
                                      uint64_t budget, const ErrorAllocation& config, uint64_t seed,
                                      int round, std::span<const uint8_t> converged) {
  const size_t n = error.size();
  std::vector<uint32_t> out(n, 0);
  if (n == 0 || budget == 0 || count.size() != n || (!converged.empty() && converged.size() != n))
    return out;
  float top = 0;
  for (float e : error)
    if (std::isfinite(e)) top = std::max(top, e);
  // Per pixel: sqrt(c_p) and its count; a pixel that may receive no samples gets root 0 and
  // an infinite count, so that every target stays below it and the sums need no branch.
  // Made afresh every round: huge pages, one fault per 2 MiB (core/large_pages.h).
  LargeVector<double> root(n), have(n);
  double countSum = 0;
  size_t activeCount = 0;
  for (size_t p = 0; p < n; ++p) {
    const double e = std::isfinite(error[p]) ? std::max(0.0f, error[p]) : top;
    const bool active = converged.empty() || !converged[p];
    root[p] = active ? std::sqrt(e * std::max<uint32_t>(count[p], 1)) : 0.0;
    have[p] = active ? double(count[p]) : HUGE_VAL;
    countSum += count[p];
    activeCount += active;
  }
  if (activeCount == 0) return out;
  const double floorCount = config.floorFraction * (countSum + double(budget)) / double(n);
  auto share = [&](size_t p, double lambda, double floor) {
    return std::max(0.0, std::max(floor, lambda * root[p]) - have[p]);
  };
  // What lambda spends, and d spend / d lambda: the roots of the pixels whose share grows
  // with lambda (above their floor and their count).
  auto spendAndSlope = [&](double lambda, double floorScale) {
    const double floor = floorScale * floorCount;
    return deterministicSums(n, [&](size_t p) {
      const double target = lambda * root[p];
      const bool grows = target > floor && target > have[p];
      return SumPair{share(p, lambda, floor), grows ? root[p] : 0.0};
    });
  };
  // The floors alone may exceed the budget: scale them down.
  double floorScale = 1.0;
  const double floorsOnly = spendAndSlope(0.0, 1.0).a;
  if (floorsOnly > double(budget)) floorScale = double(budget) / floorsOnly;
  // An upper bracket: at lambda0 = (budget + sum c) / sum sqrt(c_p) the shares without their
  // floors and clamps already sum to the budget, and those only add.
  double rootSum = 0, haveSum = 0;
  for (size_t p = 0; p < n; ++p)
    if (root[p] > 0) {
      rootSum += root[p];
      haveSum += have[p];
    }
  double lambda = rootSum > 0 ? (double(budget) + haveSum) / rootSum : 1.0;
  SumPair at = spendAndSlope(lambda, floorScale);
  while (at.a < double(budget) && lambda < 1e30) at = spendAndSlope(lambda *= 2, floorScale);
  // spend(lambda) is convex and piecewise linear in lambda, so Newton's steps from above stay
  // above the root and reach it in a few steps (exactly, once on its last piece); stop within
  // a hundredth of a sample: the shares are rounded to whole samples anyway.
  for (int i = 0; i < 64 && floorsOnly <= double(budget); ++i) {
    const double excess = at.a - double(budget);
    if (!(excess > 0.01) || !(at.b > 0)) break;
    const double next = lambda - excess / at.b;
    if (!(next < lambda) || !(next > 0)) break;
    lambda = next;
    at = spendAndSlope(lambda, floorScale);
  }
  if (!(floorsOnly <= double(budget))) lambda = 0.0;
  const double floor = floorScale * floorCount;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, kChunk), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
          const double d = share(p, lambda, floor);
          const double whole = std::floor(d);
          const double coin = toUnitFloat(
              uint32_t(hashValues(hashValues(seed, uint64_t(round), p), kAllocationSalt)));
          out[p] = uint32_t(whole) + (coin < d - whole ? 1u : 0u);
        }
      });
  return out;
}

std::vector<float> dilate3x3(std::span<const float> values, int width, int height) {
  // Separable: the largest finite value of each row's three, then of each column's three.
  // Non-finite values are skipped (as -inf), and the result is at least 0 (a pixel whose whole
  // neighbourhood is non-finite gets 0).
  const size_t w = size_t(width);
  LargeVector<float> rows(values.size());
  std::vector<float> out(values.size());
  auto finite = [](float v) { return std::isfinite(v) ? v : -HUGE_VALF; };
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* in = values.data() + size_t(y) * w;
      float* o = rows.data() + size_t(y) * w;
      for (int x = 0; x < width; ++x) {
        float m = finite(in[x]);
        if (x > 0) m = std::max(m, finite(in[x - 1]));
        if (x + 1 < width) m = std::max(m, finite(in[x + 1]));
        o[x] = m;
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* mid = rows.data() + size_t(y) * w;
      const float* up = y > 0 ? mid - w : mid;
      const float* down = y + 1 < height ? mid + w : mid;
      float* o = out.data() + size_t(y) * w;
      for (int x = 0; x < width; ++x) {
        o[x] = std::max(0.0f, std::max(mid[x], std::max(up[x], down[x])));
      }
    }
  });
  return out;
}

}  // namespace penumbra
