// BP's paper algorithm: its parameters, their checks, its presets and its descriptor.
#include "methods/bp/paper.h"

#include "methods/bp/slices.h"
#include "methods/bp/state.h"

#include <algorithm>

namespace penumbra {

int BpPaperConfig::effectiveCoarseSpp(const RunShape& shape) const {
  if (coarseSpp > 0) return coarseSpp;
  if (shape.openEnded) return 4;
  const int quarter = int(roundUpPowerOfTwo(uint32_t(std::max(1, shape.spp / 4))));
  return std::min(shape.spp, std::max(4, quarter));
}

std::string BpPaperConfig::check(const RunShape& shape) const {
  if (std::string problem = BpCommonConfig::check(shape, effectiveCoarseSpp(shape), true);
      !problem.empty())
    return problem;
  if (filter.alphas.empty() || filter.phi.size() + 1 != filter.alphas.size())
    return "--phi needs exactly one threshold fewer than --alphas has values";
  if (!std::is_sorted(filter.phi.begin(), filter.phi.end()))
    return "--phi thresholds must be ascending";
  if (filter.secondPassAlpha >= int(filter.alphas.size()))
    return "--second-pass-alpha must index --alphas (0.." +
           std::to_string(filter.alphas.size() - 1) + ")";
  return {};
}

const ParamTable<BpPaperConfig>& bpPaperParams() {
  static const ParamTable<BpPaperConfig> table = [] {
    ParamTable<BpPaperConfig> t;
    t.include(bpCommonParams());
    t.group("BP paper algorithm (--preset paper, tuned): Table 1")
        .real("psi", "psi", "Bias threshold Psi: pixels above it are difficult",
              [](auto& c) -> auto& { return c.psi; }, 0, 1e6, {0, 1})
        .integer("candidates", "candidates", "Candidates per new sample, N_candi",
                 [](auto& c) -> auto& { return c.candidates; }, 1, 64, {1, 16})
        .integer(
            "levels", "levels m", "Histogram levels m of a slice",
            [](auto& c) -> auto& { return c.histogramLevels; }, 1, kMaxHistogramLevels)
        .integer("radius", "radius r", "Filter radius r ((2r+1)^2 window)",
                 [](auto& c) -> auto& { return c.filter.radius; }, 0, 32, {0, 8})
        .list(
            "alphas", "alpha",
            "Spatial falloffs alpha_1..alpha_n, widest filter first (comma separated)",
            [](auto& c) -> auto& { return c.filter.alphas; }, 1e-6, 1e6, {0.01, 20}, true)
        .real(
            "sigma-c", "sigma_c", "Range falloff sigma_c on tone-mapped RGB",
            [](auto& c) -> auto& { return c.filter.sigmaC; }, 1e-6, 1e6, {0.005, 1}, true)
        .list("phi", "phi",
              "Bias thresholds Phi choosing alpha (ascending, one fewer than --alphas)",
              [](auto& c) -> auto& { return c.filter.phi; }, 0, 1e6, {0, 2})
        .integer(
            "second-pass-alpha", "second pass alpha",
            "Index (from 0) into --alphas of the second pass's falloff (alpha_3)",
            [](auto& c) -> auto& { return c.filter.secondPassAlpha; }, 0, 15);
    t.group("BP paper algorithm: ablations (ALGORITHM.md section 12)")
        .choice<CandidateMode>(
            "candidate-mode", "candidates",
            "traced: trace every candidate and keep the best (eq. 16); predicted: score "
            "candidates by the network, trace only the best, then test it for outliers",
            [](auto& c) -> auto& { return c.candidateMode; }, {"traced", "predicted"})
        .real(
            "outlier-tau", "outlier tau",
            "Predicted mode: reject a sample whose relative distance to its slice's mean "
            "exceeds this",
            [](auto& c) -> auto& { return c.outlierTau; }, 1e-6, 1e6, {0.1, 20}, true)
        .toggle(
            "warping", "warping",
            "Do not move slice B's sample into slice C: every slice gets its own", "--no-warping",
            [](auto& c) -> auto& { return c.warping; })
        .toggle(
            "outlier-removal", "outlier removal (eq. 16)",
            "Keep the first candidate (one traced sample per slot, no eq. 16 choice, no "
            "outlier test)",
            "--no-outlier-removal", [](auto& c) -> auto& { return c.outlierRemoval; })
        .toggle(
            "second-pass", "second pass", "Skip the second bilateral pass (alpha_3)",
            "--no-second-pass", [](auto& c) -> auto& { return c.filter.secondPass; })
        .toggle(
            "stratified-mean", "stratified mean",
            "Pixel estimate = plain mean of its samples instead of the mean of slice means",
            "--plain-mean", [](auto& c) -> auto& { return c.stratifiedMean; })
        .toggle(
            "top-up", "top up",
            "Sample only difficult pixels (bias > Psi, er > e), even if budget is left over",
            "--no-top-up", [](auto& c) -> auto& { return c.topUp; });
    return t;
  }();
  return table;
}

const MethodDescriptor& bpPaperMethod() {
  static const MethodDescriptor descriptor([] {
    MethodDefinition<BpPaperConfig> d;
    d.name = "bp";
    d.algorithm = "paper";
    d.description = "BP networks (the paper's method)";
    d.params = &bpPaperParams();
    d.presets = {
        {"paper", "ALGORITHM.md's recommended resolutions of the paper", nullptr},
        {"tuned",
         "the paper's rounds without candidate choice (it biases towards the slice's majority "
         "value) or warping, the plain pixel mean (the stratified mean of few samples per "
         "slice loses the lens/time stratification), sigma_c 0.05 (0.3 blurs texture)",
         [](BpPaperConfig& c) {
           c.outlierRemoval = false;
           c.warping = false;
           c.stratifiedMean = false;
           c.filter.sigmaC = 0.05f;
         }}};
    d.maps = {&maps::ErrorEstimate, &maps::Selected,    &maps::FilterScale,
              &maps::SampleCount,   &maps::TracedCount, &maps::NetworkError,
              &maps::Prediction,    &maps::SliceB,      &maps::SliceC};
    // No variance of the mean, and its bias is no error estimate to stop on.
    d.abilities = [](const BpPaperConfig& c) {
      return MethodAbilities{false, c.reconstruct, true, false};
    };
    d.check = [](const BpPaperConfig& c, const RunShape& shape) { return c.check(shape); };
    d.make = [](const PreparedScene& prepared, const RunShape& shape,
                const BpPaperConfig& c) -> std::unique_ptr<ProgressiveMethod> {
      return makeBpPaperMethod(prepared, shape, c);
    };
    d.withoutReconstruction = [](BpPaperConfig& c) { c.reconstruct = false; };
    return d;
  }());
  return descriptor;
}

}  // namespace penumbra
