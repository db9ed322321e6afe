// The `penumbra` command line: each subcommand registers its flags and callback on the
// CLI11 app. A callback reports failure by throwing CommandError (or SceneError); main
// prints "penumbra <command>: <message>" and exits with status 1.
#pragma once

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace penumbra {

struct CommandError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void registerRenderCommand(CLI::App& app);
void registerDiffCommand(CLI::App& app);
void registerViewCommand(CLI::App& app);
void registerReferenceCommand(CLI::App& app);
void registerCompareCommand(CLI::App& app);
void registerMergeCommand(CLI::App& app);

// The command line as typed (argv[0] shown as "penumbra"), for records such as reports.
std::string& commandLine();

}  // namespace penumbra
