// Command-line options that choose and configure the rendering method: --method, --preset
// and one flag for every parameter of every method's table (methods/params.h), shared by
// `render`, `view` and `compare`. A flag sets the parameter of each method that has it.
#pragma once

#include "methods/factory.h"

#include <CLI/CLI.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace penumbra {

struct MethodOptions {
  MethodKind method = MethodKind::Ld;
  BpPreset preset = BpPreset::Consistent;

  // A parameter flag as given on the command line.
  struct Given {
    std::vector<std::string> values;  // a list's elements, or the one value
    bool flag = false;                // a toggle's flag was given
    const CLI::Option* option = nullptr;
    bool given() const { return flag || (option && option->count() > 0); }
  };
  std::map<std::string, Given> given;  // by parameter name

  MethodKind kind() const { return method; }
  // The configuration of `kind`: its defaults, then (bp) the preset, then every flag given.
  // Throws CommandError naming the flag on a bad value.
  MethodConfig config(MethodKind kind, BpPreset bpPreset) const;
  // The chosen method with this run shape; throws CommandError naming the flag when invalid.
  MethodSpec spec(const RunShape& shape) const;
};

// `skip`: parameter names the command uses for something else (view's --rounds).
void addMethodOptions(CLI::App& command, MethodOptions& options,
                      const std::set<std::string>& skip = {});

// Sets "name=value" on the spec's configuration; throws CommandError when the method has no
// such parameter or the value is bad. `where` names the place for the message.
void applyParamSetting(MethodSpec& spec, const std::string& setting, const std::string& where);

}  // namespace penumbra
