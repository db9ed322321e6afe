// The display transform, the overlays built from a snapshot, and their composition: the CPU
// reference of what the display shader draws.
#include "present/overlays.h"

#include "core/image.h"
#include "eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace penumbra {
namespace {

const std::vector<float> kBias = {0.0f, 0.25f, 0.5f,
                                  1.0f, 2.0f,  std::numeric_limits<float>::quiet_NaN()};

// A snapshot with the maps as BP fills them: bias over [0, 1], the selected pixels, the
// sample counts and the filter scales labelled by their alphas.
Snapshot smallSnapshot() {
  Snapshot s;
  s.method = "bp";
  s.width = 3;
  s.height = 2;
  s.raw = Image(3, 2, vec3(0.5f));
  s.reconstructed = s.raw;
  s.addMap(maps::ErrorEstimate, "bias", kBias, MapLegend::sequential(0.0f, 1.0f));
  addSelectedMap(s, {0, 1, 0, 1, 0, 1});
  addSampleCountMaps(s, {4, 8, 12, 16, 4, 4}, {4, 8, 12, 16, 4, 4});
  s.addMap(maps::FilterScale, "filter alpha", {0, 1, 2, 3, 4, 0},
           MapLegend::categorical({"a=0.1", "a=1", "a=3", "a=5", "a=10"}));
  return s;
}

TEST(Display, SrgbTransformMatchesTheTransferFunctionAndExposure) {
  const DisplaySettings plain;
  EXPECT_NEAR(displayTransform(vec3(0.18f), plain).x, linearToSrgb(0.18f), 1e-6f);
  EXPECT_EQ(displayTransform(vec3(2.0f), plain).y, 1.0f);  // clamped
  EXPECT_EQ(displayTransform(vec3(-1.0f), plain).z, 0.0f);
  DisplaySettings plusOne;
  plusOne.exposure = 1.0f;  // one stop doubles the linear value
  EXPECT_NEAR(displayTransform(vec3(0.1f), plusOne).x, linearToSrgb(0.2f), 1e-6f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(displayTransform(vec3(nan), plain).x, 0.0f);
}

TEST(Display, FilmicCurveIsMonotonicWithAShoulder) {
  EXPECT_EQ(filmicCurve(0.0f), 0.0f);
  float previous = 0.0f;
  for (float x = 0.01f; x < 20.0f; x *= 1.3f) {
    const float y = filmicCurve(x);
    EXPECT_GE(y, previous) << x;
    previous = y;
  }
  // Values above 1 are compressed, not clipped: 1, 2 and 4 stay apart, all below 1 (the
  // fitted curve reaches 1 near x = 6).
  EXPECT_LT(filmicCurve(1.0f), filmicCurve(2.0f));
  EXPECT_LT(filmicCurve(2.0f), filmicCurve(4.0f));
  EXPECT_LT(filmicCurve(4.0f), 1.0f);
  EXPECT_EQ(filmicCurve(std::numeric_limits<float>::infinity()), 1.0f);
  DisplaySettings filmic;
  filmic.curve = ToneCurve::Filmic;
  EXPECT_NEAR(displayTransform(vec3(2.0f), filmic).x, linearToSrgb(filmicCurve(2.0f)), 1e-6f);
}

TEST(Overlays, NamesRoundTripAndNumberKeysFollowTheList) {
  ASSERT_GE(overlayList().size(), 6u);
  EXPECT_EQ(overlayList()[0], &maps::ErrorEstimate);
  for (const MapKind* o : overlayList()) {
    ASSERT_TRUE(overlayByName(o->name).has_value()) << o->name;
    EXPECT_EQ(*overlayByName(o->name), MapId(*o));
    if (o->alias) {
      EXPECT_EQ(overlayByName(o->alias), MapId(*o)) << o->alias;
    }
  }
  EXPECT_EQ(overlayByName("none"), MapId());
  EXPECT_EQ(overlayByName("slices"), maps::Selected);
  EXPECT_EQ(overlayByName("filter-scale"), maps::FilterScale);
  EXPECT_FALSE(overlayByName("sparkle").has_value());
}

TEST(Overlays, BiasMapUsesViridisOverZeroToOneAndMagentaForNaN) {
  const Snapshot s = smallSnapshot();
  const OverlayImage o = buildOverlay(s, maps::ErrorEstimate, s.reconstructed, nullptr);
  ASSERT_TRUE(o.available()) << o.unavailable;
  EXPECT_EQ(o.label, "bias");
  EXPECT_EQ(o.legend.kind, ColorMapKind::Sequential);
  EXPECT_FLOAT_EQ(o.legend.maxValue, 1.0f);
  auto srgb = [](vec3 c) { return vec3(linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)); };
  for (int i = 0; i < 5; ++i) {
    const vec3 expected = colormapViridis(std::min(1.0f, kBias[i]));
    const vec3 got = srgb(o.colors.pixels[i]);
    EXPECT_NEAR(got.x, expected.x, 2e-3f) << i;
    EXPECT_NEAR(got.y, expected.y, 2e-3f) << i;
    EXPECT_NEAR(got.z, expected.z, 2e-3f) << i;
  }
  // Bias 2 is clamped to the top of the map, like bias 1.
  EXPECT_EQ(o.colors.pixels[4], o.colors.pixels[3]);
  EXPECT_EQ(o.colors.pixels[5], vec3(1.0f, 0.0f, 1.0f));
}

TEST(Overlays, CategoricalMapsUseOneColourPerCategory) {
  const Snapshot s = smallSnapshot();
  const OverlayImage a = buildOverlay(s, maps::FilterScale, s.raw, nullptr);
  ASSERT_TRUE(a.available());
  EXPECT_EQ(a.legend.categories.size(), 5u);
  EXPECT_EQ(a.legend.categories[0], "a=0.1");  // the method's own labels
  EXPECT_EQ(a.colors.pixels[0], categoryColor(0, 5));
  EXPECT_EQ(a.colors.pixels[4], categoryColor(4, 5));
  EXPECT_EQ(a.colors.pixels[5], a.colors.pixels[0]);
  const OverlayImage sel = buildOverlay(s, maps::Selected, s.raw, nullptr);
  EXPECT_EQ(sel.colors.pixels[1], categoryColor(1, 2));
  EXPECT_EQ(sel.colors.pixels[0], categoryColor(0, 2));
}

TEST(Overlays, MissingMapsSayWhy) {
  Snapshot s = smallSnapshot();
  s.method = "ld";
  std::erase_if(s.maps, [](const SnapshotMap& m) { return m.id == maps::ErrorEstimate; });
  const OverlayImage o = buildOverlay(s, maps::ErrorEstimate, s.raw, nullptr);
  EXPECT_FALSE(o.available());
  EXPECT_NE(o.unavailable.find("ld"), std::string::npos);
  const OverlayImage r = buildOverlay(s, maps::ReferenceError, s.raw, nullptr);
  EXPECT_FALSE(r.available());
  EXPECT_NE(r.unavailable.find("--reference"), std::string::npos);
  const Image wrongSize(2, 2);
  const OverlayImage w = buildOverlay(s, maps::ReferenceError, s.raw, &wrongSize);
  EXPECT_FALSE(w.available());
  EXPECT_NE(w.unavailable.find("2x2"), std::string::npos);
}

TEST(Overlays, ReferenceErrorIsTheRelativeSquaredErrorOfTheShownImage) {
  Snapshot s = smallSnapshot();
  Image reference(3, 2, vec3(0.5f));
  reference.pixels[2] = vec3(1.0f);  // one pixel is off: (0.5-1)^2 / (1 + 0.01)
  const OverlayImage o = buildOverlay(s, maps::ReferenceError, s.raw, &reference);
  ASSERT_TRUE(o.available());
  EXPECT_NEAR(o.values[2], 0.25f / 1.01f, 1e-6f);
  EXPECT_EQ(o.values[0], 0.0f);
  EXPECT_GT(o.legend.maxValue, 0.0f);
}

TEST(Compose, BlendsInDisplaySpaceAndZeroBlendLeavesTheImage) {
  const vec3 display(0.2f, 0.4f, 0.6f);
  const vec3 red(1.0f, 0.0f, 0.0f);
  EXPECT_EQ(composePixel(display, red, 0.0f), display);
  EXPECT_EQ(composePixel(display, red, 1.0f), red);
  const vec3 half = composePixel(display, red, 0.5f);
  EXPECT_NEAR(half.x, 0.6f, 1e-6f);
  EXPECT_NEAR(half.y, 0.2f, 1e-6f);
  EXPECT_EQ(composePixel(display, red, 3.0f), red);  // clamped
  // The overlay colour is sRGB encoded before the mix.
  EXPECT_NEAR(composePixel(vec3(0.0f), vec3(0.18f), 1.0f).x, linearToSrgb(0.18f), 1e-6f);
}

TEST(Compose, FrameAppliesTheTransformThenTheOverlay) {
  const Snapshot s = smallSnapshot();
  const OverlayImage o = buildOverlay(s, maps::SampleCount, s.raw, nullptr);
  ASSERT_TRUE(o.available());
  DisplaySettings settings;
  settings.exposure = -1.0f;
  const Image plain = composeFrame(s.raw, settings, nullptr, 0.7f);
  EXPECT_NEAR(plain.pixels[0].x, linearToSrgb(0.25f), 1e-6f);
  const Image mixed = composeFrame(s.raw, settings, &o, 0.7f);
  for (size_t i = 0; i < mixed.pixels.size(); ++i)
    EXPECT_EQ(mixed.pixels[i], composePixel(plain.pixels[i], o.colors.pixels[i], 0.7f));
  OverlayImage wrong = o;
  wrong.colors = Image(1, 1);
  EXPECT_THROW(composeFrame(s.raw, settings, &wrong, 0.5f), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
