// Validation and presets of the BP method's parameters.
#include "methods/bp/config.h"

#include "methods/bp/slices.h"
#include "methods/film_reconstruction.h"

#include <algorithm>

namespace penumbra {

int BpConfig::effectiveCoarseSpp(const RunShape& shape) const {
  if (coarseSpp > 0) return coarseSpp;
  if (shape.openEnded) return 4;
  if (algorithm == BpAlgorithm::Consistent)  // an eighth: allocation has more to spend
    return std::min(shape.spp, std::max(4, int(roundUpPowerOfTwo(uint32_t(shape.spp / 8)))));
  const int quarter = int(roundUpPowerOfTwo(uint32_t(std::max(1, shape.spp / 4))));
  return std::min(shape.spp, std::max(4, quarter));
}

std::string BpConfig::validate(const RunShape& shape) const {
  auto bad = [](const std::string& what) { return what; };
  if (const std::string problem = shape.validate(); !problem.empty()) return problem;
  if (coarseSpp < 0) return bad("--coarse-spp must be at least 1 (or 0 for automatic)");
  if (!shape.openEnded && coarseSpp > shape.spp) return bad("--coarse-spp cannot exceed --spp");
  if (maxRounds < 1) return bad("--rounds must be at least 1");
  if (network.inputs != 4 && network.inputs != 5) return bad("--inputs must be 4 or 5");
  if (network.hidden < 1 || network.hidden > kMaxNetHidden)
    return bad("--hidden must be in 1.." + std::to_string(kMaxNetHidden));
  if (network.epochs < 0) return bad("--nit must be at least 0");
  if (!(network.muMin > 0 && network.muMin <= network.muStart && network.muStart <= network.muMax))
    return bad("learning rates must satisfy 0 < min <= start <= max");
  if (predictionDraws < 1) return bad("--prediction-draws must be at least 1");
  if (slicesPerSide < 1 || slicesPerSide > kMaxSlicesPerSide)
    return bad("--slices must be in 1.." + std::to_string(kMaxSlicesPerSide));
  if (histogramLevels < 1 || histogramLevels > kMaxHistogramLevels)
    return bad("--levels must be in 1.." + std::to_string(kMaxHistogramLevels));
  if (candidates < 1) return bad("--candidates must be at least 1");
  if (!(psi >= 0)) return bad("--psi must be at least 0");
  if (!(biasEpsilon > 0)) return bad("--bias-epsilon must be positive");
  if (!(outlierTau > 0)) return bad("--outlier-tau must be positive");
  // The consistent algorithm without networks stores no samples (its film holds the sums).
  const bool stores = algorithm == BpAlgorithm::Paper || networkWeight > 0;
  if (stores && reservoir < effectiveCoarseSpp(shape))
    return bad("--reservoir must hold at least the coarse pass (" +
               std::to_string(effectiveCoarseSpp(shape)) + " samples)");
  if (filter.alphas.size() < 1 || filter.phi.size() + 1 != filter.alphas.size())
    return bad("--phi needs exactly one threshold fewer than --alphas has values");
  if (!std::is_sorted(filter.phi.begin(), filter.phi.end()))
    return bad("--phi thresholds must be ascending");
  for (float a : filter.alphas)
    if (!(a > 0)) return bad("--alphas must be positive");
  if (filter.radius < 0 || filter.radius > 32) return bad("--radius must be in 0..32");
  if (!(filter.sigmaC > 0)) return bad("--sigma-c must be positive");
  if (!(retrainGrowth >= 1)) return bad("--retrain-growth must be at least 1");
  if (!(networkWeight >= 0)) return bad("--network-weight must be at least 0");
  if (!(allocation.floorFraction >= 0 && allocation.floorFraction <= 1))
    return bad("--sample-floor must be in 0..1");
  if (const std::string problem = recon::validate(denoise); !problem.empty()) return problem;
  if (filter.secondPassAlpha < 0 || filter.secondPassAlpha >= int(filter.alphas.size()))
    return bad("the second pass alpha index is out of range");
  return {};
}

void applyBpPreset(BpConfig& config, BpPreset preset) {
  const BpConfig paper;
  const bool tuned = preset == BpPreset::Tuned;
  const bool consistent = preset == BpPreset::Consistent;
  config.algorithm = consistent ? BpAlgorithm::Consistent : paper.algorithm;
  // The networks only indicate sub-pixel structure there (docs/RESULTS.md: they add little):
  // a third of the paper's epochs bounds their cost.
  if (consistent) config.network.epochs = 20;
  // Measured (docs/RESULTS.md): at equal time the networks' indicator costs more than it
  // gains on every shipped scene, so the preset leaves it off; bp:network-weight=1 is the
  // ablation that shows it.
  if (consistent) config.networkWeight = 0.0f;
  // Both objectives in the ranking: relMSE alone starves an emitter's bright edge, whose
  // absolute error dominates the MSE (docs/bp-method.md).
  if (consistent) config.absoluteWeight = 0.25f;
  // Half the paper's rounds: each round's ranking costs the same whatever it spends, and
  // measured at 16 and 64 spp on tire, balls and cornell (2 seeds) 4 rounds give the same MSE
  // as 8 (0.98-1.01x) for half the selection time (docs/bp-method.md).
  if (consistent) config.maxRounds = 4;
  config.outlierRemoval = tuned ? false : paper.outlierRemoval;
  config.warping = tuned ? false : paper.warping;
  config.stratifiedMean = tuned ? false : paper.stratifiedMean;
  config.filter.sigmaC = tuned ? 0.05f : paper.filter.sigmaC;
}

const char* toString(BpPreset preset) {
  switch (preset) {
    case BpPreset::Paper:
      return "paper";
    case BpPreset::Tuned:
      return "tuned";
    case BpPreset::Consistent:
      return "consistent";
  }
  return "?";
}

std::optional<BpPreset> parseBpPreset(std::string_view name) {
  if (name == "paper") return BpPreset::Paper;
  if (name == "tuned") return BpPreset::Tuned;
  if (name == "consistent") return BpPreset::Consistent;
  return std::nullopt;
}

const ParamTable<BpConfig>& bpParams() {
  static const ParamTable<BpConfig> table = [] {
    ParamTable<BpConfig> t;
    t.group("BP method (paper's Table 1)")
        .integer("nit", "Nit", "Training epochs per (re)training, Nit",
                 [](auto& c) -> auto& { return c.network.epochs; }, 0, 100000, {0, 200})
        .integer(
            "hidden", "hidden Nm", "Hidden units Nm",
            [](auto& c) -> auto& { return c.network.hidden; }, 1, kMaxNetHidden)
        .integer(
            "inputs", "inputs",
            "Network inputs: 4 = (radius, u, v, t) as in the paper's experiments, "
            "5 = (dx, dy, u, v, t)",
            [](auto& c) -> auto& { return c.network.inputs; }, 4, 5)
        .real("psi", "psi", "Bias threshold Psi: pixels above it are difficult",
              [](auto& c) -> auto& { return c.psi; }, 0, 1e6, {0, 1})
        .real("error-threshold", "e",
              "Network error threshold e: training stops below it, and pixels with er <= e "
              "count as converged",
              [](auto& c) -> auto& { return c.network.errorThreshold; }, 0, 1e9, {0, 1})
        .integer("candidates", "candidates", "Candidates per new sample, N_candi",
                 [](auto& c) -> auto& { return c.candidates; }, 1, 64, {1, 16})
        .integer(
            "slices", "slices S", "Slices per pixel side S (S x S slices)",
            [](auto& c) -> auto& { return c.slicesPerSide; }, 1, kMaxSlicesPerSide)
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
            [](auto& c) -> auto& { return c.filter.secondPassAlpha; }, 0, 15)
        .real("bias-h", "b_h", "Fixed hidden threshold b_h",
              [](auto& c) -> auto& { return c.network.biasHidden; }, -1e6, 1e6, {-1, 1})
        .real("bias-o", "b_o", "Fixed output threshold b_o",
              [](auto& c) -> auto& { return c.network.biasOutput; }, -1e6, 1e6, {-1, 1})
        .choice<LearningRateMode>(
            "learning-rate", "learning rate",
            "Learning-rate control by er: bold (x1.05 on improvement, x0.7 on a rise) or "
            "proportional (to er / er_first)",
            [](auto& c) -> auto& { return c.network.rate; }, {"bold", "proportional"})
        .real("mu", "mu", "Initial learning rate",
              [](auto& c) -> auto& { return c.network.muStart; }, 1e-6, 10, {0.001, 0.5})
        .real("mu-min", "mu min", "Smallest learning rate",
              [](auto& c) -> auto& { return c.network.muMin; }, 1e-6, 10, {0.001, 0.5})
        .real("mu-max", "mu max", "Largest learning rate",
              [](auto& c) -> auto& { return c.network.muMax; }, 1e-6, 10, {0.001, 0.5});
    t.group("BP method: schedule")
        .integer("coarse-spp", "coarse spp N0",
                 "Samples per pixel of the coarse pass N0 (0 = max(4, spp/4), a power of two)",
                 [](auto& c) -> auto& { return c.coarseSpp; }, 0, 1 << 20, {0, 64})
        .integer("rounds", "rounds",
                 "Adaptive rounds that spend the rest of the budget (BP and the baselines)",
                 [](auto& c) -> auto& { return c.maxRounds; }, 1, 1000, {1, 32})
        .integer("reservoir", "reservoir",
                 "Samples kept per pixel for training and candidate scoring (bounds memory)",
                 [](auto& c) -> auto& { return c.reservoir; }, 1, 1 << 16, {4, 256});
    t.group("BP method: consistent algorithm")
        .choice<BpAlgorithm>("algorithm", "algorithm",
                             "paper: ALGORITHM.md's rounds and bilateral filterbank; consistent: "
                             "the film's consistent reconstruction and allocation by its error",
                             [](auto& c) -> auto& { return c.algorithm; }, {"paper", "consistent"})
        .real("retrain-growth", "retrain growth",
              "Consistent: retrain a pixel's network once its samples grew by this factor",
              [](auto& c) -> auto& { return c.retrainGrowth; }, 1, 1e6, {1, 4})
        .real("network-weight", "network weight",
              "Consistent: a pixel's estimated error is scaled by 1 + this x its network bias "
              "(0: the networks are not used)",
              [](auto& c) -> auto& { return c.networkWeight; }, 0, 1e6, {0, 8})
        .real("absolute-weight", "absolute weight",
              "Consistent: a pixel's error is its raw relMSE plus this x its 7x7 "
              "neighbourhood's mean raw MSE over the image's mean squared (0: relMSE only)",
              [](auto& c) -> auto& { return c.absoluteWeight; }, 0, 1e6, {0, 8})
        .real("sample-floor", "sample floor",
              "Consistent: every pixel keeps at least this share of the mean sample count",
              [](auto& c) -> auto& { return c.allocation.floorFraction; }, 0, 1, {0, 1})
        .toggle(
            "slice-steering", "slice steering",
            "Consistent: send each pixel's new samples to its S x S slices by their variance "
            "(Neyman allocation) and estimate the pixel by the slices' area-weighted mean",
            "--slice-steering", [](auto& c) -> auto& { return c.sliceSteering; })
        .include(
            denoiseParams(), [](auto& c) -> auto& { return c.denoise; });
    t.group("BP method: ablations (ALGORITHM.md section 12)")
        .choice<TargetMode>("targets", "targets",
                            "Training targets: per-sample (each sample's tone-mapped radiance) or "
                            "pixel-mean (the paper's literal reading)",
                            [](auto& c) -> auto& { return c.targets; },
                            {"per-sample", "pixel-mean"})
        .integer("prediction-draws", "I' draws K",
                 "Lens/time draws K averaged for the prediction I' (1 = the paper's one draw)",
                 [](auto& c) -> auto& { return c.predictionDraws; }, 1, 256, {1, 32})
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
            "--no-top-up", [](auto& c) -> auto& { return c.topUp; })
        .toggle(
            "reconstruct", "reconstruct",
            "Output the raw per-pixel estimate, without the bilateral filterbank",
            "--no-reconstruct", [](auto& c) -> auto& { return c.reconstruct; });
    return t;
  }();
  return table;
}

}  // namespace penumbra
