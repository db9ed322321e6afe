#include "methods/error_allocation.h"

#include "core/rng.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
constexpr uint64_t kAllocationSalt = 0x616c6c6f63617465ULL;
}  // namespace

std::vector<uint32_t> allocateByError(std::span<const float> error, std::span<const uint32_t> count,
                                      uint64_t budget, const ErrorAllocation& config, uint64_t seed,
                                      int round) {
  const size_t n = error.size();
  std::vector<uint32_t> out(n, 0);
  if (n == 0 || budget == 0 || count.size() != n) return out;
  float top = 0;
  for (float e : error)
    if (std::isfinite(e)) top = std::max(top, e);
  // Per pixel: sqrt(c_p) and whether it may receive samples at all.
  std::vector<double> root(n);
  std::vector<uint8_t> active(n);
  double countSum = 0;
  size_t activeCount = 0;
  for (size_t p = 0; p < n; ++p) {
    const double e = std::isfinite(error[p]) ? std::max(0.0f, error[p]) : top;
    active[p] = !(config.noiseThreshold > 0 && e < config.noiseThreshold);
    root[p] = std::sqrt(e * std::max<uint32_t>(count[p], 1));
    countSum += count[p];
    activeCount += active[p];
  }
  if (activeCount == 0) return out;
  const double floorCount = config.floorFraction * (countSum + double(budget)) / double(n);
  auto spend = [&](double lambda, double floorScale, std::vector<double>* share) {
    double total = 0;
    for (size_t p = 0; p < n; ++p) {
      if (!active[p]) continue;
      const double target = std::max(floorScale * floorCount, lambda * root[p]);
      const double d = std::max(0.0, target - double(count[p]));
      total += d;
      if (share) (*share)[p] = d;
    }
    return total;
  };
  // The floors alone may exceed the budget: scale them down, then find lambda by bisection.
  double floorScale = 1.0;
  const double floorsOnly = spend(0.0, 1.0, nullptr);
  if (floorsOnly > double(budget)) floorScale = double(budget) / floorsOnly;
  double lo = 0, hi = 1;
  while (spend(hi, floorScale, nullptr) < double(budget) && hi < 1e30) hi *= 2;
  // To a relative 1e-5: the shares are rounded to whole samples anyway.
  for (int i = 0; i < 60 && floorsOnly <= double(budget) && hi - lo > 1e-5 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (spend(mid, floorScale, nullptr) < double(budget) ? lo : hi) = mid;
  }
  std::vector<double> share(n, 0.0);
  spend(floorsOnly <= double(budget) ? hi : 0.0, floorScale, &share);
  for (size_t p = 0; p < n; ++p) {
    const double whole = std::floor(share[p]);
    const double coin =
        toUnitFloat(uint32_t(hashValues(hashValues(seed, uint64_t(round), p), kAllocationSalt)));
    out[p] = uint32_t(whole) + (coin < share[p] - whole ? 1u : 0u);
  }
  return out;
}

std::vector<float> dilate3x3(std::span<const float> values, int width, int height) {
  std::vector<float> out(values.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double top = 0;
      int used = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
          const float v = values[size_t(qy) * width + qx];
          if (!std::isfinite(v)) continue;
          top = std::max(top, double(v));
          ++used;
        }
      out[size_t(y) * width + x] = used ? float(top) : 0.0f;
    }
  return out;
}

}  // namespace penumbra
