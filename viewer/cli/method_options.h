// Command-line options that choose and configure the rendering method (--method, every
// parameter of the BP method: the paper's Table 1 and the ablation switches of
// ALGORITHM.md §12, and the baselines' schedule and criteria of §10), shared by `render` and the
// commands that will run methods too.
#pragma once

#include "methods/factory.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace penumbra {

struct MethodOptions {
  std::string method = "ld";
  std::string preset = "paper";
  BpConfig bp;                                // defaults = the recommended values
  const CLI::Option* sigmaCOption = nullptr;  // given explicitly, it overrides the preset
  std::string targets = "per-sample";
  std::string candidateMode = "traced";
  std::string learningRate = "bold";
  bool noWarping = false, noOutlierRemoval = false, noSecondPass = false, plainMean = false;
  bool noTopUp = false, noReconstruct = false;
  AllocationConfig allocation;  // the baselines' schedule (--initial-spp, --batch)
  std::string divergence = "hellinger";
  float gamma = 0.2f;
  bool isBp() const { return method == "bp"; }
  bool isLd() const { return method == "ld"; }
  // The BP configuration for a render of `spp` kept samples with `seed`; throws
  // CommandError naming the flag on an inconsistent combination.
  BpConfig bpConfig(int spp, uint64_t seed, SamplerKind sampler) const;
  // Any method's full specification for such a render; throws CommandError likewise.
  MethodSpec spec(int spp, uint64_t seed, SamplerKind sampler) const;
};

// batchSchedule: also --rounds (the batch schedule's adaptive rounds); the viewer runs
// open-ended and uses --rounds for its own purpose.
void addMethodOptions(CLI::App& command, MethodOptions& options, bool batchSchedule = true);

}  // namespace penumbra
