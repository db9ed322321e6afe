#include "methods/factory.h"

#include <stdexcept>
#include <type_traits>

namespace penumbra {

namespace {
struct Entry {
  MethodKind kind;
  const char* name;
  const char* description;
};
constexpr Entry kMethods[] = {
    {MethodKind::Ld, "ld", "Low discrepancy (box filter)"},
    {MethodKind::Bp, "bp", "BP networks (the paper's method)"},
    {MethodKind::FDiv, "fdiv", "F-divergence, Hellinger (Rigau et al. 2003)"},
    {MethodKind::Fuzzy, "fuzzy", "Fuzzy uncertainty (re-implemented, after Xu et al. 2008)"},
    {MethodKind::Gem, "gem", "GEM (Rousselle et al. 2011)"},
    {MethodKind::Cycles, "cycles", "Cycles half-buffer error (Dammertz et al. 2010)"},
};

template <typename Config>
std::vector<MethodParam> erase(const ParamTable<Config>& table) {
  std::vector<MethodParam> out;
  for (const Param<Config>& p : table.params())
    out.push_back(rebindParam<MethodConfig>(
        p, [](auto& c) -> auto& { return std::get<Config>(c); }));
  return out;
}
}  // namespace

const std::vector<MethodParam>& methodParams(MethodKind kind) {
  static const std::vector<MethodParam> none;
  static const std::vector<MethodParam> ld = erase(ldParams());
  static const std::vector<MethodParam> bp = erase(bpParams());
  static const std::vector<MethodParam> fdiv = erase(fdivParams());
  static const std::vector<MethodParam> fuzzy = erase(fuzzyParams());
  static const std::vector<MethodParam> gem = erase(gemParams());
  static const std::vector<MethodParam> cycles = erase(cyclesParams());
  switch (kind) {
    case MethodKind::Ld:
      return ld;
    case MethodKind::Bp:
      return bp;
    case MethodKind::FDiv:
      return fdiv;
    case MethodKind::Fuzzy:
      return fuzzy;
    case MethodKind::Gem:
      return gem;
    case MethodKind::Cycles:
      return cycles;
  }
  return none;
}

std::string describeChanges(const MethodSpec& spec, const MethodConfig& base) {
  std::string text;
  for (const MethodParam& p : methodParams(spec.kind())) {
    const std::string value = formatParam(p, spec.config);
    if (value != formatParam(p, base)) text += (text.empty() ? "" : " ") + p.name + "=" + value;
  }
  return text;
}

std::optional<MethodKind> parseMethodKind(std::string_view name) {
  for (const Entry& e : kMethods)
    if (name == e.name) return e.kind;
  return std::nullopt;
}

const char* toString(MethodKind kind) {
  for (const Entry& e : kMethods)
    if (e.kind == kind) return e.name;
  return "?";
}

const char* describe(MethodKind kind) {
  for (const Entry& e : kMethods)
    if (e.kind == kind) return e.description;
  return "?";
}

const std::vector<std::string>& methodNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Entry& e : kMethods) v.push_back(e.name);
    return v;
  }();
  return names;
}

MethodConfig defaultConfig(MethodKind kind) {
  switch (kind) {
    case MethodKind::Ld:
      return LdConfig{};
    case MethodKind::Bp:
      return BpConfig{};
    case MethodKind::FDiv:
      return FDivConfig{};
    case MethodKind::Fuzzy:
      return FuzzyConfig{};
    case MethodKind::Gem:
      return GemConfig{};
    case MethodKind::Cycles:
      return CyclesConfig{};
  }
  throw std::invalid_argument("unknown method");
}

std::vector<MethodConfig> defaultConfigs() {
  std::vector<MethodConfig> configs;
  for (const Entry& e : kMethods) configs.push_back(defaultConfig(e.kind));
  return configs;
}

std::string validate(const MethodSpec& s) {
  return std::visit(
      [&](const auto& c) -> std::string {
        using Config = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<Config, LdConfig>) {
          return s.shape.validate();
        } else {
          if constexpr (std::is_same_v<Config, GemConfig>)
            if (!(c.gamma > 0.0f && c.gamma < 1.0f / 1.9f)) return "gamma must be in (0, 0.526)";
          return c.validate(s.shape);
        }
      },
      s.config);
}

std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared, const MethodSpec& s) {
  if (const std::string error = validate(s); !error.empty()) throw std::invalid_argument(error);
  return std::visit(
      [&](const auto& c) -> std::unique_ptr<ProgressiveMethod> {
        using Config = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<Config, LdConfig>) return makeLdMethod(prepared, s.shape, c);
        if constexpr (std::is_same_v<Config, BpConfig>) return makeBpMethod(prepared, s.shape, c);
        if constexpr (std::is_same_v<Config, FDivConfig>)
          return makeFDivMethod(prepared, s.shape, c);
        if constexpr (std::is_same_v<Config, FuzzyConfig>)
          return makeFuzzyMethod(prepared, s.shape, c);
        if constexpr (std::is_same_v<Config, GemConfig>) return makeGemMethod(prepared, s.shape, c);
        if constexpr (std::is_same_v<Config, CyclesConfig>)
          return makeCyclesMethod(prepared, s.shape, c);
      },
      s.config);
}

}  // namespace penumbra
