#include "cli/method_options.h"

namespace penumbra {

namespace {

// "ld (Low discrepancy (box filter)), bp (...), ...": --method's choices, from the descriptors.
std::string methodHelp(const MethodRegistry& registry) {
  std::string text = "Rendering method: ";
  for (const std::string& name : registry.names())
    text += (name == registry.names().front() ? "" : ", ") + name + " (" +
            registry.find(name)->description() + ")";
  return text;
}

// Every preset of every method: "bp: consistent (the default: ...), paper (...); ld: ...".
std::string presetHelp(const MethodRegistry& registry) {
  std::string text =
      "A named configuration of the method (explicit flags still apply); without one, the "
      "method's defaults. ";
  bool firstName = true;
  for (const std::string& name : registry.names()) {
    const auto presets = registry.presetsOf(name);
    if (presets.empty()) continue;
    text += std::string(firstName ? "" : "; ") + name + ": ";
    firstName = false;
    for (size_t i = 0; i < presets.size(); ++i)
      text += (i ? ", " : "") + presets[i].second->name +
              (presets[i].second->isDefaults && presets[i].first == registry.find(name)
                   ? " (the default)"
                   : "") +
              " (" + presets[i].second->help + ")";
  }
  return text;
}

std::vector<std::string> presetNames(const MethodRegistry& registry) {
  std::vector<std::string> names;
  for (const MethodDescriptor* m : registry.methods())
    for (const MethodDescriptor::Preset& p : m->presets())
      if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
  return names;
}

}  // namespace

std::string howToChoose(const MethodDescriptor& method) {
  if (method.algorithm().empty() || method.presets().empty()) return "--method " + method.name();
  std::string text = "--preset ";
  for (size_t i = 0; i < method.presets().size(); ++i)
    text += (i ? " or " : "") + method.presets()[i].name;
  return text;
}

void requireNoiseThresholdHonoured(const MethodDescriptor& method, const MethodConfig& config,
                                   bool noiseThreshold, bool timeLimit) {
  if (noiseThreshold && !timeLimit && !method.abilities(config).estimatesError)
    throw CommandError("--noise-threshold: " + method.title() + " (" + howToChoose(method) +
                       ") has no error estimate to stop on; choose a method that estimates its "
                       "error, or give --time-limit or --spp instead");
}

void addMethodOptions(CLI::App& c, MethodOptions& o, const std::set<std::string>& skip) {
  const MethodRegistry& registry = *o.registry;
  c.add_option("--method", o.method, methodHelp(registry))
      ->check(CLI::IsMember(registry.names()))
      ->default_str(o.method);
  c.add_option("--preset", o.preset, presetHelp(registry))
      ->check(CLI::IsMember(presetNames(registry)))
      ->default_str(o.preset);
  // One flag per parameter name; the first method that has it describes it.
  for (const MethodDescriptor* method : registry.methods()) {
    const MethodConfig defaults = method->defaults();
    for (const MethodParam& p : method->params()) {
      if (skip.count(p.name) || o.given.count(p.name)) continue;
      addParamFlag(c, p, o.given[p.name], formatParam(p, defaults));
    }
  }
}

const MethodDescriptor& MethodOptions::descriptor() const {
  if (!registry->find(method))
    throw CommandError("--method " + method + ": expected one of " + registry->nameList());
  const MethodDescriptor* chosen = registry->find(method, preset);
  if (!chosen) {
    std::string names;
    for (const auto& [m, p] : registry->presetsOf(method))
      names += (names.empty() ? "" : ", ") + p->name;
    throw CommandError("--preset " + preset + ": " + method + " has no such preset" +
                       (names.empty() ? " (it has none)" : " (it has: " + names + ")"));
  }
  return *chosen;
}

MethodConfig MethodOptions::config(const MethodDescriptor& method, std::string_view name) const {
  MethodConfig config = method.defaults();
  const MethodConfig defaults = config;
  if (const MethodDescriptor::Preset* p = name.empty() ? nullptr : method.preset(name))
    p->apply(config);
  for (const MethodParam& p : method.params()) {
    const auto it = given.find(p.name);
    if (it != given.end()) applyGivenFlag(p, it->second, config, defaults);
  }
  return config;
}

void MethodOptions::requireRead(const std::vector<const MethodDescriptor*>& methods) const {
  for (const auto& [name, flag] : given) {
    if (!flag.given()) continue;
    bool read = false;
    for (const MethodDescriptor* m : methods) read = read || m->param(name);
    if (read) continue;
    const std::vector<const MethodDescriptor*> readers = registry->readersOf(name);
    std::string by;
    for (const MethodDescriptor* reader : readers)
      by += (by.empty() ? "" : "; ") + reader->title() + " (" + howToChoose(*reader) + ")";
    const MethodParam* p = readers.front()->param(name);  // a flag is some method's
    std::string what = methods.size() == 1 ? methods.front()->title() + " does not read it"
                                           : "none of the methods compared reads it";
    throw CommandError(flagOf(*p) + ": " + what + (by.empty() ? "" : "; it is read by " + by));
  }
}

MethodSpec MethodOptions::spec(const RunShape& shape) const {
  const MethodDescriptor& chosen = descriptor();
  requireRead({&chosen});
  MethodSpec s{shape, config(chosen, preset)};
  if (const std::string problem = validate(s); !problem.empty()) throw CommandError(problem);
  return s;
}

void applyParamSetting(MethodConfig& config, const std::string& setting, const std::string& where) {
  const size_t eq = setting.find('=');
  const std::string name = setting.substr(0, eq);
  const MethodDescriptor& method = config.method();
  if (const MethodParam* p = method.param(name)) {
    if (eq == std::string::npos)
      throw CommandError(where + ": '" + setting + "' needs a value (" + name + "=VALUE)");
    const std::string problem = parseParam(*p, config, setting.substr(eq + 1));
    if (!problem.empty()) throw CommandError(where + ": " + problem);
    return;
  }
  std::string names;
  for (const MethodParam& p : method.params()) names += (names.empty() ? "" : ", ") + p.name;
  throw CommandError(where + ": " + method.title() + " has no parameter '" + name + "'" +
                     (names.empty() ? "" : " (it has: " + names + ")"));
}

}  // namespace penumbra
