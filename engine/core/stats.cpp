#include "core/stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace penumbra {

namespace {
std::vector<float> finiteValues(std::span<const float> values) {
  std::vector<float> finite;
  finite.reserve(values.size());
  for (float v : values)
    if (std::isfinite(v)) finite.push_back(v);
  return finite;
}

float atRank(std::vector<float>& values, size_t k) {
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return values[k];
}
}  // namespace

std::optional<float> lowerQuantile(std::span<const float> values, double q) {
  std::vector<float> finite = finiteValues(values);
  if (finite.empty()) return std::nullopt;
  return atRank(finite, std::min(finite.size() - 1, size_t(q * double(finite.size()))));
}

std::optional<float> nearestRankQuantile(std::span<const float> values, float q) {
  std::vector<float> finite = finiteValues(values);
  if (finite.empty()) return std::nullopt;
  return atRank(finite, std::min(finite.size() - 1, size_t(q * float(finite.size() - 1) + 0.5f)));
}

}  // namespace penumbra
