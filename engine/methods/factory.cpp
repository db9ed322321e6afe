#include "methods/factory.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra {

#define PENUMBRA_METHOD(function) const MethodDescriptor& function();
#include "methods/method_list.inc"
#undef PENUMBRA_METHOD

const MethodRegistry& builtinMethods() {
#define PENUMBRA_METHOD(function) &function(),
  static const MethodRegistry registry({
#include "methods/method_list.inc"
  });
#undef PENUMBRA_METHOD
  return registry;
}

MethodRegistry::MethodRegistry(std::vector<const MethodDescriptor*> methods)
    : methods_(std::move(methods)) {
  for (const MethodDescriptor* m : methods_) {
    if (std::find(names_.begin(), names_.end(), m->name()) == names_.end())
      names_.push_back(m->name());
    for (const MapKind* kind : m->maps())
      if (std::find(maps_.begin(), maps_.end(), kind) == maps_.end()) maps_.push_back(kind);
  }
  for (const MapKind* kind : maps::kShared)
    if (std::find(maps_.begin(), maps_.end(), kind) == maps_.end()) maps_.push_back(kind);
  // The overlays by key, then the files-only maps in the methods' order.
  std::stable_sort(maps_.begin(), maps_.end(), [](const MapKind* a, const MapKind* b) {
    const int ka = a->key > 0 ? a->key : 1 << 30, kb = b->key > 0 ? b->key : 1 << 30;
    return ka < kb;
  });
}

std::string MethodRegistry::nameList() const {
  std::string text;
  for (const std::string& n : names_) text += (text.empty() ? "" : ", ") + n;
  return text;
}

const MethodDescriptor* MethodRegistry::find(std::string_view name, std::string_view preset) const {
  for (const MethodDescriptor* m : methods_)
    if (m->name() == name && (preset.empty() || m->preset(preset))) return m;
  return nullptr;
}

std::vector<std::pair<const MethodDescriptor*, const MethodDescriptor::Preset*>>
MethodRegistry::presetsOf(std::string_view name) const {
  std::vector<std::pair<const MethodDescriptor*, const MethodDescriptor::Preset*>> out;
  for (const MethodDescriptor* m : methods_)
    if (m->name() == name)
      for (const MethodDescriptor::Preset& p : m->presets()) out.emplace_back(m, &p);
  return out;
}

MethodConfig MethodRegistry::configFor(std::string_view name, std::string_view preset) const {
  const MethodDescriptor* method = find(name);
  if (!method)
    throw std::invalid_argument("unknown method '" + std::string(name) +
                                "' (expected one of: " + nameList() + ")");
  if (preset.empty()) return method->defaults();
  method = find(name, preset);
  if (!method) {
    std::string names;
    for (const auto& [m, p] : presetsOf(name)) names += (names.empty() ? "" : ", ") + p->name;
    throw std::invalid_argument(std::string(name) + " has no preset '" + std::string(preset) + "'" +
                                (names.empty() ? " (it has none)" : " (it has: " + names + ")"));
  }
  MethodConfig config = method->defaults();
  method->preset(preset)->apply(config);
  return config;
}

std::optional<MapId> MethodRegistry::mapByName(std::string_view name) const {
  if (name == "none") return MapId();
  for (const MapKind* kind : maps_)
    if (name == kind->name || (kind->alias && name == kind->alias)) return MapId(*kind);
  return std::nullopt;
}

std::vector<const MethodDescriptor*> MethodRegistry::readersOf(std::string_view name) const {
  std::vector<const MethodDescriptor*> out;
  for (const MethodDescriptor* m : methods_)
    if (m->param(name)) out.push_back(m);
  return out;
}

std::string describeChanges(const MethodConfig& config, const MethodConfig& base) {
  std::string text;
  for (const MethodParam& p : config.method().params()) {
    const std::string value = formatParam(p, config);
    if (value != formatParam(p, base)) text += (text.empty() ? "" : " ") + p.name + "=" + value;
  }
  return text;
}

std::string validate(const MethodSpec& s) {
  if (std::string problem = s.shape.validate(); !problem.empty()) return problem;
  const MethodDescriptor& method = s.method();
  if (std::string problem = checkParams(method.params(), s.config); !problem.empty())
    return problem;
  return method.check(s.config, s.shape);
}

void requireValid(const MethodSpec& spec) {
  if (const std::string error = validate(spec); !error.empty()) throw std::invalid_argument(error);
}

std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared, const MethodSpec& s) {
  requireValid(s);
  return s.method().make(prepared, s);
}

}  // namespace penumbra
