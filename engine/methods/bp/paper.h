// BP's paper algorithm (ALGORITHM.md §1-§9, §15; `--method bp --preset paper` or `tuned`): a
// coarse low-discrepancy pass, then rounds in which every pixel's BP network is (re)trained on
// its samples, a bias estimate picks the difficult pixels, their sub-pixel slices get new
// samples chosen among candidates (with the less complex slice's sample warped into the more
// complex one), and a bilateral filterbank whose scale follows the bias reconstructs the image.
//
// Budget (§8): with spp = N, exactly N x #pixels samples are kept: N0 in the coarse pass,
// the rest spread over at most maxRounds rounds, difficult pixels first in descending bias
// and topped up with the highest-bias others. Candidates traced but not kept are counted
// separately (traced spp). In open-ended mode (§15) each round adds roundSpp x #pixels
// kept samples until stopped, and per-pixel memory stays bounded: running sums plus a
// reservoir of at most `reservoir` samples for training and eq. 16.
//
// Determinism: every random choice derives from (seed, pixel, sample index), pixels are
// processed independently and the network lanes are grouped by the batch alone, so the
// image after each round does not depend on the number of threads.
#pragma once

#include "methods/bp/config.h"
#include "methods/bp/reconstruct.h"
#include "methods/method.h"
#include "methods/params.h"
#include "methods/progressive.h"
#include "trace/integrator.h"

#include <memory>

namespace penumbra {

enum class CandidateMode { Traced, Predicted };  // §7.2 [A16]: (B) trace all, (A) network

// The paper algorithm's configuration: the shared part, then its own. Its defaults are
// ALGORITHM.md's recommended resolutions (the `paper` preset).
struct BpPaperConfig : BpCommonConfig {
  float psi = 0.05f;        // bias threshold
  int histogramLevels = 5;  // m
  int candidates = 4;       // N_candi
  CandidateMode candidateMode = CandidateMode::Traced;
  float candidateEpsilon = 0.02f;  // eq. 16
  float outlierTau = 4.0f;         // predicted mode's outlier test
  bool warping = true;
  bool outlierRemoval = true;
  bool stratifiedMean = true;  // output = mean of per-slice means [A19]
  bool topUp = true;           // fill each round's budget past the difficult set [A6]
  FilterConfig filter;

  // N0: coarseSpp, or max(4, spp/4) rounded up to a power of two [A7] (4 open-ended).
  int effectiveCoarseSpp(const RunShape& shape) const;
  // What the table's ranges cannot say: empty when valid, else a message naming the flags.
  std::string check(const RunShape& shape) const;
};

const ParamTable<BpPaperConfig>& bpPaperParams();
// The descriptor: `bp` with the presets `paper` (the defaults) and `tuned` (our deviation,
// measured in docs/RESULTS.md to beat low-discrepancy sampling on the four paper scenes: no
// best-of-N candidate choice, no warping, the plain pixel mean and sigma_c = 0.05).
const MethodDescriptor& bpPaperMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeBpPaperMethod(const PreparedScene& prepared,
                                                     const RunShape& shape,
                                                     const BpPaperConfig& config);

}  // namespace penumbra
