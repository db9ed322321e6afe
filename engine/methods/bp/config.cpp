// Validation and presets of the BP method's parameters.
#include "methods/bp/config.h"

#include "methods/bp/slices.h"

#include <algorithm>

namespace penumbra {

int BpConfig::effectiveCoarseSpp() const {
  if (coarseSpp > 0) return coarseSpp;
  if (openEnded) return 4;
  const int quarter = int(roundUpPowerOfTwo(uint32_t(std::max(1, spp / 4))));
  return std::min(spp, std::max(4, quarter));
}

std::string BpConfig::validate() const {
  auto bad = [](const std::string& what) { return what; };
  if (!openEnded && spp < 1) return bad("--spp must be at least 1");
  if (coarseSpp < 0) return bad("--coarse-spp must be at least 1 (or 0 for automatic)");
  if (!openEnded && coarseSpp > spp) return bad("--coarse-spp cannot exceed --spp");
  if (maxRounds < 1) return bad("--rounds must be at least 1");
  if (openEnded && roundSpp < 1) return bad("--round-spp must be at least 1");
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
  if (reservoir < effectiveCoarseSpp())
    return bad("--reservoir must hold at least the coarse pass (" +
               std::to_string(effectiveCoarseSpp()) + " samples)");
  if (filter.alphas.size() < 1 || filter.phi.size() + 1 != filter.alphas.size())
    return bad("--phi needs exactly one threshold fewer than --alphas has values");
  if (!std::is_sorted(filter.phi.begin(), filter.phi.end()))
    return bad("--phi thresholds must be ascending");
  for (float a : filter.alphas)
    if (!(a > 0)) return bad("--alphas must be positive");
  if (filter.radius < 0 || filter.radius > 32) return bad("--radius must be in 0..32");
  if (!(filter.sigmaC > 0)) return bad("--sigma-c must be positive");
  if (filter.secondPassAlpha < 0 || filter.secondPassAlpha >= int(filter.alphas.size()))
    return bad("the second pass alpha index is out of range");
  return {};
}

void applyBpPreset(BpConfig& config, BpPreset preset) {
  const BpConfig paper;
  const bool tuned = preset == BpPreset::Tuned;
  config.outlierRemoval = tuned ? false : paper.outlierRemoval;
  config.warping = tuned ? false : paper.warping;
  config.stratifiedMean = tuned ? false : paper.stratifiedMean;
  config.filter.sigmaC = tuned ? 0.05f : paper.filter.sigmaC;
}

const char* toString(BpPreset preset) { return preset == BpPreset::Tuned ? "tuned" : "paper"; }

}  // namespace penumbra
