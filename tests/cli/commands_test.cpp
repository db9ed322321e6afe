// The commands' flags for the run's shape come from its one table: each command lists those
// that make sense there (`view --help` shows the stopping rules its panel edits; compare keeps
// its own time rule; a reference takes its spp and seed).
#include "cli/commands.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <string>

namespace penumbra {
namespace {

std::string helpOf(const std::string& command) {
  CLI::App app;
  registerRenderCommand(app);
  registerViewCommand(app);
  registerReferenceCommand(app);
  registerCompareCommand(app);
  return app.get_subcommand(command)->help();
}

bool lists(const std::string& help, const std::string& flag) {
  return help.find("  " + flag + " ") != std::string::npos;
}

TEST(Commands, ViewHelpListsTheStoppingRulesAndTheSampler) {
  const std::string help = helpOf("view");
  for (const char* flag :
       {"--time-limit", "--noise-threshold", "--sampler", "--round-spp", "--spp", "--seed"})
    EXPECT_TRUE(lists(help, flag)) << flag << " missing from\n" << help;
}

TEST(Commands, RenderTakesTheWholeRunShape) {
  const std::string help = helpOf("render");
  for (const char* flag :
       {"--time-limit", "--noise-threshold", "--sampler", "--round-spp", "--spp", "--seed"})
    EXPECT_TRUE(lists(help, flag)) << flag;
  EXPECT_NE(help.find("the scene's render.spp"), std::string::npos);
}

TEST(Commands, CompareKeepsItsOwnTimeRuleAndSeeds) {
  const std::string help = helpOf("compare");
  for (const char* flag : {"--equal-time", "--seeds", "--first-seed", "--spp", "--sampler"})
    EXPECT_TRUE(lists(help, flag)) << flag;
  for (const char* flag : {"--time-limit", "--noise-threshold", "--seed"})
    EXPECT_FALSE(lists(help, flag)) << flag;
}

TEST(Commands, AReferenceTakesItsSppAndSeed) {
  const std::string help = helpOf("reference");
  EXPECT_TRUE(lists(help, "--spp"));
  EXPECT_TRUE(lists(help, "--seed"));
  EXPECT_NE(help.find("=8192"), std::string::npos) << help;  // its own default
  for (const char* flag : {"--time-limit", "--noise-threshold", "--sampler", "--round-spp"})
    EXPECT_FALSE(lists(help, flag)) << flag;
}

}  // namespace
}  // namespace penumbra
