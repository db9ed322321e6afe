// Adding a method touches its own folder and one line of the methods' list: here the toy's
// "folder" is this file and the list is a registry of the built-in methods and the toy. Its
// flags, presets and help, its panel widgets and overlay, its `render --stats` record and its
// compare label and description then appear with no other edit.
#include "cli/compare.h"
#include "cli/method_options.h"
#include "cli/render_stats.h"
#include "methods/factory.h"
#include "present/overlays.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"
#include "viewer/app/headless.h"
#include "viewer/app/view_panel.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <algorithm>

namespace penumbra {
namespace {

// ---- The toy's folder -----------------------------------------------------------------------

struct ToyConfig {
  float gain = 1.0f;
  int steps = 2;
  bool glow = false;
};

const ParamTable<ToyConfig>& toyParams() {
  static const ParamTable<ToyConfig> table = [] {
    ParamTable<ToyConfig> t;
    t.group("Toy method")
        .real("toy-gain", "gain", "Brightness of the toy's grey image",
              [](auto& c) -> auto& { return c.gain; }, 0, 10, {0, 4})
        .integer("toy-steps", "steps", "Rounds the toy runs",
                 [](auto& c) -> auto& { return c.steps; }, 1, 100, {1, 10})
        .toggle(
            "toy-glow", "glow", "Add a glow", "--toy-glow",
            [](auto& c) -> auto& { return c.glow; });
    return t;
  }();
  return table;
}

// The toy's own map: the pixel's column over the width.
constexpr MapKind kToyRamp{"toy_ramp", nullptr, "Toy ramp", 20};

class ToyMethod final : public ProgressiveMethod {
 public:
  ToyMethod(const PreparedScene& prepared, const RunShape& shape, const ToyConfig& config)
      : ProgressiveMethod(shape),
        config_(config),
        width_(prepared.scene.settings.width),
        height_(prepared.scene.settings.height) {}
  void runRound(const std::atomic<bool>*) override {
    if (!done()) ++rounds_;
  }
  int roundsDone() const override { return rounds_; }
  std::shared_ptr<Snapshot> snapshot(bool, const std::atomic<bool>*) override {
    auto snap = std::make_shared<Snapshot>();
    snap->method = "toy";
    snap->round = rounds_;
    snap->final = done();
    snap->width = width_;
    snap->height = height_;
    snap->raw = Image(width_, height_, vec3(0.1f * config_.gain * float(rounds_)));
    snap->reconstructed = snap->raw;
    const size_t n = size_t(width_) * height_;
    std::vector<float> ramp(n);
    for (size_t p = 0; p < n; ++p) ramp[p] = float(p % size_t(width_)) / float(width_);
    snap->addMap(kToyRamp, "column", ramp, MapLegend::sequential(0, 1));
    addSelectedMap(*snap, std::vector<uint8_t>(n, 1));
    addSampleCountMaps(*snap, std::vector<uint32_t>(n, rounds_), std::vector<uint32_t>(n, rounds_));
    snap->keptSamples = uint64_t(rounds_) * n;
    snap->seconds = seconds();
    snap->addStat("toy_steps_run", double(rounds_));
    return snap;
  }
  size_t memoryBytes() const override { return 0; }
  PixelInspection inspect(int x, int y) const override {
    return startInspection(x, y, width_, height_, rounds_, "toy");
  }

 protected:
  bool budgetSpent() const override { return rounds_ >= config_.steps; }

