// Every rendering method by name, and one factory: what `render`, `view` and `compare`
// use to run any of them with the same settings (ALGORITHM.md §11's fair comparison).
#pragma once

#include "methods/bp/method.h"
#include "methods/cycles.h"
#include "methods/fdiv.h"
#include "methods/fuzzy.h"
#include "methods/gem.h"
#include "methods/ld.h"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

enum class MethodKind { Ld, Bp, FDiv, Fuzzy, Gem, Cycles };

std::optional<MethodKind> parseMethodKind(std::string_view name);
const char* toString(MethodKind kind);
// "ld", "bp", "fdiv", "fuzzy", "gem", "cycles".
const std::vector<std::string>& methodNames();
// One line for people: "Low discrepancy (box filter)", "Fuzzy uncertainty (re-implemented)".
const char* describe(MethodKind kind);

struct MethodSpec {
  MethodKind kind = MethodKind::Ld;
  BpConfig bp;                  // bp: every parameter but the run's shape below
  AllocationConfig allocation;  // fdiv, fuzzy, gem, cycles: initialSpp, rounds, batch
  Divergence divergence = Divergence::Hellinger;  // fdiv
  float gamma = 0.2f;                             // gem
  // The run's shape, for every method.
  uint64_t seed = 0;
  int spp = 16;
  bool openEnded = false;
  int roundSpp = 1;
  int maxSpp = 0;
  SamplerKind sampler = SamplerKind::LowDiscrepancy;
};

// Empty when the spec is valid, else a message naming the parameter.
std::string validate(const MethodSpec& spec);
// Throws std::invalid_argument with validate()'s message; the scene must outlive it.
std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared,
                                              const MethodSpec& spec);

}  // namespace penumbra
