// The methods' parameter tables: every entry reads and writes its own field, names are
// unique, values parse and print back, bad values are refused naming the flag, and the ranges
// are checked from the table alone.
#include "methods/params.h"

#include "methods/bp/consistent.h"
#include "methods/bp/paper.h"
#include "methods/factory.h"
#include "methods/gem/gem.h"
#include "methods/ld/ld.h"

#include <gtest/gtest.h>

#include <set>

namespace penumbra {
namespace {

TEST(Params, EveryEntryReadsAndWritesItsOwnField) {
  for (const MethodDescriptor* method : builtinMethods().methods()) {
    const std::string name = method->title();
    const std::vector<MethodParam>& params = method->params();
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
      MethodConfig config = method->defaults();
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
  MethodSpec spec{RunShape{}, bpPaperMethod().defaults()};
  const std::vector<MethodParam>& params = bpPaperMethod().params();
  auto find = [&](const std::string& name) -> const MethodParam& {
    for (const MethodParam& p : params)
      if (p.name == name) return p;
    throw std::logic_error(name);
  };
  EXPECT_EQ(parseParam(find("nit"), spec.config, "12"), "");
  EXPECT_EQ(spec.config.as<BpPaperConfig>().network.epochs, 12);
  EXPECT_EQ(parseParam(find("sigma-c"), spec.config, "0.07"), "");
  EXPECT_FLOAT_EQ(spec.config.as<BpPaperConfig>().filter.sigmaC, 0.07f);
  EXPECT_EQ(formatParam(find("sigma-c"), spec.config), "0.07");
  EXPECT_EQ(parseParam(find("alphas"), spec.config, "0.5,2,4"), "");
  EXPECT_EQ(spec.config.as<BpPaperConfig>().filter.alphas, (std::vector<float>{0.5f, 2.0f, 4.0f}));
  EXPECT_EQ(formatParam(find("alphas"), spec.config), "0.5,2,4");
  EXPECT_EQ(parseParam(find("candidate-mode"), spec.config, "predicted"), "");
  EXPECT_EQ(spec.config.as<BpPaperConfig>().candidateMode, CandidateMode::Predicted);
  EXPECT_EQ(parseParam(find("warping"), spec.config, "false"), "");
  EXPECT_FALSE(spec.config.as<BpPaperConfig>().warping);

  EXPECT_NE(parseParam(find("nit"), spec.config, "1.5").find("--nit 1.5"), std::string::npos);
  EXPECT_NE(parseParam(find("nit"), spec.config, "-1").find("0..100000"), std::string::npos);
  EXPECT_NE(parseParam(find("candidate-mode"), spec.config, "best").find("traced, predicted"),
            std::string::npos);
  EXPECT_NE(parseParam(find("alphas"), spec.config, "1,x").find("--alphas"), std::string::npos);
  EXPECT_EQ(spec.config.as<BpPaperConfig>().network.epochs, 12);  // a refused value changes nothing

  const std::string changes = describeChanges(spec.config, bpPaperMethod().defaults());
  EXPECT_NE(changes.find("nit=12"), std::string::npos);
  EXPECT_NE(changes.find("sigma-c=0.07"), std::string::npos);
  EXPECT_NE(changes.find("warping=false"), std::string::npos);
  EXPECT_EQ(changes.find("hidden"), std::string::npos);
}

TEST(Params, TheBaselinesShareTheScheduleAndKeepTheirOwn) {
  const MethodRegistry& methods = builtinMethods();
  for (const char* name : {"fdiv", "fuzzy", "gem", "cycles"}) {
    std::set<std::string> names;
    for (const MethodParam& p : methods.find(name)->params()) names.insert(p.name);
    EXPECT_TRUE(names.count("initial-spp") && names.count("batch") && names.count("rounds"));
    EXPECT_EQ(names.count("divergence"), std::string(name) == "fdiv" ? 1u : 0u);
    EXPECT_EQ(names.count("gamma"), std::string(name) == "gem" ? 1u : 0u);
  }
  // LD's own: whether it filters, and the filter's parameters it shares with BP.
  std::set<std::string> ld;
  for (const MethodParam& p : ldMethod().params()) ld.insert(p.name);
  EXPECT_TRUE(ld.count("filter") && ld.count("nl-k") && ld.count("cross-filter"));
  EXPECT_EQ(ld.count("rounds"), 0u);
}

// Each of BP's algorithms has the parameters it reads: the networks and schedule both, the
// filterbank and candidates only the paper's, the film's filter and allocation only the
// consistent one's.
TEST(Params, BpsAlgorithmsHaveOnlyTheParametersTheyRead) {
  for (const char* shared : {"nit", "hidden", "inputs", "coarse-spp", "rounds", "reservoir",
                             "slices", "reconstruct", "targets", "prediction-draws"}) {
    EXPECT_NE(bpPaperMethod().param(shared), nullptr) << shared;
    EXPECT_NE(bpConsistentMethod().param(shared), nullptr) << shared;
  }
  for (const char* paper : {"psi", "candidates", "levels", "radius", "alphas", "sigma-c", "phi",
                            "second-pass-alpha", "candidate-mode", "outlier-tau", "warping",
                            "outlier-removal", "second-pass", "stratified-mean", "top-up"}) {
    EXPECT_NE(bpPaperMethod().param(paper), nullptr) << paper;
    EXPECT_EQ(bpConsistentMethod().param(paper), nullptr) << paper;
  }
  for (const char* consistent : {"retrain-growth", "network-weight", "absolute-weight",
                                 "sample-floor", "slice-steering", "nl-k", "features"}) {
    EXPECT_NE(bpConsistentMethod().param(consistent), nullptr) << consistent;
    EXPECT_EQ(bpPaperMethod().param(consistent), nullptr) << consistent;
  }
  EXPECT_EQ(bpPaperMethod().param("algorithm"), nullptr);  // the preset chooses it
}

// The ranges are the table's, open or closed, and checkParams reports the first value outside
// them by its flag; a toggle is named by its flag.
TEST(Params, CheckParamsUsesTheTablesRanges) {
  MethodConfig gem = gemMethod().defaults();
  const MethodParam* gamma = gemMethod().param("gamma");
  ASSERT_NE(gamma, nullptr);
  EXPECT_TRUE(gamma->minOpen && gamma->maxOpen);
  EXPECT_EQ(checkParams(gemMethod().params(), gem), "");
  gem.as<GemConfig>().gamma = 0.0f;  // c_gamma needs gamma > 0
  EXPECT_NE(checkParams(gemMethod().params(), gem).find("--gamma 0: must be in (0, 0.526316)"),
            std::string::npos)
      << checkParams(gemMethod().params(), gem);
  gem.as<GemConfig>().gamma = 1 / 1.9f;  // and 1.9 gamma < 1
  EXPECT_NE(checkParams(gemMethod().params(), gem), "");
  gem.as<GemConfig>().gamma = 0.5f;
  EXPECT_EQ(checkParams(gemMethod().params(), gem), "");
  EXPECT_NE(parseParam(*gamma, gem, "0").find("must be in (0, 0.526316)"), std::string::npos);

  MethodConfig paper = bpPaperMethod().defaults();
  paper.as<BpPaperConfig>().filter.alphas = {1.0f, -2.0f, 3.0f, 4.0f, 5.0f};
  EXPECT_NE(checkParams(bpPaperMethod().params(), paper).find("--alphas"), std::string::npos);
  paper.as<BpPaperConfig>().filter.alphas = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f};
  paper.as<BpPaperConfig>().network.hidden = 0;
  EXPECT_NE(checkParams(bpPaperMethod().params(), paper).find("--hidden 0"), std::string::npos);
  // The filter's ranges, named by their flags (not the C++ fields).
  MethodConfig ld = ldMethod().defaults();
  ld.as<LdConfig>().denoise.patchRadius = 9;
  EXPECT_NE(recon::validate(ld.as<LdConfig>().denoise).find("--nl-patch 9"), std::string::npos);
  EXPECT_NE(validate({RunShape{}, ld}).find("--nl-patch"), std::string::npos);
}

}  // namespace
}  // namespace penumbra
