// BP's consistent algorithm (`--method bp`, the default, and `--preset consistent`;
// consistent.cpp says what it does): the film's consistent reconstruction, samples where its
// estimated error falls most, and the per-pixel networks as an optional indicator of sub-pixel
// structure (off by default: measured, they cost more than they gain).
#pragma once

#include "methods/bp/config.h"
#include "methods/bp/net_recon.h"
#include "methods/error_allocation.h"
#include "methods/method.h"
#include "methods/progressive.h"
#include "methods/recon/denoise.h"
#include "methods/run_shape.h"
#include "trace/integrator.h"

#include <memory>

namespace penumbra {

// The consistent algorithm's configuration: the shared part, then its own. Its defaults are
// the `consistent` preset.
struct BpConsistentConfig : BpCommonConfig {
  BpConsistentConfig() {
    // The networks only indicate sub-pixel structure here: a third of the paper's epochs
    // bounds their cost (docs/RESULTS.md: they add little).
    network.epochs = 20;
    // Half the paper's rounds: each round's ranking costs the same whatever it spends, and
    // measured at 16 and 64 spp on tire, balls and cornell (2 seeds) 4 rounds give the same MSE
    // as 8 (0.98-1.01x) for half the selection time (docs/bp-method.md).
    maxRounds = 4;
  }
  recon::DenoiseConfig denoise;
  float retrainGrowth = 1.5f;  // retrain a network once its pixel's samples grew this much
  // A pixel's error is scaled by 1 + weight x its network bias. Measured (docs/RESULTS.md): at
  // equal time the networks' indicator costs more than it gains on every shipped scene, so the
  // default leaves it off; bp:network-weight=1 is the ablation that shows it.
  float networkWeight = 0.0f;
  // 1: networks fitted to the neighbours' samples over their dimensions correct the samples
  // of the pixels whose samples vary most (methods/bp/net_recon.h, a control variate); 0:
  // none. (network-weight's indicator is apart.)
  int networks = 0;
  bp::NetReconConfig netRecon;
  // A pixel's error is its raw relMSE plus this x its neighbourhood's raw MSE over the image's
  // mean value squared: the sum of the two objectives, so bright noisy pixels (an emitter's
  // edge) are not starved by the relative measure alone. At 16 spp cornell's MSE fell from
  // 0.61x to 0.07x LD's, relMSE 0.11x -> 0.12x (docs/bp-method.md).
  float absoluteWeight = 0.25f;
  ErrorAllocation allocation;
  // Within a pixel, each new sample goes to the S x S slice (`slicesPerSide`) where it lowers
  // the stratified estimate's variance most (Neyman allocation, per-slice variances shrunk
  // towards the pixel's), drawn from that slice's own low-discrepancy stream; the estimate is
  // the slices' area-weighted mean (methods/film.h). Off by default: measured, it gains
  // nothing (docs/bp-method.md).
  bool sliceSteering = false;

  // The paper's per-pixel networks as an indicator of the allocation (network-weight > 0).
  bool usesNetworks() const { return networkWeight > 0; }
  // The networks that correct the samples (--networks 1).
  bool correctsWithNetworks() const { return networks != 0; }
  // N0: coarseSpp, or an eighth of spp (allocation has more to spend), at least 4, rounded up
  // to a power of two (4 open-ended).
  int effectiveCoarseSpp(const RunShape& shape) const;
  // What the table's ranges cannot say: empty when valid, else a message naming the flags.
  std::string check(const RunShape& shape) const;
};

const ParamTable<BpConsistentConfig>& bpConsistentParams();
// The descriptor: `bp`, the default, with the preset `consistent` (its defaults).
const MethodDescriptor& bpConsistentMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeBpConsistentMethod(const PreparedScene& prepared,
                                                          const RunShape& shape,
                                                          const BpConsistentConfig& config);

}  // namespace penumbra
