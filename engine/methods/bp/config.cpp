// The parameters BP's two algorithms share, and their checks.
#include "methods/bp/config.h"

#include "methods/bp/slices.h"

namespace penumbra {

std::string BpCommonConfig::check(const RunShape& shape, int coarse, bool stores) const {
  if (!shape.openEnded && coarseSpp > shape.spp) return "--coarse-spp cannot exceed --spp";
  if (!(network.muMin <= network.muStart && network.muStart <= network.muMax))
    return "--mu-min, --mu and --mu-max must satisfy min <= start <= max";
  if (stores && reservoir < coarse)
    return "--reservoir must hold at least the coarse pass (" + std::to_string(coarse) +
           " samples)";
  return {};
}

const ParamTable<BpCommonConfig>& bpCommonParams() {
  static const ParamTable<BpCommonConfig> table = [] {
    ParamTable<BpCommonConfig> t;
    t.group("BP: the networks (both algorithms)")
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
        .real("error-threshold", "e",
              "Network error threshold e: training stops below it, and (paper) pixels with "
              "er <= e count as converged",
              [](auto& c) -> auto& { return c.network.errorThreshold; }, 0, 1e9, {0, 1})
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
              [](auto& c) -> auto& { return c.network.muMax; }, 1e-6, 10, {0.001, 0.5})
        .choice<TargetMode>("targets", "targets",
                            "Training targets: per-sample (each sample's tone-mapped radiance) or "
                            "pixel-mean (the paper's literal reading)",
                            [](auto& c) -> auto& { return c.targets; },
                            {"per-sample", "pixel-mean"})
        .integer("prediction-draws", "I' draws K",
                 "Lens/time draws K averaged for the prediction I' (1 = the paper's one draw)",
                 [](auto& c) -> auto& { return c.predictionDraws; }, 1, 256, {1, 32})
        .real(
            "bias-epsilon", "bias epsilon", "Regulariser of the bias, eq. 13's epsilon",
            [](auto& c) -> auto& { return c.biasEpsilon; }, 0, 1e6, {0.001, 1}, true)
        .open(true, false);
    t.group("BP: schedule and slices (both algorithms)")
        .integer("coarse-spp", "coarse spp N0",
                 "Samples per pixel of the coarse pass N0 (0 = automatic: max(4, spp/4) for the "
                 "paper algorithm, max(4, spp/8) for the consistent one, a power of two)",
                 [](auto& c) -> auto& { return c.coarseSpp; }, 0, 1 << 20, {0, 64})
        .integer("rounds", "rounds",
                 "Adaptive rounds that spend the rest of the budget (BP and the baselines)",
                 [](auto& c) -> auto& { return c.maxRounds; }, 1, 1000, {1, 32})
        .integer("reservoir", "reservoir",
                 "Samples kept per pixel for training and candidate scoring (bounds memory)",
                 [](auto& c) -> auto& { return c.reservoir; }, 1, 1 << 16, {4, 256})
        .integer(
            "slices", "slices S", "Slices per pixel side S (S x S slices)",
            [](auto& c) -> auto& { return c.slicesPerSide; }, 1, kMaxSlicesPerSide)
        .toggle(
            "reconstruct", "reconstruct",
            "Output the raw per-pixel estimate, without the reconstruction", "--no-reconstruct",
            [](auto& c) -> auto& { return c.reconstruct; });
    return t;
  }();
  return table;
}

}  // namespace penumbra
