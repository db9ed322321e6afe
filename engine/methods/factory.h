// Every rendering method by name, and the one factory `render`, `view`, `compare` and
// `reference` build methods with: a MethodSpec is the run's shape (the same for every
// method, ALGORITHM.md §11's fair comparison) and the chosen method's own configuration.
#pragma once

#include "methods/bp/method.h"
#include "methods/cycles.h"
#include "methods/fdiv.h"
#include "methods/fuzzy.h"
#include "methods/gem.h"
#include "methods/ld.h"
#include "methods/run_shape.h"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace penumbra {

// In the order of MethodConfig's alternatives.
enum class MethodKind { Ld, Bp, FDiv, Fuzzy, Gem, Cycles };

using MethodConfig =
    std::variant<LdConfig, BpConfig, FDivConfig, FuzzyConfig, GemConfig, CyclesConfig>;

std::optional<MethodKind> parseMethodKind(std::string_view name);
const char* toString(MethodKind kind);
// "ld", "bp", "fdiv", "fuzzy", "gem", "cycles".
const std::vector<std::string>& methodNames();
// One line for people: "Low discrepancy (box filter)", "Fuzzy uncertainty (re-implemented)".
const char* describe(MethodKind kind);
// The method's default configuration, and every method's, in MethodKind's order.
MethodConfig defaultConfig(MethodKind kind);
std::vector<MethodConfig> defaultConfigs();

struct MethodSpec {
  RunShape shape;
  MethodConfig config;  // LdConfig by default

  MethodKind kind() const { return MethodKind(config.index()); }
  template <typename Config>
  Config* get() {
    return std::get_if<Config>(&config);
  }
  template <typename Config>
  const Config* get() const {
    return std::get_if<Config>(&config);
  }
};

// The method's parameters over MethodConfig (each entry reads and writes the alternative of
// `kind`), for code that handles every method alike: the command line, the panel, the stats.
using MethodParam = Param<MethodConfig>;
const std::vector<MethodParam>& methodParams(MethodKind kind);
// "nit=20 sigma-c=0.1": the parameters of `spec` that differ from `base` (of the same method).
std::string describeChanges(const MethodSpec& spec, const MethodConfig& base);

// Empty when the spec is valid, else a message naming the parameter.
std::string validate(const MethodSpec& spec);
// Throws std::invalid_argument with validate()'s message; the scene must outlive it.
std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared,
                                              const MethodSpec& spec);

}  // namespace penumbra
