// The f-divergence baseline's score.
#include "methods/fdiv/fdiv.h"

#include "methods/factory.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

const ParamTable<FDivConfig>& fdivParams() {
  static const ParamTable<FDivConfig> table = [] {
    ParamTable<FDivConfig> t;
    t.include(allocationParams())
        .choice<Divergence>(
            "divergence", "divergence",
            "fdiv: hellinger (the BP paper's eq. 15), kl (Kullback-Leibler) or chi2",
            [](auto& c) -> auto& { return c.divergence; }, {"hellinger", "kl", "chi2"});
    return t;
  }();
  return table;
}

namespace adaptive {

double divergence(const LuminanceSums& s, Divergence kind) {
  if (s.n < 2 || !(s.sum > 0)) return 0.0;
  const double n = s.n;
  double d = 0;
  switch (kind) {
    case Divergence::Hellinger:
      // 1/2 sum (sqrt p_i - sqrt(1/N))^2 = 1 - sum sqrt(L_i) / sqrt(N sum L).
      d = 1.0 - s.sumSqrt / std::sqrt(n * s.sum);
      break;
    case Divergence::KullbackLeibler:
      // sum p_i ln(N p_i) = (1/S) sum L ln L - ln S + ln N.
      d = s.sumLLogL / s.sum - std::log(s.sum) + std::log(n);
      break;
    case Divergence::ChiSquare:
      d = n * s.sumSquares / (s.sum * s.sum) - 1.0;
      break;
  }
  return std::max(0.0, d);  // rounding can leave a tiny negative for equal samples
}

double fDivergenceScore(const LuminanceSums& s, Divergence kind) {
  if (s.n == 0) return 0.0;
  const double mean = s.sum / s.n;
  return mean * std::sqrt(divergence(s, kind)) / s.n;
}

}  // namespace adaptive

namespace {

class FDivMethod final : public AllocationMethod {
 public:
  FDivMethod(const PreparedScene& prepared, const RunShape& shape, const FDivConfig& config)
      : AllocationMethod(prepared, shape, config, "fdiv"),
        divergence_(config.divergence),
        sum_(pixelCount_, glm::dvec3(0.0)),
        lum_(pixelCount_) {}

 protected:
  void addSample(size_t p, uint32_t, vec3 L) override {
    sum_[p] += glm::dvec3(L);
    lum_[p].add(std::max(0.0f, luminance(L)));
  }

  void computeScores(std::vector<float>& scores) override {
    forEachPixel(pixelCount_, [&](size_t p) {
      const double s = adaptive::fDivergenceScore(lum_[p], divergence_);
      scores[p] = std::isfinite(s) ? float(s) : 0.0f;
    });
  }

  vec3 pixelMean(size_t p) const override {
    const uint32_t n = lum_[p].n;
    return n > 0 ? vec3(sum_[p] / double(n)) : vec3(0.0f);
  }

  size_t statisticsBytes() const override {
    return sum_.capacity() * sizeof(glm::dvec3) + lum_.capacity() * sizeof(adaptive::LuminanceSums);
  }

  std::string scoreName() const override { return "f-divergence score"; }

 private:
  Divergence divergence_;
  std::vector<glm::dvec3> sum_;
  std::vector<adaptive::LuminanceSums> lum_;
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makeFDivMethod(const PreparedScene& prepared,
                                                  const RunShape& shape, const FDivConfig& config) {
  return makeValidated<FDivMethod>(fdivMethod(), prepared, shape, config);
}

const MethodDescriptor& fdivMethod() {
  static const MethodDescriptor descriptor(allocationDefinition<FDivMethod, FDivConfig>(
      "fdiv", "F-divergence, Hellinger (Rigau et al. 2003)", fdivParams()));
  return descriptor;
}

}  // namespace penumbra
