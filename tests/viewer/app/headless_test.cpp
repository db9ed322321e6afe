// Headless screenshots of the viewer, through both EGL and OSMesa: the image and every
// overlay against stored golden PNGs (tests/data/golden/), the GL picture against the CPU
// reference of the display transform and overlay blend, slices when zoomed in, the panel,
// and the errors a broken shader gives.
//
// Tolerance: a screenshot fails when more than 1% of its pixels differ from the golden by
// more than 4/255 in any channel. On failure the actual, expected and difference images are
// written to the test output folder. PENUMBRA_UPDATE_GOLDENS=1 rewrites the goldens.
// The network kernel is pinned to SSE (PENUMBRA_NET_SIMD, set by CTest) so that the
// renders, hence the goldens, are the same on every x86-64 CPU.
#include "viewer/app/headless.h"
#include "core/image_io.h"
#include "methods/bp/consistent.h"
#include "methods/bp/state.h"
#include "methods/render.h"
#include "present/overlays.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"
#include "viewer/app/gl/display_renderer.h"
#include "viewer/app/gl/shader.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 64;
constexpr int kRounds = 3;

std::shared_ptr<const PreparedScene> tire() {
  static std::shared_ptr<const PreparedScene> scene = test::shippedScene("tire", kSize);
  return scene;
}

// A converged render of the same view, for the reference-error overlay.
std::shared_ptr<const Image> reference() {
  static std::shared_ptr<const Image> image = [] {
    RenderOptions o;
    o.spp = 256;
    o.seed = 99;
    return std::make_shared<const Image>(renderImage(*tire(), o).image);
  }();
  return image;
}

// The overlays that only the paper's rounds publish (the default preset runs no networks).
bool paperOnly(MapId overlay) { return overlay == maps::NetworkError; }

// The viewer on bp with `preset`, as the panel's preset button sets it.
void usePreset(ViewOptions& o, const char* preset) {
  o.method = o.methods->find("bp", preset);
  o.config() = o.methods->configFor("bp", preset);
}

ViewOptions options(MapId overlay) {
  ViewOptions o;
  o.scene = tire();
  // What `penumbra view` runs by default, or the tuned preset for a map only it has.
  usePreset(o, paperOnly(overlay) ? "tuned" : "consistent");
  // The networks map is there only with the networks on.
  if (overlay == maps::Networks) o.config().as<BpConsistentConfig>().networks = 1;
  o.shape.seed = 7;
  o.overlay = overlay;
  o.reference = reference();
  return o;
}

HeadlessBackend backendOf(const std::string& name) {
  return name == "osmesa" ? HeadlessBackend::OsMesa : HeadlessBackend::Egl;
}

std::string outputFile(const std::string& name) {
  const std::string path = test::outputPath("viewer/" + name);
  fs::create_directories(fs::path(path).parent_path());
  return path;
}

// Compares with tests/data/golden/<name>.png under the stated tolerance.
void expectMatchesGolden(const HeadlessFrame& frame, const std::string& name,
                         const std::string& label) {
  ASSERT_FALSE(frame.rgb.empty()) << frame.failure;
  const std::string golden = test::sourcePath("tests/data/golden/" + name + ".png");
  const char* update = std::getenv("PENUMBRA_UPDATE_GOLDENS");
  if (update && std::string(update) == "1") {
    fs::create_directories(fs::path(golden).parent_path());
    writePng8(golden, frame.width, frame.height, 3, frame.rgb);
    std::printf("wrote %s\n", golden.c_str());
    return;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; run with PENUMBRA_UPDATE_GOLDENS=1";
  int w = 0, h = 0;
  const std::vector<uint8_t> expected = readPng8(golden, w, h);
  ASSERT_EQ(w, frame.width) << golden;
  ASSERT_EQ(h, frame.height) << golden;
  size_t differing = 0;
  std::vector<uint8_t> diff(frame.rgb.size());
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    int worst = 0;
    for (int k = 0; k < 3; ++k) {
      const int d = std::abs(int(frame.rgb[3 * i + k]) - int(expected[4 * i + k]));
      worst = std::max(worst, d);
      diff[3 * i + k] = uint8_t(std::min(255, d * 8));
    }
    differing += worst > 4;
  }
  const double fraction = double(differing) / (double(w) * h);
  if (fraction > 0.01) {
    const std::string base = outputFile(label);
    writePng8(base + "_actual.png", w, h, 3, frame.rgb);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int k = 0; k < 3; ++k) rgb[3 * i + k] = expected[4 * i + k];
    writePng8(base + "_expected.png", w, h, 3, rgb);
    writePng8(base + "_diff.png", w, h, 3, diff);
    ADD_FAILURE() << label << ": " << differing << " pixels (" << fraction * 100
                  << "%) differ by more than 4/255 from " << golden << "; see " << base
                  << "_{actual,expected,diff}.png";
  }
}

