// A method described once, in its own folder: its name, what it is, its configuration type and
// parameter table, its presets, the maps it publishes and what it can do, and how to make it.
// The factory (factory.h) lists the descriptors; the command line, the panel, compare's labels
// and `render --stats` ask a descriptor instead of knowing a method's configuration (in the
// manner of mitsuba's plugin registration and pbrt-v4's Create(name, parameters)).
//
// Adding a method: a folder engine/methods/<name>/ with its configuration, its parameter table
// (ParamTable<Config>, params.h), its ProgressiveMethod and a function returning its
// descriptor, built with MethodDescriptor's constructor from a MethodDefinition<Config>; then
// one line in methods/method_list.inc.
#pragma once

#include "methods/params.h"
#include "methods/progressive.h"
#include "methods/run_shape.h"
#include "methods/snapshot.h"
#include "trace/integrator.h"

#include <any>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

namespace penumbra {

class MethodDescriptor;

// A method's configuration by value: the method it belongs to and its own typed configuration,
// which only the method's own files know the type of.
class MethodConfig {
 public:
  MethodConfig() = default;  // none
  template <typename Config>
  MethodConfig(const MethodDescriptor& method, Config config)
      : method_(&method), value_(std::move(config)) {}

  bool empty() const { return method_ == nullptr; }
  // Throws std::logic_error on an empty configuration.
  const MethodDescriptor& method() const {
    if (!method_) throw std::logic_error("MethodConfig: no method");
    return *method_;
  }
  // The typed configuration, or nullptr when it is of another type.
  template <typename Config>
  Config* get() {
    return std::any_cast<Config>(&value_);
  }
  template <typename Config>
  const Config* get() const {
    return std::any_cast<Config>(&value_);
  }
  // The same for the method's own code, which knows the type: throws std::logic_error when not.
  template <typename Config>
  Config& as() {
    return *checked(get<Config>());
  }
  template <typename Config>
  const Config& as() const {
    return *checked(get<Config>());
  }

 private:
  template <typename T>
  static T* checked(T* config) {
    if (!config) throw std::logic_error("MethodConfig: not a " + std::string(typeid(T).name()));
    return config;
  }
  const MethodDescriptor* method_ = nullptr;
  std::any value_;
};

// The run's shape (the same for every method, ALGORITHM.md §11's fair comparison) and the
// chosen method's own configuration.
struct MethodSpec {
  RunShape shape;
  MethodConfig config;
  const MethodDescriptor& method() const { return config.method(); }
};

// A parameter over MethodConfig: the command line, the panel and the stats handle every
// method's parameters alike through these.
using MethodParam = Param<MethodConfig>;

// What a method can do with a configuration, for the front ends' choices.
struct MethodAbilities {
  bool keepsVariance = false;   // each pixel's variance of the mean: --variance-out
  bool filters = false;         // shows a reconstruction, not its raw estimate
  bool adapts = false;          // places samples by an estimate (so its raw estimate differs)
  bool estimatesError = false;  // estimates its image's error: honours --noise-threshold
};

// A named configuration: the method's defaults, then `apply`; a preset without `apply` names the
// defaults themselves (bp's "consistent" and "paper").
template <typename Config>
struct TypedPreset {
  std::string name;  // --preset NAME, compare's NAME:PRESET
  std::string help;  // one line
  std::function<void(Config&)> apply;
};

// `make` for a method whose constructor takes (prepared, shape, config).
template <typename Method, typename Config>
std::unique_ptr<ProgressiveMethod> construct(const PreparedScene& prepared, const RunShape& shape,
                                             const Config& config) {
  return std::make_unique<Method>(prepared, shape, config);
}

// What a method's folder writes to describe it; MethodDescriptor erases the type.
template <typename Config>
struct MethodDefinition {
  std::string name;  // what users type: --method NAME, compare's entries
  // For a name with several algorithms (bp: "consistent", "paper"), which one this is; else empty.
  // --preset chooses among the algorithms of a name.
  std::string algorithm;
  std::string description;  // one line for people: "Low discrepancy (box filter)"
  const ParamTable<Config>* params = nullptr;
  Config defaults{};
  // --method NAME alone gives the defaults of the name's first descriptor (factory.h's list).
  std::vector<TypedPreset<Config>> presets;
  std::vector<const MapKind*> maps;  // every map its snapshots may hold
  std::function<MethodAbilities(const Config&)> abilities;
  // What the table's ranges cannot say (one parameter against another, or against the run's
  // shape): empty when valid, else a message naming the flags.
  std::function<std::string(const Config&, const RunShape&)> check;
  std::function<std::unique_ptr<ProgressiveMethod>(const PreparedScene&, const RunShape&,
                                                   const Config&)>
      make;
  // The configuration whose image is the raw estimate (compare's NAME:raw), where skipping the
  // reconstruction saves its time; unset: the method's image is read raw as it is.
  std::function<void(Config&)> withoutReconstruction;
};

class MethodDescriptor {
 public:
  struct Preset {
    std::string name, help;
    bool isDefaults = false;  // names the descriptor's defaults
    std::function<void(MethodConfig&)> apply;
  };

