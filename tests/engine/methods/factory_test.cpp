// The factory: the methods of method_list.inc by name and preset, their configurations, the
// one validation (the tables' ranges, then each method's own checks) and making a method.
#include "methods/factory.h"

#include "methods/bp/consistent.h"
#include "methods/bp/paper.h"
#include "methods/fdiv/fdiv.h"
#include "methods/gem/gem.h"
#include "methods/ld/ld.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <stdexcept>

namespace penumbra {
namespace {

TEST(Factory, ListsEveryMethodOnceByNameWithItsDescription) {
  const MethodRegistry& methods = builtinMethods();
  EXPECT_EQ(methods.names(),
            (std::vector<std::string>{"ld", "bp", "fdiv", "fuzzy", "gem", "cycles"}));
  EXPECT_EQ(methods.nameList(), "ld, bp, fdiv, fuzzy, gem, cycles");
  std::set<std::string> titles;
  for (const MethodDescriptor* m : methods.methods()) {
    EXPECT_TRUE(titles.insert(m->title()).second) << m->title();
    EXPECT_FALSE(m->description().empty()) << m->title();
    EXPECT_FALSE(m->maps().empty()) << m->title();
    EXPECT_EQ(m->defaults().empty(), false);
    EXPECT_EQ(&m->defaults().method(), m);
    EXPECT_EQ(validate({RunShape{}, m->defaults()}), "") << m->title();
  }
  EXPECT_NE(methods.find("fuzzy")->description().find("re-implemented"), std::string::npos);
  EXPECT_EQ(methods.find("nope"), nullptr);
}

TEST(Factory, APresetChoosesTheAlgorithmOfItsName) {
  const MethodRegistry& methods = builtinMethods();
  EXPECT_EQ(methods.find("bp"), &bpConsistentMethod());
  EXPECT_EQ(methods.find("bp", "paper"), &bpPaperMethod());
  EXPECT_EQ(methods.find("ld", "filtered"), &ldMethod());
  EXPECT_EQ(methods.find("ld", "tuned"), nullptr);
  EXPECT_TRUE(methods.configFor("ld", "filtered").as<LdConfig>().filter);
  EXPECT_FALSE(methods.configFor("ld").as<LdConfig>().filter);
  std::vector<std::string> bp;
  for (const auto& [method, preset] : methods.presetsOf("bp")) bp.push_back(preset->name);
  EXPECT_EQ(bp, (std::vector<std::string>{"consistent", "paper", "tuned"}));
  try {
    methods.configFor("fdiv", "tuned");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fdiv has no preset 'tuned'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(methods.configFor("magic"), std::invalid_argument);
}

TEST(Factory, KnowsWhoReadsAParameter) {
  const MethodRegistry& methods = builtinMethods();
  EXPECT_EQ(methods.readersOf("warping"), (std::vector<const MethodDescriptor*>{&bpPaperMethod()}));
  EXPECT_EQ(methods.readersOf("gamma"), (std::vector<const MethodDescriptor*>{&gemMethod()}));
  EXPECT_EQ(methods.readersOf("nl-k").size(), 2u);  // ld and bp's consistent algorithm
  EXPECT_TRUE(methods.readersOf("frobnicate").empty());
}

TEST(Factory, DescribesChangesByFlagName) {
  MethodConfig config = gemMethod().defaults();
  EXPECT_EQ(describeChanges(config, gemMethod().defaults()), "");
  config.as<GemConfig>().gamma = 0.3f;
  config.as<GemConfig>().rounds = 3;
  EXPECT_EQ(describeChanges(config, gemMethod().defaults()), "rounds=3 gamma=0.3");
}

// One validation: the run shape's table, the method's table, then the method's own checks, each
// message naming the flag; makeMethod and a method's own make function refuse the same.
TEST(Factory, RejectsBadSpecsNamingTheFlag) {
  auto prepared = test::shippedScene("cornell", 8);
  MethodSpec s{RunShape::batch(16), gemMethod().defaults()};
  s.config.as<GemConfig>().gamma = 0.9f;
  EXPECT_NE(validate(s).find("--gamma"), std::string::npos) << validate(s);
  EXPECT_THROW(makeMethod(*prepared, s), std::invalid_argument);
  s = {RunShape::batch(0), fdivMethod().defaults()};
  EXPECT_NE(validate(s).find("--spp"), std::string::npos) << validate(s);
  EXPECT_THROW(makeMethod(*prepared, s), std::invalid_argument);
  EXPECT_THROW(makeFDivMethod(*prepared, s.shape, s.config.as<FDivConfig>()),
               std::invalid_argument);
  s = {RunShape::batch(8), bpPaperMethod().defaults()};
  s.config.as<BpPaperConfig>().coarseSpp = 16;  // beyond the table: against the shape
  EXPECT_NE(validate(s).find("--coarse-spp cannot exceed --spp"), std::string::npos) << validate(s);
  s.config.as<BpPaperConfig>().coarseSpp = 0;
  s.config.as<BpPaperConfig>().filter.secondPassAlpha = 7;
  EXPECT_NE(validate(s).find("--second-pass-alpha"), std::string::npos) << validate(s);
  s = {RunShape::batch(8), ldMethod().defaults()};
  s.config.as<LdConfig>().denoise.radii = {2, 1};  // a setting with no flag: named by its field
  EXPECT_NE(validate(s).find("radii"), std::string::npos) << validate(s);
  EXPECT_THROW(makeLdMethod(*prepared, s.shape, s.config.as<LdConfig>()), std::invalid_argument);
}

TEST(Factory, MakesTheMethodItsConfigurationBelongsTo) {
  auto prepared = test::shippedScene("cornell", 8);
  for (const MethodDescriptor* m : builtinMethods().methods()) {
    auto method = makeMethod(*prepared, {RunShape::batch(4, 1), m->defaults()});
    while (!method->done()) method->runRound(nullptr);
    const auto snap = method->snapshot(false);
    EXPECT_EQ(snap->method, m->name()) << m->title();
    EXPECT_EQ(snap->keptSamples, 4u * 8 * 8) << m->title();
  }
}

// A viewer showing no overlay asks for no maps (ProgressiveMethod::setMapsWanted): every
// method's snapshot then has none, and its images and counts are the same bit for bit.
TEST(Factory, EveryMethodsSnapshotWithoutMapsHasTheSameImagesAndNoMaps) {
  auto prepared = test::shippedScene("cornell", 12);
  for (const MethodDescriptor* m : builtinMethods().methods()) {
    auto method = makeMethod(*prepared, {RunShape::batch(4, 1), m->defaults()});
    while (!method->done()) method->runRound(nullptr);
    EXPECT_TRUE(method->mapsWanted()) << m->title();
    const auto with = method->snapshot();
    method->setMapsWanted(false);
    const auto without = method->snapshot();
    EXPECT_TRUE(with->withMaps) << m->title();
    EXPECT_FALSE(with->maps.empty()) << m->title();
    EXPECT_FALSE(without->withMaps) << m->title();
    EXPECT_TRUE(without->maps.empty()) << m->title();
    ASSERT_EQ(with->raw.pixels.size(), without->raw.pixels.size()) << m->title();
    ASSERT_EQ(with->reconstructed.pixels.size(), without->reconstructed.pixels.size());
    EXPECT_EQ(0, std::memcmp(with->raw.pixels.data(), without->raw.pixels.data(),
                             with->raw.pixels.size() * sizeof(vec3)))
        << m->title();
    EXPECT_EQ(0,
              std::memcmp(with->reconstructed.pixels.data(), without->reconstructed.pixels.data(),
                          with->reconstructed.pixels.size() * sizeof(vec3)))
        << m->title();
    EXPECT_EQ(with->keptSamples, without->keptSamples) << m->title();
    EXPECT_EQ(with->tracedSamples, without->tracedSamples) << m->title();
    method->setMapsWanted(true);
    EXPECT_EQ(method->snapshot()->maps.size(), with->maps.size()) << m->title();
  }
}

}  // namespace
}  // namespace penumbra
