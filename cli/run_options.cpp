#include "cli/run_options.h"

namespace penumbra {

void RunOptions::apply(RunShape& shape) const {
  const RunShape defaults = shape;
  for (const Param<RunShape>& p : runShapeParams().params()) {
    const auto it = given.find(p.name);
    if (it != given.end()) applyGivenFlag(p, it->second, shape, defaults);
  }
}

void addRunOptions(CLI::App& app, RunOptions& options, RunCommand command, const RunShape& defaults,
                   const std::map<std::string, std::string>& shown) {
  for (const Param<RunShape>& p : runShapeParams().params()) {
    if (!(p.scope & command)) continue;
    const auto text = shown.find(p.name);
    addParamFlag(app, p, options.given[p.name],
                 text != shown.end() ? text->second : formatParam(p, defaults));
  }
}

}  // namespace penumbra
