// --method, --preset and the methods' parameter flags: a flag sets every method that reads it,
// a preset chooses the algorithm of a name, and a flag the chosen method does not read is an
// error naming the method and those that read it.
#include "cli/method_options.h"

#include "methods/bp/consistent.h"
#include "methods/bp/paper.h"
#include "methods/ld/ld.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <vector>

namespace penumbra {
namespace {

// The options refer to the command's flags: they live together.
struct Parsed {
  CLI::App app;
  MethodOptions options;
};

std::unique_ptr<Parsed> parse(const std::string& line) {
  auto p = std::make_unique<Parsed>();
  addMethodOptions(p->app, p->options);
  p->app.parse(line);
  return p;
}

const MethodOptions& parsed(const std::string& line) {
  static std::vector<std::unique_ptr<Parsed>> kept;
  kept.push_back(parse(line));
  return kept.back()->options;
}

std::string errorOf(const MethodOptions& options) {
  try {
    options.spec(RunShape::batch(8));
  } catch (const CommandError& e) {
    return e.what();
  }
  return "";
}

TEST(MethodOptions, APresetChoosesTheAlgorithm) {
  EXPECT_EQ(&parsed("--method bp").descriptor(), &bpConsistentMethod());
  EXPECT_EQ(&parsed("--method bp --preset consistent").descriptor(), &bpConsistentMethod());
  EXPECT_EQ(&parsed("--method bp --preset paper").descriptor(), &bpPaperMethod());
  const MethodSpec tuned = parsed("--method bp --preset tuned --nit 7").spec(RunShape::batch(8));
  EXPECT_EQ(&tuned.method(), &bpPaperMethod());
  EXPECT_FALSE(tuned.config.as<BpPaperConfig>().warping);         // the preset
  EXPECT_EQ(tuned.config.as<BpPaperConfig>().network.epochs, 7);  // the flag over it
  EXPECT_TRUE(parsed("--preset filtered").spec(RunShape::batch(8)).config.as<LdConfig>().filter);
  EXPECT_NE(errorOf(parsed("--method fdiv --preset tuned")).find("fdiv has no such preset"),
            std::string::npos);
}

TEST(MethodOptions, AFlagTheChosenAlgorithmDoesNotReadIsAnErrorNamingIt) {
  EXPECT_EQ(errorOf(parsed("--method bp --no-warping")),
            "--no-warping: bp's consistent algorithm does not read it; it is read by bp's paper "
            "algorithm (--preset paper or tuned)");
  EXPECT_EQ(errorOf(parsed("--method bp --preset paper --network-weight 1")),
            "--network-weight: bp's paper algorithm does not read it; it is read by bp's "
            "consistent algorithm (--preset consistent)");
  EXPECT_NE(errorOf(parsed("--gamma 0.3"))
                .find("--gamma: ld does not read it; it is read by gem "
                      "(--method gem)"),
            std::string::npos);
  EXPECT_EQ(errorOf(parsed("--method bp --preset paper --no-warping --nit 3")), "");
  EXPECT_EQ(errorOf(parsed("--method bp --nl-k 0.5 --nit 3")), "");
}

TEST(MethodOptions, AFlagSetsEveryMethodThatReadsIt) {
  const MethodOptions& options = parsed("--nl-k 0.5 --nit 9");
  EXPECT_FLOAT_EQ(options.config(ldMethod(), "").as<LdConfig>().denoise.k, 0.5f);
  const MethodConfig consistent = options.config(bpConsistentMethod(), "");
  EXPECT_FLOAT_EQ(consistent.as<BpConsistentConfig>().denoise.k, 0.5f);
  EXPECT_EQ(consistent.as<BpConsistentConfig>().network.epochs, 9);
  EXPECT_EQ(options.config(bpPaperMethod(), "paper").as<BpPaperConfig>().network.epochs, 9);
}

TEST(MethodOptions, ASettingNamesTheMethodsParameters) {
  MethodConfig config = bpPaperMethod().defaults();
  applyParamSetting(config, "psi=0.2", "--methods: bp:paper");
  EXPECT_FLOAT_EQ(config.as<BpPaperConfig>().psi, 0.2f);
  try {
    applyParamSetting(config, "nl-k=0.2", "--methods: bp:paper");
    FAIL() << "no exception";
  } catch (const CommandError& e) {
    EXPECT_NE(std::string(e.what()).find("bp's paper algorithm has no parameter 'nl-k'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(applyParamSetting(config, "psi", "x"), CommandError);
  EXPECT_THROW(applyParamSetting(config, "psi=-1", "x"), CommandError);
}

}  // namespace
}  // namespace penumbra
