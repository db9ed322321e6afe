// Every rendering method by name, and the one factory `render`, `view`, `compare` and
// `reference` build methods with. The methods are the descriptors of methods/method_list.inc,
// one line each; a MethodRegistry is such a list (the tests make their own, with a toy method
// added), and everything here folds over it.
#pragma once

#include "methods/method.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

class MethodRegistry {
 public:
  explicit MethodRegistry(std::vector<const MethodDescriptor*> methods);

  const std::vector<const MethodDescriptor*>& methods() const { return methods_; }
  // Each name once, in the list's order: "ld", "bp", "fdiv", ...
  const std::vector<std::string>& names() const { return names_; }
  // "ld, bp, fdiv, ...", for messages and help.
  std::string nameList() const;
  // The descriptor of `name` that has `preset` (empty: the name's first descriptor); nullptr
  // when there is none.
  const MethodDescriptor* find(std::string_view name, std::string_view preset = {}) const;
  // Every preset of `name`, over its algorithms, in order.
  std::vector<std::pair<const MethodDescriptor*, const MethodDescriptor::Preset*>> presetsOf(
      std::string_view name) const;
  // The configuration `name` with `preset` gives (empty: the defaults of its first descriptor).
  // Throws std::invalid_argument naming what is unknown.
  MethodConfig configFor(std::string_view name, std::string_view preset = {}) const;
  // Every map a method may publish, and the shared ones, each once: the overlays (by key)
  // first, then the maps only --aov-dir writes.
  const std::vector<const MapKind*>& maps() const { return maps_; }
  // A map by its name or alias; "none" gives the empty id.
  std::optional<MapId> mapByName(std::string_view name) const;
  // The descriptors that read parameter `name`.
  std::vector<const MethodDescriptor*> readersOf(std::string_view name) const;

 private:
  std::vector<const MethodDescriptor*> methods_;
  std::vector<std::string> names_;
  std::vector<const MapKind*> maps_;
};

// The methods of methods/method_list.inc.
const MethodRegistry& builtinMethods();

// "nit=20 sigma-c=0.1": the parameters of `config` that differ from `base` (of the same method).
std::string describeChanges(const MethodConfig& config, const MethodConfig& base);

// Empty when the spec is valid, else a message naming the flag: the run shape's and the method's
// parameters against their tables' ranges, then the method's own cross-parameter checks.
std::string validate(const MethodSpec& spec);
// Throws std::invalid_argument with validate()'s message: what a method's own make function
// calls when a test makes the method directly.
void requireValid(const MethodSpec& spec);
// A method's own make function (a test makes a method directly): validates the configuration
// against `descriptor`, then makes `Method`.
template <typename Method, typename Config>
std::unique_ptr<ProgressiveMethod> makeValidated(const MethodDescriptor& descriptor,
                                                 const PreparedScene& prepared,
                                                 const RunShape& shape, const Config& config) {
  requireValid({shape, MethodConfig(descriptor, config)});
  return std::make_unique<Method>(prepared, shape, config);
}
// Validates, then makes the method; the scene must outlive it.
std::unique_ptr<ProgressiveMethod> makeMethod(const PreparedScene& prepared,
                                              const MethodSpec& spec);

}  // namespace penumbra
