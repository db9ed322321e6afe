// BP's consistent algorithm: its parameters, their checks and its descriptor.
#include "methods/bp/consistent.h"

#include "methods/bp/slices.h"
#include "methods/bp/state.h"
#include "methods/film_reconstruction.h"

#include <algorithm>

namespace penumbra {

int BpConsistentConfig::effectiveCoarseSpp(const RunShape& shape) const {
  if (coarseSpp > 0) return coarseSpp;
  if (shape.openEnded) return 4;
  return std::min(shape.spp, std::max(4, int(roundUpPowerOfTwo(uint32_t(shape.spp / 8)))));
}

std::string BpConsistentConfig::check(const RunShape& shape) const {
  // Without networks it stores no samples: its film holds the sums.
  if (std::string problem = BpCommonConfig::check(shape, effectiveCoarseSpp(shape), usesNetworks());
      !problem.empty())
    return problem;
  return recon::validate(denoise);
}

const ParamTable<BpConsistentConfig>& bpConsistentParams() {
  static const ParamTable<BpConsistentConfig> table = [] {
    ParamTable<BpConsistentConfig> t;
    t.include(bpCommonParams());
    t.group("BP consistent algorithm (--preset consistent)")
        .real("retrain-growth", "retrain growth",
              "Retrain a pixel's network once its samples grew by this factor",
              [](auto& c) -> auto& { return c.retrainGrowth; }, 1, 1e6, {1, 4})
        .integer("networks", "networks",
                 "1: networks fitted to the neighbours' samples over their offsets, lens, time and "
                 "light sample correct the samples of the pixels that vary most (a control "
                 "variate); 0: none",
                 [](auto& c) -> auto& { return c.networks; }, 0, 1, {0, 1})
        .integer("reach", "network reach",
                 "A network fits the samples of its pixel's (2 reach + 1)^2 neighbourhood",
                 [](auto& c) -> auto& { return c.netRecon.reach; }, 1, 4, {1, 4})
        .real("network-share", "network share",
              "At most this share of the pixels train a network: those whose samples vary most",
              [](auto& c) -> auto& { return c.netRecon.share; }, 0, 1, {0, 0.2f})
        .integer("network-samples", "network samples",
                 "Samples a pixel keeps for its neighbours' networks",
                 [](auto& c) -> auto& { return c.netRecon.capacity; }, 1, 1024, {4, 64})
        .integer("network-epochs", "network epochs",
                 "Epochs of a network's first training (a warm retraining takes half)",
                 [](auto& c) -> auto& { return c.netRecon.epochs; }, 1, 100000, {10, 400})
        .real("network-weight", "network weight",
              "A pixel's estimated error is scaled by 1 + this x its network bias (0: the "
              "networks are not trained)",
              [](auto& c) -> auto& { return c.networkWeight; }, 0, 1e6, {0, 8})
        .real("absolute-weight", "absolute weight",
              "A pixel's error is its raw relMSE plus this x its 7x7 neighbourhood's mean raw MSE "
              "over the image's mean squared (0: relMSE only)",
              [](auto& c) -> auto& { return c.absoluteWeight; }, 0, 1e6, {0, 8})
        .real("sample-floor", "sample floor",
              "Every pixel keeps at least this share of the mean sample count",
              [](auto& c) -> auto& { return c.allocation.floorFraction; }, 0, 1, {0, 1})
        .toggle(
            "slice-steering", "slice steering",
            "Send each pixel's new samples to its S x S slices by their variance (Neyman "
            "allocation) and estimate the pixel by the slices' area-weighted mean",
            "--slice-steering", [](auto& c) -> auto& { return c.sliceSteering; })
        .include(
            recon::denoiseParams(), [](auto& c) -> auto& { return c.denoise; });
    return t;
  }();
  return table;
}

const MethodDescriptor& bpConsistentMethod() {
  static const MethodDescriptor descriptor([] {
    MethodDefinition<BpConsistentConfig> d;
    d.name = "bp";
    d.algorithm = "consistent";
    d.description = "BP networks (the paper's method)";
    d.params = &bpConsistentParams();
    d.presets = {{"consistent",
                  "the consistent reconstruction of the film and samples where its estimated "
                  "error falls most (the networks off: --network-weight turns them on)",
                  nullptr}};
    d.maps = {&maps::ErrorEstimate, &maps::Selected,     &maps::FilterScale, &maps::SampleCount,
              &maps::TracedCount,   &maps::NetworkError, &maps::Prediction,  &maps::Albedo,
              &maps::Normal,        &maps::Depth,        &maps::Emission,    &maps::RawError,
              &maps::Networks};
    d.abilities = [](const BpConsistentConfig& c) {
      return MethodAbilities{true, c.reconstruct, true, true};
    };
    d.check = [](const BpConsistentConfig& c, const RunShape& shape) { return c.check(shape); };
    d.make = [](const PreparedScene& prepared, const RunShape& shape,
                const BpConsistentConfig& c) -> std::unique_ptr<ProgressiveMethod> {
      return makeBpConsistentMethod(prepared, shape, c);
    };
    d.withoutReconstruction = [](BpConsistentConfig& c) { c.reconstruct = false; };
    return d;
  }());
  return descriptor;
}

}  // namespace penumbra
