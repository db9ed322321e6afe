// The paper's method (ALGORITHM.md §1-§9, §15): a coarse low-discrepancy pass, then rounds
// in which every pixel's BP network is (re)trained on its samples, a bias estimate picks
// the difficult pixels, their sub-pixel slices get new samples chosen among candidates
// (with the less complex slice's sample warped into the more complex one), and a bilateral
// filterbank whose scale follows the bias reconstructs the image.
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

#include "methods/bp/candidates.h"
#include "methods/bp/config.h"
#include "methods/bp/error_estimate.h"
#include "methods/bp/trainer.h"
#include "methods/progressive.h"
#include "trace/integrator.h"

#include <memory>

namespace penumbra {

// Creates the BP method on a prepared scene (which must outlive it). Throws
// std::invalid_argument with validate()'s message on a bad configuration.
std::unique_ptr<ProgressiveMethod> makeBpMethod(const PreparedScene& prepared,
                                                const RunShape& shape, const BpConfig& config);

}  // namespace penumbra
