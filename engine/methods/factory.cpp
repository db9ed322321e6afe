#include "methods/factory.h"

#include <stdexcept>

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

// A method's configuration with the run's shape (seed, budget, open-ended or not) set.
template <typename Config>
Config withShape(Config c, const MethodSpec& s) {
  c.seed = s.seed;
  c.spp = s.spp;
  c.openEnded = s.openEnded;
  c.roundSpp = s.roundSpp;
  c.maxSpp = s.maxSpp;
  c.sampler = s.sampler;
  return c;
}
AllocationConfig allocationOf(const MethodSpec& s) { return withShape(s.allocation, s); }
BpConfig bpOf(const MethodSpec& s) { return withShape(s.bp, s); }
}  // namespace

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

std::string validate(const MethodSpec& s) {
  switch (s.kind) {
    case MethodKind::Ld:
      if (!s.openEnded && s.spp < 1) return "spp must be at least 1";
      if (s.openEnded && s.roundSpp < 1) return "round spp must be at least 1";
      return {};
    case MethodKind::Bp:
      return bpOf(s).validate();
    case MethodKind::Gem:
      if (!(s.gamma > 0.0f && s.gamma < 1.0f / 1.9f)) return "gamma must be in (0, 0.526)";
      return allocationOf(s).validate();
    default:
      return allocationOf(s).validate();
  }
}

std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared, const MethodSpec& s) {
  if (const std::string error = validate(s); !error.empty()) throw std::invalid_argument(error);
  switch (s.kind) {
    case MethodKind::Ld: {
      LdConfig c;
      c.seed = s.seed;
      c.spp = s.spp;
      c.openEnded = s.openEnded;
      c.roundSpp = s.openEnded ? s.roundSpp : s.spp;
      c.maxSpp = s.maxSpp;
      c.sampler = s.sampler;
      return makeLdMethod(prepared, c);
    }
    case MethodKind::Bp:
      return makeBpMethod(prepared, bpOf(s));
    case MethodKind::Gem: {
      GemConfig c;
      static_cast<AllocationConfig&>(c) = allocationOf(s);
      c.gamma = s.gamma;
      return makeGemMethod(prepared, c);
    }
    case MethodKind::FDiv: {
      FDivConfig c;
      static_cast<AllocationConfig&>(c) = allocationOf(s);
      c.divergence = s.divergence;
      return makeFDivMethod(prepared, c);
    }
    case MethodKind::Fuzzy: {
      FuzzyConfig c;
      static_cast<AllocationConfig&>(c) = allocationOf(s);
      return makeFuzzyMethod(prepared, c);
    }
    case MethodKind::Cycles: {
      CyclesConfig c;
      static_cast<AllocationConfig&>(c) = allocationOf(s);
      return makeCyclesMethod(prepared, c);
    }
  }
  throw std::invalid_argument("unknown method");
}

}  // namespace penumbra