  template <typename Config>
  explicit MethodDescriptor(MethodDefinition<Config> d)
      : name_(std::move(d.name)),
        algorithm_(std::move(d.algorithm)),
        description_(std::move(d.description)),
        maps_(std::move(d.maps)) {
    if (d.params)
      for (const Param<Config>& p : d.params->params())
        params_.push_back(rebindParam<MethodConfig>(
            p, [](auto& c) -> auto& { return c.template as<Config>(); }));
    defaults_ = [this, defaults = std::move(d.defaults)] { return MethodConfig(*this, defaults); };
    for (TypedPreset<Config>& p : d.presets)
      presets_.push_back({std::move(p.name), std::move(p.help), !p.apply,
                          [apply = std::move(p.apply)](MethodConfig& c) {
                            if (apply) apply(c.template as<Config>());
                          }});
    abilities_ = [f = std::move(d.abilities)](const MethodConfig& c) {
      return f ? f(c.as<Config>()) : MethodAbilities{};
    };
    check_ = [f = std::move(d.check)](const MethodConfig& c, const RunShape& shape) {
      return f ? f(c.as<Config>(), shape) : std::string();
    };
    make_ = [f = std::move(d.make)](const PreparedScene& prepared, const MethodSpec& spec) {
      return f(prepared, spec.shape, spec.config.as<Config>());
    };
    if (d.withoutReconstruction)
      withoutReconstruction_ = [f = std::move(d.withoutReconstruction)](MethodConfig& c) {
        f(c.as<Config>());
      };
  }
  MethodDescriptor(const MethodDescriptor&) = delete;  // configurations point at it
  MethodDescriptor& operator=(const MethodDescriptor&) = delete;

  const std::string& name() const { return name_; }
  const std::string& algorithm() const { return algorithm_; }
  const std::string& description() const { return description_; }
  // "bp's consistent algorithm", or "ld": how messages name it.
  std::string title() const {
    return algorithm_.empty() ? name_ : name_ + "'s " + algorithm_ + " algorithm";
  }
  const std::vector<MethodParam>& params() const { return params_; }
  const MethodParam* param(std::string_view name) const {
    for (const MethodParam& p : params_)
      if (p.name == name) return &p;
    return nullptr;
  }
  const std::vector<Preset>& presets() const { return presets_; }
  const Preset* preset(std::string_view name) const {
    for (const Preset& p : presets_)
      if (p.name == name) return &p;
    return nullptr;
  }
  // The preset that names the defaults, or nullptr.
  const Preset* defaultPreset() const {
    for (const Preset& p : presets_)
      if (p.isDefaults) return &p;
    return nullptr;
  }
  const std::vector<const MapKind*>& maps() const { return maps_; }

  MethodConfig defaults() const { return defaults_(); }
  MethodAbilities abilities(const MethodConfig& config) const { return abilities_(config); }
  // The cross-parameter checks (the ranges are the table's: validate() in factory.h runs both).
  std::string check(const MethodConfig& config, const RunShape& shape) const {
    return check_(config, shape);
  }
  std::unique_ptr<ProgressiveMethod> make(const PreparedScene& prepared,
                                          const MethodSpec& spec) const {
    return make_(prepared, spec);
  }
  // Sets `config` to show the raw estimate without computing a reconstruction; false when the
  // method has no such setting.
  bool skipReconstruction(MethodConfig& config) const {
    if (!withoutReconstruction_) return false;
    withoutReconstruction_(config);
    return true;
  }

 private:
  std::string name_, algorithm_, description_;
  std::vector<MethodParam> params_;
  std::vector<Preset> presets_;
  std::vector<const MapKind*> maps_;
  std::function<MethodConfig()> defaults_;
  std::function<MethodAbilities(const MethodConfig&)> abilities_;
  std::function<std::string(const MethodConfig&, const RunShape&)> check_;
  std::function<std::unique_ptr<ProgressiveMethod>(const PreparedScene&, const MethodSpec&)> make_;
  std::function<void(MethodConfig&)> withoutReconstruction_;
};

}  // namespace penumbra
