// The methods' parameter tables: every entry reads and writes its own field, names are
// unique, values parse and print back, bad values are refused naming the flag.
#include "methods/factory.h"

#include <gtest/gtest.h>

#include <set>

namespace penumbra {
namespace {

TEST(Params, EveryEntryReadsAndWritesItsOwnField) {
  for (const std::string& name : methodNames()) {
    const MethodKind kind = *parseMethodKind(name);
    const std::vector<MethodParam>& params = methodParams(kind);
    std::set<std::string> names;
    for (const MethodParam& p : params) {
      EXPECT_TRUE(names.insert(p.name).second) << name << ": " << p.name << " twice";
      EXPECT_FALSE(p.help.empty()) << p.name;
      EXPECT_FALSE(p.label.empty()) << p.name;
      EXPECT_FALSE(p.group.empty()) << p.name;
      if (p.kind == ParamKind::Flag) {
        EXPECT_EQ(p.flag.rfind("--", 0), 0u) << p.name;
      }
    }
    // Changing one entry changes that entry alone: no two entries share a field.
    for (size_t i = 0; i < params.size(); ++i) {
      const MethodParam& p = params[i];
      MethodConfig config = defaultConfig(kind);
      const MethodConfig defaults = config;
      if (p.kind == ParamKind::FloatList) {
        std::vector<float> v = p.getList(config);
        v.push_back(float(p.max));
        p.setList(config, v);
      } else {
        p.set(config, p.get(config) == p.max ? p.min : p.max);
      }
      for (size_t k = 0; k < params.size(); ++k)
        EXPECT_EQ(formatParam(params[k], config) != formatParam(params[k], defaults), k == i)
            << name << ": setting " << p.name << " changed " << params[k].name;
    }
  }
}

TEST(Params, TextRoundTripsAndBadValuesNameTheFlag) {
  MethodSpec spec{RunShape{}, BpConfig{}};
  const std::vector<MethodParam>& params = methodParams(MethodKind::Bp);
  auto find = [&](const std::string& name) -> const MethodParam& {
    for (const MethodParam& p : params)
      if (p.name == name) return p;
    throw std::logic_error(name);
  };
  EXPECT_EQ(parseParam(find("nit"), spec.config, "12"), "");
  EXPECT_EQ(spec.get<BpConfig>()->network.epochs, 12);
  EXPECT_EQ(parseParam(find("sigma-c"), spec.config, "0.07"), "");
  EXPECT_FLOAT_EQ(spec.get<BpConfig>()->filter.sigmaC, 0.07f);
  EXPECT_EQ(formatParam(find("sigma-c"), spec.config), "0.07");
  EXPECT_EQ(parseParam(find("alphas"), spec.config, "0.5,2,4"), "");
  EXPECT_EQ(spec.get<BpConfig>()->filter.alphas, (std::vector<float>{0.5f, 2.0f, 4.0f}));
  EXPECT_EQ(formatParam(find("alphas"), spec.config), "0.5,2,4");
  EXPECT_EQ(parseParam(find("candidate-mode"), spec.config, "predicted"), "");
  EXPECT_EQ(spec.get<BpConfig>()->candidateMode, CandidateMode::Predicted);
  EXPECT_EQ(parseParam(find("warping"), spec.config, "false"), "");
  EXPECT_FALSE(spec.get<BpConfig>()->warping);

  EXPECT_NE(parseParam(find("nit"), spec.config, "1.5").find("--nit 1.5"), std::string::npos);
  EXPECT_NE(parseParam(find("nit"), spec.config, "-1").find("0..100000"), std::string::npos);
  EXPECT_NE(parseParam(find("candidate-mode"), spec.config, "best").find("traced, predicted"),
            std::string::npos);
  EXPECT_NE(parseParam(find("alphas"), spec.config, "1,x").find("--alphas"), std::string::npos);
  EXPECT_EQ(spec.get<BpConfig>()->network.epochs, 12);  // a refused value changes nothing

  const std::string changes = describeChanges(spec, BpConfig{});
  EXPECT_NE(changes.find("nit=12"), std::string::npos);
  EXPECT_NE(changes.find("sigma-c=0.07"), std::string::npos);
  EXPECT_NE(changes.find("warping=false"), std::string::npos);
  EXPECT_EQ(changes.find("hidden"), std::string::npos);
}

TEST(Params, TheBaselinesShareTheScheduleAndKeepTheirOwn) {
  for (MethodKind kind :
       {MethodKind::FDiv, MethodKind::Fuzzy, MethodKind::Gem, MethodKind::Cycles}) {
    std::set<std::string> names;
    for (const MethodParam& p : methodParams(kind)) names.insert(p.name);
    EXPECT_TRUE(names.count("initial-spp") && names.count("batch") && names.count("rounds"));
    EXPECT_EQ(names.count("divergence"), kind == MethodKind::FDiv ? 1u : 0u);
    EXPECT_EQ(names.count("gamma"), kind == MethodKind::Gem ? 1u : 0u);
  }
  // LD's own: whether it filters, and the filter's parameters it shares with BP.
  std::set<std::string> ld;
  for (const MethodParam& p : methodParams(MethodKind::Ld)) ld.insert(p.name);
  EXPECT_TRUE(ld.count("filter") && ld.count("nl-k") && ld.count("cross-filter"));
  EXPECT_EQ(ld.count("rounds"), 0u);
}

}  // namespace
}  // namespace penumbra
