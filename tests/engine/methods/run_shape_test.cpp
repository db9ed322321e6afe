// The run's shape: one table of its settings, each scoped to the commands it makes sense for,
// its checks naming the flag, and the stopping rule's convergence test.
#include "methods/run_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

namespace penumbra {
namespace {

std::set<std::string> flagsOf(unsigned command) {
  std::set<std::string> names;
  for (const Param<RunShape>& p : runShapeParams().params())
    if (p.scope & command) names.insert(p.name);
  return names;
}

TEST(RunShape, EachCommandTakesTheSettingsThatMakeSenseThere) {
  const std::set<std::string> all = {"seed",    "spp",        "round-spp",
                                     "sampler", "time-limit", "noise-threshold"};
  EXPECT_EQ(flagsOf(kRenderCommand), all);
  EXPECT_EQ(flagsOf(kViewCommand), all);
  // compare has its own seeds and its own time rule (--equal-time).
  EXPECT_EQ(flagsOf(kCompareCommand), (std::set<std::string>{"spp", "round-spp", "sampler"}));
  // A reference is a low-discrepancy batch to its end.
  EXPECT_EQ(flagsOf(kReferenceCommand), (std::set<std::string>{"seed", "spp"}));
}

TEST(RunShape, EveryEntryReadsAndWritesItsOwnField) {
  const auto& params = runShapeParams().params();
  for (size_t i = 0; i < params.size(); ++i) {
    RunShape shape;
    const RunShape defaults = shape;
    params[i].set(shape, params[i].get(shape) == params[i].max ? params[i].min : params[i].max);
    for (size_t k = 0; k < params.size(); ++k)
      EXPECT_EQ(formatParam(params[k], shape) != formatParam(params[k], defaults), k == i)
          << "setting " << params[i].name << " changed " << params[k].name;
  }
}

TEST(RunShape, ValidatesFromTheTableNamingTheFlag) {
  EXPECT_EQ(RunShape::batch(16).validate(), "");
  EXPECT_EQ(RunShape::progressive(1).validate(), "");  // spp 0: open
  EXPECT_NE(RunShape::batch(0).validate().find("--spp must be at least 1"), std::string::npos);
  RunShape s = RunShape::progressive(0);
  EXPECT_NE(s.validate().find("--round-spp 0"), std::string::npos) << s.validate();
  s = RunShape::batch(4);
  s.timeLimit = -1;
  EXPECT_NE(s.validate().find("--time-limit -1"), std::string::npos) << s.validate();
  s.timeLimit = INFINITY;
  EXPECT_NE(s.validate().find("--time-limit"), std::string::npos);
  s.timeLimit = 0;
  s.noiseThreshold = NAN;
  EXPECT_NE(s.validate().find("--noise-threshold"), std::string::npos);
}

TEST(RunShape, AnOpenEndedShapesSppIsWhereItStops) {
  const RunShape open = RunShape::progressive(2, 5);
  EXPECT_TRUE(open.openEnded);
  EXPECT_EQ(open.spp, 0);
  EXPECT_EQ(open.roundSpp, 2);
  EXPECT_EQ(open.seed, 5u);
  EXPECT_EQ(RunShape::progressive(2, 5, 64).spp, 64);
  EXPECT_FALSE(open.hasStoppingRule());
}

TEST(RunShape, APixelConvergesBelowTheNoiseThresholdOnly) {
  RunShape s;
  EXPECT_FALSE(s.converged(0.0f));  // no threshold: nothing converges
  s.noiseThreshold = 0.01f;
  EXPECT_TRUE(s.hasStoppingRule());
  EXPECT_TRUE(s.converged(0.005f));
  EXPECT_FALSE(s.converged(0.01f));
  EXPECT_FALSE(s.converged(NAN));
}

}  // namespace
}  // namespace penumbra
