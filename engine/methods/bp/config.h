// The BP method's parameters (the paper's Table 1, ALGORITHM.md's resolutions and the
// ablations of §12) and its named presets.
#pragma once

#include "methods/bp/network.h"
#include "methods/bp/reconstruct.h"
#include "methods/error_allocation.h"
#include "methods/params.h"
#include "methods/recon/denoise.h"
#include "methods/run_shape.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra {

enum class TargetMode { PerSample, PixelMean };  // §4.3 [A8]
enum class CandidateMode { Traced, Predicted };  // §7.2 [A16]: (B) trace all, (A) network
// paper: the method of ALGORITHM.md (method.cpp); consistent: the film, the consistent
// reconstruction and allocation by its estimated error, the networks steering it (consistent.cpp).
enum class BpAlgorithm { Paper, Consistent };

// Everything but the run's shape (methods/run_shape.h).
struct BpConfig {
  int coarseSpp = 0;  // N0; 0 = max(4, spp/4) rounded up to a power of two [A7]
  int maxRounds = 8;  // adaptive rounds of the batch schedule
  NetworkConfig network;
  TargetMode targets = TargetMode::PerSample;
  int predictionDraws = 8;  // K lens/time draws averaged for I' [A12]
  float biasEpsilon = 0.02f;
  float psi = 0.05f;        // bias threshold
  int slicesPerSide = 2;    // S
  int histogramLevels = 5;  // m
  int candidates = 4;       // N_candi
  CandidateMode candidateMode = CandidateMode::Traced;
  float candidateEpsilon = 0.02f;  // eq. 16
  float outlierTau = 4.0f;         // predicted mode's outlier test
  bool warping = true;
  bool outlierRemoval = true;
  bool stratifiedMean = true;  // output = mean of per-slice means [A19]
  bool topUp = true;           // fill each round's budget past the difficult set [A6]
  bool reconstruct = true;
  FilterConfig filter;
  int reservoir = 64;  // samples kept per pixel for training and eq. 16
  // The consistent algorithm:
  BpAlgorithm algorithm = BpAlgorithm::Paper;
  recon::DenoiseConfig denoise;
  float retrainGrowth = 1.5f;  // retrain a network once its pixel's samples grew this much
  float networkWeight = 1.0f;  // a pixel's error is scaled by 1 + weight x its network bias
  // A pixel's error is its raw relMSE plus this x its neighbourhood's raw MSE over the image's
  // mean value squared: the sum of the two objectives, so bright noisy pixels (an emitter's
  // edge) are not starved by the relative measure alone. The consistent preset sets 0.25: at
  // 16 spp cornell's MSE fell from 0.61x to 0.07x LD's, relMSE 0.11x -> 0.12x
  // (docs/bp-method.md).
  float absoluteWeight = 0.0f;
  ErrorAllocation allocation;
  // Within a pixel, each new sample goes to the S x S slice (`slicesPerSide`) where it lowers
  // the stratified estimate's variance most (Neyman allocation, per-slice variances shrunk
  // towards the pixel's), drawn from that slice's own low-discrepancy stream; the estimate is
  // the slices' area-weighted mean (methods/film.h). Off in the preset: measured, it gains
  // nothing (docs/bp-method.md).
  bool sliceSteering = false;

  int effectiveCoarseSpp(const RunShape& shape) const;
  // Empty when valid for a run of this shape, else a message naming the offending parameter.
  std::string validate(const RunShape& shape) const;
};

// Every parameter above, for the command line, the panel, the stats and compare's labels.
const ParamTable<BpConfig>& bpParams();

// Named configurations. Consistent (the default of `--method bp`): the film's consistent
// reconstruction, allocation by its estimated error and the networks' bias as the indicator
// of sub-pixel structure (consistent.cpp). Paper: ALGORITHM.md's recommended resolutions (the
// defaults of BpConfig). Tuned: our deviation, measured in docs/RESULTS.md to beat low-discrepancy
// sampling on the four paper scenes: no best-of-N candidate choice (it biases towards the
// slice's majority value), no warping, the plain pixel mean (the stratified mean of few
// samples per slice loses the lens/time stratification) and a tighter range falloff
// sigma_c = 0.05 (0.3 blurs texture).
enum class BpPreset { Paper, Tuned, Consistent };
void applyBpPreset(BpConfig& config, BpPreset preset);
const char* toString(BpPreset preset);
std::optional<BpPreset> parseBpPreset(std::string_view name);

}  // namespace penumbra
