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

#include "methods/bp/network.h"
#include "methods/bp/reconstruct.h"
#include "methods/bp/slices.h"
#include "methods/ld.h"
#include "methods/progressive.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <memory>

namespace penumbra {

enum class TargetMode { PerSample, PixelMean };  // §4.3 [A8]
enum class CandidateMode { Traced, Predicted };  // §7.2 [A16]: (B) trace all, (A) network

struct BpConfig {
  uint64_t seed = 0;
  int spp = 16;       // kept samples per pixel (batch mode)
  int coarseSpp = 0;  // N0; 0 = max(4, spp/4) rounded up to a power of two [A7]
  int maxRounds = 8;  // adaptive rounds of the batch schedule
  bool openEnded = false;
  int roundSpp = 1;  // open-ended: kept samples per pixel per round, on average
  int maxSpp = 0;    // open-ended: stop at this average kept spp (0 = never)
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
  SamplerKind sampler = SamplerKind::LowDiscrepancy;

  int effectiveCoarseSpp() const;
  // Empty when valid, else a message naming the offending parameter.
  std::string validate() const;
};

// Named configurations. Paper: ALGORITHM.md's recommended resolutions (the defaults of
// BpConfig). Tuned: our deviation, measured in docs/RESULTS.md to beat low-discrepancy
// sampling on the four paper scenes: no best-of-N candidate choice (it biases towards the
// slice's majority value), no warping, the plain pixel mean (the stratified mean of few
// samples per slice loses the lens/time stratification) and a tighter range falloff
// sigma_c = 0.05 (0.3 blurs texture).
enum class BpPreset { Paper, Tuned };
void applyBpPreset(BpConfig& config, BpPreset preset);
const char* toString(BpPreset preset);

// Creates the BP method on a prepared scene (which must outlive it). Throws
// std::invalid_argument with validate()'s message on a bad configuration.
std::unique_ptr<ProgressiveMethod> makeBpMethod(const PreparedScene& prepared,
                                                const BpConfig& config);

// Building blocks, exposed for tests.
namespace bp {

// Network input vector of a sample at centred offsets (dx, dy) with lens (u, v), time t.
void networkInputs(int inputs, float dx, float dy, float u, float v, float t, float* x);

// eq. 13 with an L1 norm over RGB and the regulariser: sum|I' - I| / (sum I + eps); 0 if
// the pixel mean is exactly black [A13].
float biasOf(vec3 prediction, vec3 mean, float eps);

// The K (u, v, t) points used for I': a 3-D Halton sequence (bases 2, 3, 5) shifted by a
// per-pixel rotation, modulo 1; K = 1 gives one random point.
void predictionPoints(int count, uint64_t pixelKey, float* uvt);

// Kept samples each pixel gets this round: S^2 per selected pixel, pixels in `order`
// (highest priority first), several passes when the budget exceeds one pass, the last
// pixel getting the remainder. Sums exactly to min(budget, ...) = budget when order is
// non-empty.
std::vector<uint32_t> allocateSlots(std::span<const uint32_t> order, size_t pixelCount,
                                    uint64_t budget, int slotsPerPixel);

}  // namespace bp

}  // namespace penumbra