class Screenshot : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(Screenshot, MatchesTheGolden) {
  const auto& [backend, overlayName] = GetParam();
  const auto overlay = overlayByName(overlayName);
  ASSERT_TRUE(overlay.has_value());
  HeadlessRequest request;
  request.backend = backendOf(backend);
  request.rounds = kRounds;
  const HeadlessFrame frame = renderHeadless(options(*overlay), request);
  EXPECT_EQ(frame.backend, backend);
  EXPECT_TRUE(frame.overlayUnavailable.empty()) << frame.overlayUnavailable;
  ASSERT_NE(frame.snapshot, nullptr);
  EXPECT_EQ(frame.snapshot->round, kRounds);
  EXPECT_EQ(frame.width, kSize);
  // Overlays draw their legend under the image.
  if (overlay->none())
    EXPECT_EQ(frame.height, kSize);
  else
    EXPECT_GT(frame.height, kSize);
  expectMatchesGolden(frame, overlayName, backend + "_" + overlayName);
}

std::vector<std::string> overlayNames() {
  std::vector<std::string> names = {"none"};
  for (const MapKind* o : overlayList()) names.push_back(o->name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Backends, Screenshot,
                         ::testing::Combine(::testing::Values("egl", "osmesa"),
                                            ::testing::ValuesIn(overlayNames())),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param);
                         });

// The names users were promised show the same overlays as the names of before.
TEST(HeadlessGl, OverlayAliasesShowTheirOverlays) {
  for (const auto& [alias, name] : {std::pair{"slices", "selected"}, {"filter-scale", "alpha"}}) {
    const auto overlay = overlayByName(alias);
    ASSERT_TRUE(overlay.has_value()) << alias;
    HeadlessRequest request;
    request.rounds = kRounds;
    const HeadlessFrame frame = renderHeadless(options(*overlay), request);
    expectMatchesGolden(frame, name, std::string("egl_") + alias);
  }
}

// The shaders get the C++ enums' values as #defines after their #version line; the line
// numbers of the compiler's messages stay the file's.
TEST(ShaderDefines, AreInjectedAfterTheVersionLine) {
  const std::vector<ShaderDefine> defines = {{"A", "1"}, {"B", "2u"}};
  EXPECT_EQ(injectDefines("#version 330 core\nvoid main() {}\n", defines),
            "#version 330 core\n#define A 1\n#define B 2u\n#line 2\nvoid main() {}\n");
  EXPECT_EQ(injectDefines("void main() {}\n", defines),
            "#define A 1\n#define B 2u\n#line 1\nvoid main() {}\n");
  EXPECT_EQ(injectDefines("#version 330 core\n", {}), "#version 330 core\n");
  // The display shaders' constants come from the C++ enums.
  bool filmic = false;
  for (const ShaderDefine& d : displayShaderDefines())
    if (d.name == "TONE_CURVE_FILMIC") filmic = d.value == std::to_string(int(ToneCurve::Filmic));
  EXPECT_TRUE(filmic);
}

// The GL picture equals composeFrame (the CPU reference) to within one level of rounding.
TEST(HeadlessGl, PictureMatchesTheCpuReference) {
  struct Variant {
    MapId overlay;
    float exposure;
    ToneCurve curve;
  };
  for (const Variant v : {Variant{MapId(), 0.0f, ToneCurve::Srgb},
                          Variant{maps::ErrorEstimate, 1.0f, ToneCurve::Filmic},
                          Variant{maps::FilterScale, -0.5f, ToneCurve::Srgb}}) {
    ViewOptions o = options(v.overlay);
    o.display.exposure = v.exposure;
    o.display.curve = v.curve;
    o.blend = 0.6f;
    const DisplaySettings display = o.display;
    HeadlessRequest request;
    request.rounds = 2;
    const HeadlessFrame frame = renderHeadless(o, request);
    ASSERT_NE(frame.snapshot, nullptr);
    const Image& shown = frame.snapshot->reconstructed;
    const OverlayImage overlay = buildOverlay(*frame.snapshot, v.overlay, shown, reference().get());
    const Image cpu = composeFrame(shown, display, &overlay, 0.6f);
    int worst = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int k = 0; k < 3; ++k) {
          const int gl = frame.rgb[3 * (size_t(y) * frame.width + x) + k];
          const int ref = int(std::lround(255.0f * cpu.at(x, y)[k]));
          worst = std::max(worst, std::abs(gl - ref));
        }
    EXPECT_LE(worst, 1) << v.overlay.name() << " exposure " << v.exposure;
  }
}

