// Command-line options that choose and configure the rendering method: --method, --preset and
// one flag for every parameter of every method's table (methods/params.h), shared by `render`,
// `view` and `compare`. Everything is asked of the methods' descriptors (methods/method.h): a
// new method's flags appear with no edit here.
#pragma once

#include "cli/param_flags.h"
#include "methods/factory.h"

#include <CLI/CLI.hpp>

#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// The flags given refer to the command's options: a MethodOptions is read while its CLI::App
// lives.
struct MethodOptions {
  const MethodRegistry* registry = &builtinMethods();
  std::string method = "ld";
  std::string preset;                      // empty: the method's defaults
  std::map<std::string, GivenFlag> given;  // by parameter name

  // The descriptor --method and --preset choose; throws CommandError when the method has no
  // such preset.
  const MethodDescriptor& descriptor() const;
  // `method`'s configuration: its defaults, then `preset` when it has it, then every flag given
  // that it reads. Throws CommandError naming the flag on a bad value.
  MethodConfig config(const MethodDescriptor& method, std::string_view preset) const;
  // The chosen method with this run shape. Throws CommandError naming the flag when the spec is
  // invalid, or when a flag given is one the chosen method does not read.
  MethodSpec spec(const RunShape& shape) const;
  // Throws CommandError when a parameter flag was given that none of `methods` reads, naming
  // the flag and the methods that read it.
  void requireRead(const std::vector<const MethodDescriptor*>& methods) const;
};

// `skip`: parameter names the command uses for something else (view's --rounds).
void addMethodOptions(CLI::App& command, MethodOptions& options,
                      const std::set<std::string>& skip = {});

// Throws CommandError when a noise threshold would be a run's only stopping rule (no time
// limit) and the method has no error estimate to stop on: the run would never end.
void requireNoiseThresholdHonoured(const MethodDescriptor& method, const MethodConfig& config,
                                   bool noiseThreshold, bool timeLimit);

// "--preset consistent" or "--method ld": what a user types to get `method`.
std::string howToChoose(const MethodDescriptor& method);

// Sets "name=value" on the configuration; throws CommandError when the method has no such
// parameter or the value is bad. `where` names the place for the message.
void applyParamSetting(MethodConfig& config, const std::string& setting, const std::string& where);

}  // namespace penumbra
