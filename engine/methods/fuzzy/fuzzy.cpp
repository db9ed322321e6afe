// The fuzzy-uncertainty baseline's score and its per-pixel reservoir of luminances.
#include "methods/fuzzy/fuzzy.h"

#include "methods/factory.h"

#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

const ParamTable<FuzzyConfig>& fuzzyParams() {
  static const ParamTable<FuzzyConfig> table = [] {
    ParamTable<FuzzyConfig> t;
    t.include(allocationParams());
    return t;
  }();
  return table;
}

namespace adaptive {

double fuzzyScore(std::span<const float> values, double minimum, double maximum, double mean,
                  uint32_t n) {
  if (n == 0 || values.empty()) return 0.0;
  const double range = maximum - minimum;
  if (!(range >= 1e-4 * std::max(mean, 0.0)) || !(range > 0)) return 0.0;
  double entropy = 0;
  for (float v : values) {
    const double mu = std::clamp((double(v) - minimum) / range, 0.0, 1.0);
    if (mu > 0 && mu < 1) entropy += -mu * std::log(mu) - (1 - mu) * std::log(1 - mu);
  }
  entropy /= double(values.size()) * std::log(2.0);
  const double contrast = range / (maximum + minimum + 1e-4);
  return entropy * contrast * mean / std::sqrt(double(n));
}

}  // namespace adaptive

namespace {

class FuzzyMethod final : public AllocationMethod {
 public:
  FuzzyMethod(const PreparedScene& prepared, const RunShape& shape, const FuzzyConfig& config)
      : AllocationMethod(prepared, shape, config, "fuzzy"),
        reservoir_(config.reservoir),
        sum_(pixelCount_, glm::dvec3(0.0)),
        lum_(pixelCount_),
        values_(pixelCount_),
        minimum_(pixelCount_, INFINITY),
        maximum_(pixelCount_, -INFINITY) {
    if (config.reservoir < 1) throw std::invalid_argument("the fuzzy reservoir must be >= 1");
  }

 protected:
  void addSample(size_t p, uint32_t index, vec3 L) override {
    sum_[p] += glm::dvec3(L);
    const double y = std::max(0.0f, luminance(L));
    lum_[p].add(y);
    minimum_[p] = std::min(minimum_[p], float(y));
    maximum_[p] = std::max(maximum_[p], float(y));
    auto& v = values_[p];
    if (v.size() < size_t(reservoir_)) {
      v.push_back(float(y));
    } else {  // reservoir sampling, keyed on (seed, pixel, index): deterministic
      const uint64_t j = hashValues(shape_.seed, p, index) % lum_[p].n;
      if (j < v.size()) v[j] = float(y);
    }
  }

  void computeScores(std::vector<float>& scores) override {
    forEachPixel(pixelCount_, [&](size_t p) {
      double s = 0;
      if (lum_[p].n > 0)
        s = adaptive::fuzzyScore(values_[p], minimum_[p], maximum_[p], lum_[p].sum / lum_[p].n,
                                 lum_[p].n);
      scores[p] = std::isfinite(s) ? float(s) : 0.0f;
    });
  }

  vec3 pixelMean(size_t p) const override {
    const uint32_t n = lum_[p].n;
    return n > 0 ? vec3(sum_[p] / double(n)) : vec3(0.0f);
  }

  size_t statisticsBytes() const override {
    size_t bytes = sum_.capacity() * sizeof(glm::dvec3) +
                   lum_.capacity() * sizeof(adaptive::LuminanceSums) +
                   (minimum_.capacity() + maximum_.capacity()) * sizeof(float);
    for (const auto& v : values_) bytes += sizeof(v) + v.capacity() * sizeof(float);
    return bytes;
  }

  std::string scoreName() const override { return "fuzzy uncertainty"; }

 private:
  int reservoir_;
  std::vector<glm::dvec3> sum_;
  std::vector<adaptive::LuminanceSums> lum_;
  std::vector<std::vector<float>> values_;
  std::vector<float> minimum_, maximum_;
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makeFuzzyMethod(const PreparedScene& prepared,
                                                   const RunShape& shape,
                                                   const FuzzyConfig& config) {
  return makeValidated<FuzzyMethod>(fuzzyMethod(), prepared, shape, config);
}

const MethodDescriptor& fuzzyMethod() {
  static const MethodDescriptor descriptor(allocationDefinition<FuzzyMethod, FuzzyConfig>(
      "fuzzy", "Fuzzy uncertainty (re-implemented, after Xu et al. 2008)", fuzzyParams()));
  return descriptor;
}

}  // namespace penumbra
