#include "cli/method_options.h"

#include "cli/commands.h"

namespace penumbra {

namespace {

constexpr MethodKind kWithParameters[] = {MethodKind::Bp,    MethodKind::Ld,  MethodKind::FDiv,
                                          MethodKind::Fuzzy, MethodKind::Gem, MethodKind::Cycles};

std::string joined(const std::vector<std::string>& values) {
  std::string s;
  for (const std::string& v : values) s += (s.empty() ? "" : ",") + v;
  return s;
}

}  // namespace

void addMethodOptions(CLI::App& c, MethodOptions& o, const std::set<std::string>& skip) {
  c.add_option_function<std::string>(
       "--method", [&o](const std::string& name) { o.method = *parseMethodKind(name); },
       "Rendering method: ld (low-discrepancy sampling, box filter), bp (the BP "
       "network adaptive sampling and reconstruction), or a baseline: fdiv "
       "(f-divergence), fuzzy (fuzzy uncertainty, re-implemented), gem (greedy error "
       "minimisation with its filterbank), cycles (half-buffer error)")
      ->check(CLI::IsMember(methodNames()))
      ->default_str(toString(o.method));
  c.add_option_function<std::string>(
       "--preset", [&o](const std::string& name) { o.preset = *parseBpPreset(name); },
       "BP configuration: consistent (the default: consistent reconstruction of the film, "
       "samples where its estimated error falls most, the networks steering them), paper "
       "(ALGORITHM.md's recommendations, the defaults below) or tuned (the paper's rounds "
       "without candidate choice or warping, plain mean, --sigma-c 0.05); explicit flags "
       "still apply")
      ->check(CLI::IsMember(
          {toString(BpPreset::Consistent), toString(BpPreset::Paper), toString(BpPreset::Tuned)}))
      ->default_str(toString(o.preset));

  // One flag per parameter name; the first method that has it describes it.
  for (MethodKind kind : kWithParameters) {
    const MethodConfig defaults = defaultConfig(kind);
    for (const MethodParam& p : methodParams(kind)) {
      if (skip.count(p.name) || o.given.count(p.name)) continue;
      MethodOptions::Given& g = o.given[p.name];
      if (p.kind == ParamKind::Flag) {
        g.option = c.add_flag(p.flag, g.flag, p.help)->group(p.group);
        continue;
      }
      CLI::Option* option = c.add_option("--" + p.name, g.values, p.help)
                                ->default_str(formatParam(p, defaults))
                                ->group(p.group);
      if (p.kind == ParamKind::FloatList)
        option->delimiter(',')->expected(0, 16)->type_name("FLOAT")->check(
            CLI::Range(p.min, p.max));
      else if (p.kind == ParamKind::Choice)
        option->expected(1)->type_name("TEXT")->check(CLI::IsMember(p.choices));
      else if (p.kind == ParamKind::Int)
        option->expected(1)->type_name("INT")->check(CLI::Range(int(p.min), int(p.max)));
      else
        option->expected(1)->type_name("FLOAT")->check(CLI::Range(p.min, p.max));
      g.option = option;
    }
  }
}

MethodConfig MethodOptions::config(MethodKind kind, BpPreset bpPreset) const {
  MethodConfig config = defaultConfig(kind);
  if (BpConfig* bp = std::get_if<BpConfig>(&config)) applyBpPreset(*bp, bpPreset);
  for (const MethodParam& p : methodParams(kind)) {
    const auto it = given.find(p.name);
    if (it == given.end() || !it->second.given()) continue;
    std::string problem;
    if (p.kind == ParamKind::Flag)
      p.set(config, p.get(defaultConfig(kind)) != 0 ? 0.0 : 1.0);
    else
      problem = parseParam(p, config, joined(it->second.values));
    if (!problem.empty()) throw CommandError(problem);
  }
  return config;
}

MethodSpec MethodOptions::spec(const RunShape& shape) const {
  MethodSpec s{shape, config(kind(), preset)};
  if (const std::string problem = validate(s); !problem.empty()) throw CommandError(problem);
  return s;
}

void applyParamSetting(MethodSpec& spec, const std::string& setting, const std::string& where) {
  const size_t eq = setting.find('=');
  const std::string name = setting.substr(0, eq);
  for (const MethodParam& p : methodParams(spec.kind())) {
    if (p.name != name) continue;
    if (eq == std::string::npos)
      throw CommandError(where + ": '" + setting + "' needs a value (" + name + "=VALUE)");
    const std::string problem = parseParam(p, spec.config, setting.substr(eq + 1));
    if (!problem.empty()) throw CommandError(where + ": " + problem);
    return;
  }
  std::string names;
  for (const MethodParam& p : methodParams(spec.kind()))
    names += (names.empty() ? "" : ", ") + p.name;
  throw CommandError(where + ": " + toString(spec.kind()) + " has no parameter '" + name + "'" +
                     (names.empty() ? "" : " (it has: " + names + ")"));
}

}  // namespace penumbra
