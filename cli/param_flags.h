// A parameter table's entries as command-line flags (methods/params.h): one flag per entry, its
// range, choices and default in --help, and the values given read back onto a configuration.
// The method options (method_options.h) and the run's shape (run_options.h) both use it.
#pragma once

#include "cli/commands.h"
#include "methods/params.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace penumbra {

// A flag as given on the command line (its option is the command's: valid while the CLI::App
// lives).
struct GivenFlag {
  std::vector<std::string> values;  // a list's elements, or the one value
  bool flag = false;                // a toggle's flag was given
  const CLI::Option* option = nullptr;
  bool given() const { return flag || (option && option->count() > 0); }
};

inline std::string joinedValues(const std::vector<std::string>& values) {
  std::string s;
  for (const std::string& v : values) s += (s.empty() ? "" : ",") + v;
  return s;
}

// Adds the flag of `p` to `command`, in its group, with `defaultText` shown in --help.
template <typename Config>
void addParamFlag(CLI::App& command, const Param<Config>& p, GivenFlag& given,
                  const std::string& defaultText) {
  if (p.kind == ParamKind::Flag) {
    given.option = command.add_flag(p.flag, given.flag, p.help)->group(p.group);
    return;
  }
  CLI::Option* option = command.add_option("--" + p.name, given.values, p.help)
                            ->default_str(defaultText)
                            ->group(p.group);
  if (p.kind == ParamKind::FloatList)
    option->delimiter(',')->expected(0, 16)->type_name("FLOAT")->check(CLI::Range(p.min, p.max));
  else if (p.kind == ParamKind::Choice)
    option->expected(1)->type_name("TEXT")->check(CLI::IsMember(p.choices));
  else if (p.kind == ParamKind::Int)
    option->expected(1)->type_name("INT")->check(
        CLI::Range(static_cast<long long>(p.min), static_cast<long long>(p.max)));
  else
    option->expected(1)->type_name("FLOAT")->check(CLI::Range(p.min, p.max));
  given.option = option;
}

// Sets `p` on `config` from what was given (a toggle flips `p`'s value in `defaults`). Throws
// CommandError naming the flag on a bad value.
template <typename Config>
void applyGivenFlag(const Param<Config>& p, const GivenFlag& given, Config& config,
                    const Config& defaults) {
  if (!given.given()) return;
  if (p.kind == ParamKind::Flag) {
    p.set(config, p.get(defaults) != 0 ? 0.0 : 1.0);
    return;
  }
  if (const std::string problem = parseParam(p, config, joinedValues(given.values));
      !problem.empty())
    throw CommandError(problem);
}

}  // namespace penumbra
