// Command-line options for the run's shape (methods/run_shape.h): the flags of
// runShapeParams() whose scope has the command, read back onto the shape the command starts
// from (its own defaults: the scene's spp, a reference's 8192, the viewer's open-ended rounds).
#pragma once

#include "cli/param_flags.h"
#include "methods/run_shape.h"

#include <CLI/CLI.hpp>

#include <map>
#include <string>

namespace penumbra {

struct RunOptions {
  std::map<std::string, GivenFlag> given;  // by parameter name

  bool has(const std::string& name) const {
    const auto it = given.find(name);
    return it != given.end() && it->second.given();
  }
  // Sets every flag given on `shape`; throws CommandError naming the flag on a bad value.
  void apply(RunShape& shape) const;
};

// Adds the flags of the run shape's table that apply to `command` (a RunCommand). `defaults`
// gives the values --help shows; `shown` overrides that text by name (e.g. spp: "the scene's
// render.spp").
void addRunOptions(CLI::App& app, RunOptions& options, RunCommand command, const RunShape& defaults,
                   const std::map<std::string, std::string>& shown = {});

}  // namespace penumbra