 private:
  ToyConfig config_;
  int width_, height_;
  int rounds_ = 0;
};

const MethodDescriptor& toyMethod() {
  static const MethodDescriptor descriptor([] {
    MethodDefinition<ToyConfig> d;
    d.name = "toy";
    d.description = "A toy method (the tests' own)";
    d.params = &toyParams();
    d.presets = {{"bright", "twice the gain", [](ToyConfig& c) { c.gain = 2.0f; }}};
    d.maps = {&kToyRamp, &maps::Selected, &maps::SampleCount, &maps::TracedCount};
    d.abilities = [](const ToyConfig&) { return MethodAbilities{}; };
    d.check = [](const ToyConfig& c, const RunShape&) {
      return c.glow && c.gain == 0 ? std::string("--toy-glow needs --toy-gain above 0")
                                   : std::string();
    };
    d.make = construct<ToyMethod, ToyConfig>;
    return d;
  }());
  return descriptor;
}

// ---- The one list line ----------------------------------------------------------------------

const MethodRegistry& withToy() {
  static const MethodRegistry registry = [] {
    std::vector<const MethodDescriptor*> list = builtinMethods().methods();
    list.push_back(&toyMethod());  // the line
    return MethodRegistry(list);
  }();
  return registry;
}

// ---- What appears with no other edit --------------------------------------------------------

std::shared_ptr<PreparedScene> cornell(int size) { return test::shippedScene("cornell", size); }

// The toy's flags, by name, with its help; --method and --preset know it.
TEST(ToyMethod, ItsFlagsAndPresetAreOnTheCommandLine) {
  CLI::App app;
  MethodOptions options;
  options.registry = &withToy();
  addMethodOptions(app, options);
  const std::string help = app.help();
  for (const char* text : {"--toy-gain", "--toy-steps", "--toy-glow", "Toy method",
                           "toy (A toy method (the tests' own))", "bright (twice the gain)"})
    EXPECT_NE(help.find(text), std::string::npos) << text;
  app.parse("--method toy --preset bright --toy-steps 5 --toy-glow");
  const MethodSpec spec = options.spec(RunShape::batch(4));
  ASSERT_EQ(&spec.method(), &toyMethod());
  const ToyConfig& c = spec.config.as<ToyConfig>();
  EXPECT_FLOAT_EQ(c.gain, 2.0f);  // the preset
  EXPECT_EQ(c.steps, 5);
  EXPECT_TRUE(c.glow);
}

TEST(ToyMethod, ItsChecksAndRangesNameItsFlags) {
  CLI::App app;
  MethodOptions options;
  options.registry = &withToy();
  addMethodOptions(app, options);
  app.parse("--method toy --toy-glow --toy-gain 0");
  try {
    options.spec(RunShape::batch(4));
    FAIL() << "no exception";
  } catch (const CommandError& e) {
    EXPECT_STREQ(e.what(), "--toy-glow needs --toy-gain above 0");
  }
  // Its flags are read by the toy alone: on another method they are an error naming it.
  CLI::App other;
  MethodOptions ld;
  ld.registry = &withToy();
  addMethodOptions(other, ld);
  other.parse("--method ld --toy-steps 3");
  try {
    ld.spec(RunShape::batch(4));
    FAIL() << "no exception";
  } catch (const CommandError& e) {
    EXPECT_NE(std::string(e.what()).find("--toy-steps: ld does not read it; it is read by toy"),
              std::string::npos)
        << e.what();
  }
}

// The panel offers it, and its parameters are the widgets of its section.
TEST(ToyMethod, ItsPanelWidgetsAndOverlayAppear) {
  ViewOptions o;
  o.methods = &withToy();
  o.configs = ViewOptions::defaultConfigs(withToy());
  o.method = &toyMethod();
  const std::vector<ParamSection> sections = methodSections(o);
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_EQ(sections[0].title, "Toy method");
  std::vector<std::string> labels;
  for (const MethodParam* p : sections[0].params) labels.push_back(p->label);
  EXPECT_EQ(labels, (std::vector<std::string>{"gain", "steps", "glow"}));
  const auto names = withToy().names();
  EXPECT_NE(std::find(names.begin(), names.end(), "toy"), names.end());
  // Its map is an overlay, after the others; the built-in list does not have it.
  EXPECT_EQ(overlayByName("toy_ramp", withToy()), MapId(kToyRamp));
  EXPECT_FALSE(overlayByName("toy_ramp").has_value());
  EXPECT_EQ(overlayList(withToy()).back(), &kToyRamp);
}

// The viewer runs it and draws its overlay and the panel (headless, the same code as the window).
TEST(ToyMethod, TheViewerRunsItWithItsOverlay) {
  ViewOptions o;
  o.scene = cornell(16);
  o.methods = &withToy();
  o.configs = ViewOptions::defaultConfigs(withToy());
  o.method = &toyMethod();
  o.overlay = kToyRamp;
  HeadlessRequest request;
  request.backend = HeadlessBackend::OsMesa;
  request.rounds = 2;
  request.withUi = true;
  const HeadlessFrame frame = renderHeadless(o, request);
  ASSERT_TRUE(frame.failure.empty()) << frame.failure;
  ASSERT_TRUE(frame.snapshot);
  EXPECT_EQ(frame.snapshot->method, "toy");
  EXPECT_TRUE(frame.overlayUnavailable.empty()) << frame.overlayUnavailable;
}

// render --stats: its name, description, parameters, its own figure, its kept spp.
TEST(ToyMethod, ItsStatsAreRecorded) {
  auto prepared = cornell(8);
  MethodSpec spec{RunShape::batch(4), withToy().configFor("toy", "bright")};
  auto method = makeMethod(*prepared, spec);
  while (!method->done()) method->runRound(nullptr);
  const auto snap = method->snapshot();
  const nlohmann::json j = methodRunStats(spec, "bright", *snap, method->memoryBytes());
  EXPECT_EQ(j["method"], "toy");
  EXPECT_EQ(j["preset"], "bright");
  EXPECT_EQ(j["description"], "A toy method (the tests' own)");
  EXPECT_EQ(j["config"]["toy_gain"], 2.0);
  EXPECT_EQ(j["config"]["toy_steps"], 2);
  EXPECT_EQ(j["config"]["toy_glow"], false);
  EXPECT_EQ(j["toy_steps_run"], 2.0);
  EXPECT_EQ(j["kept_spp"], 2.0);
  EXPECT_EQ(j["rounds"], 2);
  EXPECT_TRUE(j.contains("density_histogram"));  // its sample counts, as every method's
}

// compare: an entry names it with its preset and settings, and the report describes it.
TEST(ToyMethod, ItsCompareEntryAndLabel) {
  const std::vector<Entry> entries = parseEntries("ld,toy:bright:toy-steps=3@8", 4, withToy());
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].label, "toy:bright:toy-steps=3@8");
  EXPECT_EQ(entries[1].method, &toyMethod());
  EXPECT_EQ(entries[1].preset, "bright");
  EXPECT_EQ(entries[1].spp, 8);
  CompareFlags flags;
  flags.method.registry = &withToy();
  EXPECT_EQ(describeEntry(flags, entries[1]),
            "A toy method (the tests' own), bright preset, toy-steps=3");
  EXPECT_THROW(parseEntries("toy:dim", 4, withToy()), CommandError);
  EXPECT_THROW(parseEntries("toy:frobs=2", 4, withToy()), CommandError);
  EXPECT_THROW(parseEntries("toy", 4), CommandError);  // not a built-in method
}

}  // namespace
}  // namespace penumbra
