// Entry point of the `penumbra` executable: dispatches to the subcommands.
#include "cli/allocation.h"
#include "cli/commands.h"
#include "cli/plan.h"
#include "scene/scene.h"

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  penumbra::configureAllocation();  // first: glibc's mmap and trim thresholds
  CLI::App app{"Penumbra: progressive Monte Carlo preview renderer with adaptive sampling"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  penumbra::registerRenderCommand(app);
  penumbra::registerDiffCommand(app);
  penumbra::registerViewCommand(app);
  penumbra::registerReferenceCommand(app);
  penumbra::registerCompareCommand(app);
  penumbra::registerMergeCommand(app);
  for (int i = 0; i < argc; ++i)
    penumbra::commandLine() += (i ? " " : "") + std::string(i ? argv[i] : "penumbra");
  for (int i = 1; i < argc; ++i) penumbra::commandArguments().push_back(argv[i]);
  // One line per error, naming the command: "penumbra render: error: --spp: ...".
  auto fail = [&](const char* message, int status) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "penumbra%s%s: error: %s\n", subs.empty() ? "" : " ",
                 subs.empty() ? "" : subs.front()->get_name().c_str(), message);
    return status;
  };
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->check_name(argv[1]);
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      const std::string message =
          "unknown command '" + std::string(argv[1]) + "' (expected one of: " + names + ")";
      return fail(message.c_str(), 2);
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(e.what(), 2);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
  return 0;
}