// Zoomed in, the Selected overlay outlines the slices inside each pixel; without an
// overlay every image pixel is a flat block.
TEST(HeadlessGl, SlicesAreDrawnWhenZoomedIn) {
  auto blocksWithDetail = [](MapId overlay) {
    HeadlessRequest request;
    request.rounds = 2;
    request.width = request.height = 128;
    request.zoom = 16.0f;
    request.centerX = request.centerY = kSize / 2.0f;
    // Slices are the paper's rounds' (the tuned preset's); the default preset has none.
    ViewOptions o = options(overlay);
    usePreset(o, "tuned");
    const HeadlessFrame frame = renderHeadless(o, request);
    int detailed = 0;
    for (int by = 0; by < 8; ++by)
      for (int bx = 0; bx < 8; ++bx) {
        const uint8_t* first = &frame.rgb[3 * (size_t(by * 16 + 8) * 128 + bx * 16 + 8)];
        bool flat = true;
        for (int y = 1; y < 15 && flat; ++y)
          for (int x = 1; x < 15 && flat; ++x) {
            const uint8_t* p = &frame.rgb[3 * (size_t(by * 16 + y) * 128 + bx * 16 + x)];
            flat = p[0] == first[0] && p[1] == first[1] && p[2] == first[2];
          }
        detailed += !flat;
      }
    return detailed;
  };
  EXPECT_EQ(blocksWithDetail(MapId()), 0);
  EXPECT_EQ(blocksWithDetail(maps::Selected), 64);
}

TEST(HeadlessGl, TheRenderRegionIsOutlined) {
  // At zoom 4 the outline is a line of one or two screen pixels just outside the region.
  HeadlessRequest request;
  request.rounds = 1;
  request.width = request.height = 256;
  request.zoom = 4.0f;
  request.centerX = request.centerY = kSize / 2.0f;
  ViewOptions o = options(MapId());
  o.region = {20, 24, 16, 8};
  const HeadlessFrame frame = renderHeadless(o, request);
  const auto rgb = [&](int x, int y) {
    const uint8_t* p = &frame.rgb[3 * (size_t(y) * 256 + size_t(x))];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  const std::array<int, 3> outline{255, 191, 51};
  // Image x = 20 is screen x = 128 + (20 - 32) * 4 = 80; y = 24 is screen 96, y = 32 is 128.
  EXPECT_EQ(rgb(79, 110), outline) << "left edge";
  EXPECT_EQ(rgb(100, 95), outline) << "top edge";
  EXPECT_EQ(rgb(100, 128), outline) << "bottom edge";
  EXPECT_EQ(rgb(144, 110), outline) << "right edge";
  EXPECT_NE(rgb(100, 110), outline) << "inside";
  EXPECT_NE(rgb(60, 110), outline) << "outside";
}

TEST(HeadlessGl, TheUiDrawsThePanelAndTheInspector) {
  HeadlessRequest request;
  request.rounds = 2;
  request.width = 900;
  request.height = 600;
  const HeadlessFrame plain = renderHeadless(options(MapId()), request);
  request.withUi = true;
  request.inspectX = 30;
  request.inspectY = 40;
  const HeadlessFrame ui = renderHeadless(options(MapId()), request);
  ASSERT_EQ(plain.rgb.size(), ui.rgb.size());
  // The panel (top left) and the inspector (top right) cover what was background.
  auto changed = [&](int x0, int y0, int x1, int y1) {
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int k = 0; k < 3; ++k)
          n += plain.rgb[3 * (size_t(y) * 900 + x) + k] != ui.rgb[3 * (size_t(y) * 900 + x) + k];
    return n;
  };
  EXPECT_GT(changed(10, 10, 340, 200), 10000u);
  EXPECT_GT(changed(600, 10, 890, 200), 10000u);
  writePng8(outputFile("with_ui.png"), ui.width, ui.height, 3, ui.rgb);
}

class ShaderDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: CTest runs the tests of this fixture in parallel processes.
    dir_ = test::outputPath(std::string("viewer/shaders_") +
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (const auto& entry : fs::directory_iterator(test::sourcePath("shaders")))
      fs::copy(entry.path(), fs::path(dir_) / entry.path().filename());
    setenv("PENUMBRA_SHADER_DIR", dir_.c_str(), 1);
  }
  void TearDown() override { unsetenv("PENUMBRA_SHADER_DIR"); }
  std::string dir_;
};

TEST_F(ShaderDirectory, ACompileErrorNamesTheFileAndCarriesTheLog) {
  std::ofstream(fs::path(dir_) / "view.frag") << "#version 330 core\nvoid main() { nonsense; }\n";
  HeadlessRequest request;
  request.rounds = 1;
  try {
    renderHeadless(options(MapId()), request);
    FAIL() << "no error for a broken shader";
  } catch (const GlError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("view.frag"), std::string::npos) << message;
    EXPECT_NE(message.find("compile error"), std::string::npos) << message;
    EXPECT_NE(message.find("nonsense"), std::string::npos) << message;  // the compiler's log
  }
}

TEST_F(ShaderDirectory, AMissingShaderNamesTheFile) {
  fs::remove(fs::path(dir_) / "composite.frag");
  HeadlessRequest request;
  request.rounds = 1;
  try {
    renderHeadless(options(MapId()), request);
    FAIL() << "no error for a missing shader";
  } catch (const GlError& e) {
    EXPECT_NE(std::string(e.what()).find("composite.frag"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra
