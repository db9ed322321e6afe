// Entry point of the `penumbra` executable: dispatches to the subcommands.
#include "engine/scene.h"
#include "viewer/commands.h"

#include <cstdio>

int main(int argc, char** argv) {
  CLI::App app{"Penumbra: progressive Monte Carlo preview renderer with adaptive sampling"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  penumbra::registerRenderCommand(app);
  penumbra::registerDiffCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "penumbra%s%s: error: %s\n", subs.empty() ? "" : " ",
                 subs.empty() ? "" : subs.front()->get_name().c_str(), e.what());
    return 1;
  }
  return 0;
}
