// Cycles' half-buffer error as an allocation criterion.
#include "methods/cycles/cycles.h"

#include "methods/factory.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

const ParamTable<CyclesConfig>& cyclesParams() {
  static const ParamTable<CyclesConfig> table = [] {
    ParamTable<CyclesConfig> t;
    t.include(allocationParams());
    return t;
  }();
  return table;
}

namespace adaptive {

double cyclesError(vec3 meanAll, vec3 meanHalf) {
  const double sum = double(meanAll.x) + meanAll.y + meanAll.z;
  const double norm = sum < 1.0 ? std::sqrt(std::max(0.0, sum)) : sum;
  const double diff = std::abs(double(meanAll.x) - meanHalf.x) +
                      std::abs(double(meanAll.y) - meanHalf.y) +
                      std::abs(double(meanAll.z) - meanHalf.z);
  return diff / (1e-4 + norm);
}

}  // namespace adaptive

namespace {

class CyclesMethod final : public AllocationMethod {
 public:
  CyclesMethod(const PreparedScene& prepared, const RunShape& shape, const CyclesConfig& config)
      : AllocationMethod(prepared, shape, config, "cycles"),
        dilate_(config.dilate),
        sum_(pixelCount_, glm::dvec3(0.0)),
        sumHalf_(pixelCount_, glm::dvec3(0.0)),
        halfCount_(pixelCount_, 0) {}

 protected:
  void addSample(size_t p, uint32_t index, vec3 L) override {
    sum_[p] += glm::dvec3(L);
    if (index % 2 == 0) sumHalf_[p] += glm::dvec3(L);
    ++halfCount_[p];
  }

  void computeScores(std::vector<float>& scores) override {
    forEachPixel(pixelCount_, [&](size_t p) {
      double s = 0;
      const uint32_t n = halfCount_[p];
      if (n > 0)
        s = adaptive::cyclesError(vec3(sum_[p] / double(n)), vec3(2.0 * sumHalf_[p] / double(n)));
      scores[p] = std::isfinite(s) ? float(s) : 0.0f;
    });
    if (dilate_) dilate(scores);
  }

  vec3 pixelMean(size_t p) const override {
    const uint32_t n = halfCount_[p];
    return n > 0 ? vec3(sum_[p] / double(n)) : vec3(0.0f);
  }

  size_t statisticsBytes() const override {
    return (sum_.capacity() + sumHalf_.capacity()) * sizeof(glm::dvec3) +
           halfCount_.capacity() * sizeof(uint32_t);
  }

  std::string scoreName() const override { return "half-buffer error"; }

 private:
  // Unconverged regions grow by one pixel in x, then in y: a 3x3 maximum filter.
  void dilate(std::vector<float>& scores) const {
    std::vector<float> tmp(scores.size());
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        float m = scores[size_t(y) * width_ + x];
        if (x > 0) m = std::max(m, scores[size_t(y) * width_ + x - 1]);
        if (x + 1 < width_) m = std::max(m, scores[size_t(y) * width_ + x + 1]);
        tmp[size_t(y) * width_ + x] = m;
      }
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        float m = tmp[size_t(y) * width_ + x];
        if (y > 0) m = std::max(m, tmp[size_t(y - 1) * width_ + x]);
        if (y + 1 < height_) m = std::max(m, tmp[size_t(y + 1) * width_ + x]);
        scores[size_t(y) * width_ + x] = m;
      }
  }

  bool dilate_;
  std::vector<glm::dvec3> sum_, sumHalf_;
  std::vector<uint32_t> halfCount_;  // finite samples per pixel
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makeCyclesMethod(const PreparedScene& prepared,
                                                    const RunShape& shape,
                                                    const CyclesConfig& config) {
  return makeValidated<CyclesMethod>(cyclesMethod(), prepared, shape, config);
}

const MethodDescriptor& cyclesMethod() {
  static const MethodDescriptor descriptor(allocationDefinition<CyclesMethod, CyclesConfig>(
      "cycles", "Cycles half-buffer error (Dammertz et al. 2010)", cyclesParams()));
  return descriptor;
}

}  // namespace penumbra
