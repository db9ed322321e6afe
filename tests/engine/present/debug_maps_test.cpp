// Tests for engine/debug_maps: the false colours of continuous and categorical maps, the
// picture's size and padding, the legend's content, the bitmap font (drawn, distinct, clipped)
// and the EXR + PNG pair written by writeDebugMap.
#include "present/debug_maps.h"

#include "core/image_io.h"
#include "eval/metrics.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

using test::kInf;
using test::kNaN;
constexpr int kStripHeight = 34;  // legend strip height at scale 1 (maps under 640 wide)

vec3 viridisLinear(float t) {
  const vec3 srgb = colormapViridis(t);
  return vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
}

void expectColorNear(vec3 actual, vec3 expected, const std::string& what) {
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(actual[k], expected[k], 1e-5f) << what << " channel " << k;
}

// The maps' titles: "test" for the continuous ones, "classes" for the categorical ones.
MapLegend continuousLegend(float minValue, float maxValue) {
  return MapLegend::sequential(minValue, maxValue);
}

MapLegend categoricalLegend(std::vector<std::string> labels) {
  return MapLegend::categorical(std::move(labels));
}

// Whether some pixel of rows [top, image.height) has exactly this colour.
bool stripContains(const Image& image, int top, vec3 color) {
  for (int y = top; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.at(x, y) == color) return true;
  return false;
}

Image textImage(const std::string& text, int scale = 1) {
  Image image(64 * scale, 12 * scale);
  drawText(image, scale, scale, text, vec3(1.0f), scale);
  return image;
}

int litPixels(const Image& image) {
  int count = 0;
  for (const vec3& p : image.pixels) count += p != vec3(0.0f);
  return count;
}

TEST(DebugMaps, ContinuousFollowsViridisOverTheRangeAndClamps) {
  const std::vector<float> values = {2.0f, 4.0f, 6.0f, -10.0f, 100.0f, -kInf, kInf};
  const Image image = drawMapWithLegend(values, 7, 1, "test", continuousLegend(2.0f, 6.0f));
  expectColorNear(image.at(0, 0), viridisLinear(0.0f), "minimum");
  expectColorNear(image.at(1, 0), viridisLinear(0.5f), "middle");
  expectColorNear(image.at(2, 0), viridisLinear(1.0f), "maximum");
  expectColorNear(image.at(3, 0), viridisLinear(0.0f), "below the range");
  expectColorNear(image.at(4, 0), viridisLinear(1.0f), "above the range");
  expectColorNear(image.at(5, 0), viridisLinear(0.0f), "-inf");
  expectColorNear(image.at(6, 0), viridisLinear(1.0f), "+inf");
  // The colours are linear: viridis' dark end is far below its sRGB code value once decoded.
  EXPECT_LT(image.at(0, 0).x, colormapViridis(0.0f).x);
}

TEST(DebugMaps, ContinuousNaNIsMagenta) {
  const std::vector<float> values = {kNaN, 0.5f};
  const Image image = drawMapWithLegend(values, 2, 1, "test", continuousLegend(0.0f, 1.0f));
  EXPECT_EQ(image.at(0, 0), vec3(1.0f, 0.0f, 1.0f));
  expectColorNear(image.at(1, 0), viridisLinear(0.5f), "finite neighbour");
}

TEST(DebugMaps, ContinuousEmptyRangeDoesNotDivideByZero) {
  const std::vector<float> values = {1.0f, 0.0f, 2.0f};
  const Image image = drawMapWithLegend(values, 3, 1, "test", continuousLegend(1.0f, 1.0f));
  for (const vec3& p : image.pixels) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
  expectColorNear(image.at(1, 0), viridisLinear(0.0f), "below");
  expectColorNear(image.at(2, 0), viridisLinear(1.0f), "above");
}

TEST(DebugMaps, ContinuousLegendShowsTheWholeColourBar) {
  const std::vector<float> values(20 * 10, 0.5f);
  const Image image = drawMapWithLegend(values, 20, 10, "test", continuousLegend(0.0f, 1.0f));
  // The bar's ends are drawn with the exact extreme colours; the map itself has neither.
  EXPECT_TRUE(stripContains(image, 10, viridisLinear(0.0f)));
  EXPECT_TRUE(stripContains(image, 10, viridisLinear(1.0f)));
}

TEST(DebugMaps, ContinuousTickLabelsFollowTheRange) {
  const std::vector<float> values(10, 0.0f);
  const Image a = drawMapWithLegend(values, 10, 1, "test", continuousLegend(0.0f, 1.0f));
  const Image b = drawMapWithLegend(values, 10, 1, "test", continuousLegend(0.0f, 1200.0f));
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_NE(a.pixels, b.pixels);
}

TEST(DebugMaps, CategoricalColoursAndNone) {
  const std::vector<float> values = {0.0f, 1.0f, 2.0f, -1.0f, kNaN, 2.0f};
  const Image image =
      drawMapWithLegend(values, 6, 1, "classes", categoricalLegend({"a", "b", "c"}));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(image.at(i, 0), categoryColor(i, 3)) << "category " << i;
  EXPECT_EQ(image.at(5, 0), categoryColor(2, 3));
  const vec3 none = image.at(3, 0);
  EXPECT_EQ(image.at(4, 0), none) << "NaN and negative are both 'none'";
  EXPECT_EQ(none.x, none.y);
  EXPECT_EQ(none.y, none.z);
  EXPECT_GT(none.x, 0.0f);
  EXPECT_LT(none.x, 0.2f);
  for (int i = 0; i < 3; ++i) EXPECT_NE(none, categoryColor(i, 3));
}

TEST(DebugMaps, CategoricalNoneSwatchOnlyWhenNeeded) {
  const MapLegend legend = categoricalLegend({"a", "b"});
  const std::vector<float> withNone = {0.0f, -1.0f};
  const Image a = drawMapWithLegend(withNone, 2, 1, "classes", legend);
  const vec3 none = a.at(1, 0);
  EXPECT_TRUE(stripContains(a, 1, none));
  const std::vector<float> withoutNone = {0.0f, 1.0f};
  const Image b = drawMapWithLegend(withoutNone, 2, 1, "classes", legend);
  EXPECT_FALSE(stripContains(b, 1, none));
  // Every labelled category has a swatch, present in the map or not.
  EXPECT_TRUE(stripContains(b, 1, categoryColor(0, 2)));
  EXPECT_TRUE(stripContains(b, 1, categoryColor(1, 2)));
}

TEST(DebugMaps, CategoricalSwatchesWrapIntoMoreRows) {
  std::vector<std::string> labels;
  for (int i = 0; i < 12; ++i) labels.push_back("category " + std::to_string(i));
  const std::vector<float> values(30 * 5, 0.0f);
  const Image image = drawMapWithLegend(values, 30, 5, "classes", categoricalLegend(labels));
  EXPECT_EQ(image.width, 200);
  EXPECT_GT(image.height, 5 + kStripHeight);
  // Wrapping, not clipping: every swatch made it into the picture.
  for (int i = 0; i < 12; ++i)
    EXPECT_TRUE(stripContains(image, 5, categoryColor(i, 12))) << "category " << i;
}

TEST(DebugMaps, UnlabelledCategoriesStillGetColoursAndSwatches) {
  const std::vector<float> values = {0.0f, 4.0f};
  const Image image = drawMapWithLegend(values, 2, 1, "classes", categoricalLegend({"a"}));
  EXPECT_EQ(image.at(1, 0), categoryColor(4, 5));
  EXPECT_TRUE(stripContains(image, 1, categoryColor(4, 5)));
}

TEST(DebugMaps, CategoryColoursAreDistinctAndInRange) {
  std::vector<vec3> colors;
  for (int i = 0; i < 30; ++i) {
    const vec3 c = categoryColor(i, 30);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(c[k], 0.0f);
      EXPECT_LE(c[k], 1.0f);
    }
    for (size_t j = 0; j < colors.size(); ++j)
      EXPECT_GT(glm::length(c - colors[j]), 0.02f) << "categories " << i << " and " << j;
    colors.push_back(c);
  }
  EXPECT_EQ(categoryColor(3, 5), categoryColor(3, 12)) << "colours do not depend on the count";
}

TEST(DebugMaps, OutputSizeAndPadding) {
  const std::vector<float> wide(300 * 10, 0.25f);
  const Image a = drawMapWithLegend(wide, 300, 10, "test", continuousLegend(0.0f, 1.0f));
  EXPECT_EQ(a.width, 300);
  EXPECT_EQ(a.height, 10 + kStripHeight);

  const std::vector<float> narrow(50 * 20, 0.25f);
  const Image b = drawMapWithLegend(narrow, 50, 20, "test", continuousLegend(0.0f, 1.0f));
  EXPECT_EQ(b.width, 200);
  EXPECT_EQ(b.height, 20 + kStripHeight);
  expectColorNear(b.at(49, 19), viridisLinear(0.25f), "map corner");
  const vec3 pad = b.at(50, 0);
  EXPECT_EQ(pad.x, pad.y);
  EXPECT_EQ(pad.y, pad.z);
  EXPECT_LT(pad.x, 0.1f) << "padding is dark grey";
  for (int y = 0; y < 20; ++y)
    for (int x = 50; x < 200; ++x) ASSERT_EQ(b.at(x, y), pad) << x << "," << y;

  const Image c = drawMapWithLegend({}, 0, 0, "classes", categoricalLegend({"a"}));
  EXPECT_EQ(c.width, 200);
  EXPECT_EQ(c.height, kStripHeight);
}

TEST(DebugMaps, DivergingGoesFromBlueThroughGreyToRed) {
  const std::vector<float> values = {-1.0f, 0.0f, 1.0f, 5.0f, kNaN};
  const Image image = drawMapWithLegend(values, 5, 1, "signed", MapLegend::diverging(-1.0f, 1.0f));
  const auto linear = [](vec3 srgb) {
    return vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
  };
  expectColorNear(image.at(0, 0), linear(colormapDiverging(0.0f)), "low end");
  expectColorNear(image.at(1, 0), linear(colormapDiverging(0.5f)), "middle");
  expectColorNear(image.at(2, 0), linear(colormapDiverging(1.0f)), "high end");
  EXPECT_EQ(image.at(3, 0), image.at(2, 0)) << "clamped above the range";
  EXPECT_EQ(image.at(4, 0), vec3(1.0f, 0.0f, 1.0f)) << "NaN is magenta";
  EXPECT_GT(colormapDiverging(0.0f).z, colormapDiverging(0.0f).x) << "blue below the middle";
  EXPECT_GT(colormapDiverging(1.0f).x, colormapDiverging(1.0f).z) << "red above it";
  const vec3 middle = colormapDiverging(0.5f);
  EXPECT_EQ(middle.x, middle.y);
  EXPECT_EQ(middle.y, middle.z);
}

TEST(DebugMaps, RgbMapsShowTheirValues) {
  const std::vector<float> values = {0.25f, 0.5f, 1.0f, 0.0f, 0.1f, 0.0f};
  const Image colors = mapColors(values, 2, 1, MapLegend::rgb());
  EXPECT_EQ(colors.at(0, 0), vec3(0.25f, 0.5f, 1.0f));
  EXPECT_EQ(colors.at(1, 0), vec3(0.0f, 0.1f, 0.0f));
  EXPECT_THROW(mapColors(std::vector<float>(2, 0.0f), 2, 1, MapLegend::rgb()),
               std::invalid_argument);  // three values per pixel
  const Image picture = drawMapWithLegend(values, 2, 1, "I'", MapLegend::rgb());
  EXPECT_EQ(picture.height, 1 + kStripHeight);  // the strip holds the title alone
}

TEST(DebugMaps, SizeMismatchThrows) {
  const std::vector<float> values(11, 0.0f);
  EXPECT_THROW(drawMapWithLegend(values, 4, 3, "test", continuousLegend(0.0f, 1.0f)),
               std::invalid_argument);
  EXPECT_THROW(drawMapWithLegend(values, -1, -11, "test", continuousLegend(0.0f, 1.0f)),
               std::invalid_argument);
  const std::string dir = test::outputPath("debug_maps/mismatch");
  fs::remove_all(dir);
  EXPECT_THROW(writeDebugMap(dir, "m", values, 4, 3, "test", continuousLegend(0.0f, 1.0f)),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir)) << "nothing is created for a bad call";
}

TEST(DebugMapsText, DrawsSomethingForALetterAndNothingForASpace) {
  const Image letter = textImage("A");
  EXPECT_GT(litPixels(letter), 8);
  Image blank(20, 12);
  EXPECT_EQ(drawText(blank, 1, 1, " ", vec3(1.0f)), 5);
  EXPECT_EQ(litPixels(blank), 0);
  // A glyph stays inside its 5x9 box (7 rows plus the descender rows).
  for (int y = 0; y < letter.height; ++y)
    for (int x = 0; x < letter.width; ++x)
      if (letter.at(x, y) != vec3(0.0f)) {
        EXPECT_GE(x, 1);
        EXPECT_LT(x, 6);
        EXPECT_GE(y, 1);
        EXPECT_LT(y, 10);
      }
}

TEST(DebugMapsText, ReturnsTheLayoutWidthAndScales) {
  Image image(100, 40);
  EXPECT_EQ(drawText(image, 0, 0, "AB", vec3(1.0f)), 11);
  EXPECT_EQ(drawText(image, 0, 0, "AB", vec3(1.0f), 2), 22);
  EXPECT_EQ(drawText(image, 0, 0, "", vec3(1.0f)), 0);
  EXPECT_EQ(litPixels(textImage("A", 2)), 4 * litPixels(textImage("A", 1)));
  Image untouched(10, 10);
  EXPECT_EQ(drawText(untouched, 0, 0, "A", vec3(1.0f), 0), 0);
  EXPECT_EQ(litPixels(untouched), 0);
}

TEST(DebugMapsText, DifferentTextGivesDifferentPixels) {
  EXPECT_NE(textImage("abc").pixels, textImage("abd").pixels);
  EXPECT_NE(textImage("0.05").pixels, textImage("0.5").pixels);
  EXPECT_EQ(textImage("x").pixels, textImage("x").pixels);
  Image red(64, 12), green(64, 12);
  drawText(red, 0, 0, "A", vec3(1.0f, 0.0f, 0.0f));
  drawText(green, 0, 0, "A", vec3(0.0f, 1.0f, 0.0f));
  EXPECT_NE(red.pixels, green.pixels);
}

TEST(DebugMapsText, DigitGlyphsAreDistinct) {
  for (char a = '0'; a <= '9'; ++a)
    for (char b = char(a + 1); b <= '9'; ++b)
      EXPECT_NE(textImage(std::string(1, a)).pixels, textImage(std::string(1, b)).pixels)
          << a << " vs " << b;
}

TEST(DebugMapsText, EveryPrintableGlyphIsDrawnAndUnique) {
  std::vector<LargeVector<vec3>> seen;
  for (char c = '!'; c <= '~'; ++c) {
    const Image glyph = textImage(std::string(1, c));
    EXPECT_GT(litPixels(glyph), 0) << "'" << c << "'";
    for (size_t j = 0; j < seen.size(); ++j)
      EXPECT_NE(glyph.pixels, seen[j]) << "'" << c << "' vs '" << char('!' + j) << "'";
    seen.push_back(glyph.pixels);
  }
  // Characters outside the table (control codes, UTF-8 bytes) are drawn as '?'.
  EXPECT_EQ(textImage("\x01").pixels, textImage("?").pixels);
  EXPECT_EQ(textImage("\xc3").pixels, textImage("?").pixels);
}

TEST(DebugMapsText, ClipsAtTheImageBorder) {
  Image image(16, 10);
  drawText(image, -3, -4, "Hello", vec3(1.0f));
  EXPECT_GT(litPixels(image), 0) << "the visible part is still drawn";
  drawText(image, 13, 7, "Wg", vec3(1.0f), 3);
  drawText(image, -1000, 0, std::string(200, 'M'), vec3(1.0f), 2);
  drawText(image, 1000, 1000, "far away", vec3(1.0f));
  drawText(image, 0, -1000, "above", vec3(1.0f));
  drawText(image, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(), "edge",
           vec3(1.0f), 1000);

  Image empty;
  EXPECT_EQ(drawText(empty, 0, 0, "A", vec3(1.0f)), 5);
  Image outside(8, 8);
  drawText(outside, 8, 0, "A", vec3(1.0f));
  drawText(outside, -5, 0, "A", vec3(1.0f));
  drawText(outside, 0, -9, "g", vec3(1.0f));
  EXPECT_EQ(litPixels(outside), 0);
}

TEST(DebugMapsFiles, WritesExrAndPngIntoANewNestedDirectory) {
  const std::string root = test::outputPath("debug_maps/write");
  fs::remove_all(root);
  const std::string dir = root + "/nested/deeper";
  const std::vector<float> values = {0.0f, 0.25f, -3.0f, 1e6f, kNaN, 0.5f};
  const MapLegend legend = continuousLegend(0.0f, 1.0f);
  writeDebugMap(dir, "depth", values, 3, 2, "test", legend);

  ASSERT_TRUE(fs::is_regular_file(dir + "/depth.exr"));
  ASSERT_TRUE(fs::is_regular_file(dir + "/depth.png"));
  const Image raw = readImage(dir + "/depth.exr");
  ASSERT_EQ(raw.width, 3);
  ASSERT_EQ(raw.height, 2);
  for (size_t i = 0; i < values.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      if (std::isnan(values[i]))
        EXPECT_TRUE(std::isnan(raw.pixels[i][k])) << i;
      else
        EXPECT_EQ(raw.pixels[i][k], values[i]) << i;
    }

  const Image expected = drawMapWithLegend(values, 3, 2, "test", legend);
  const Image picture = readImage(dir + "/depth.png");
  ASSERT_EQ(picture.width, expected.width);
  ASSERT_EQ(picture.height, expected.height);
  for (size_t i = 0; i < expected.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(linearToSrgb(picture.pixels[i][k]), linearToSrgb(expected.pixels[i][k]),
                  0.6f / 255.0f)
          << "pixel " << i;

  // Writing again into the now existing directory replaces the files.
  writeDebugMap(dir, "depth", values, 3, 2, "classes", categoricalLegend({"x"}));
  EXPECT_EQ(readImage(dir + "/depth.png").width, 200);
}

// An Rgb map is its own picture: the EXR holds its colours, the PNG shows them without a strip.
TEST(DebugMapsFiles, RgbMapIsWrittenAsItsColours) {
  const std::string dir = test::outputPath("debug_maps/rgb");
  fs::remove_all(dir);
  const std::vector<float> values = {0.25f, 0.5f, 1.0f, 0.0f, 0.125f, 0.0f};
  writeDebugMap(dir, "prediction", values, 2, 1, "I'", MapLegend::rgb());
  const Image raw = readImage(dir + "/prediction.exr");
  ASSERT_EQ(raw.width, 2);
  ASSERT_EQ(raw.height, 1);
  EXPECT_EQ(raw.at(0, 0), vec3(0.25f, 0.5f, 1.0f));
  EXPECT_EQ(raw.at(1, 0), vec3(0.0f, 0.125f, 0.0f));
  const Image picture = readImage(dir + "/prediction.png");
  EXPECT_EQ(picture.width, 2);
  EXPECT_EQ(picture.height, 1);
}

TEST(DebugMapsFiles, UncreatableDirectoryNamesIt) {
  const std::string blocker = test::outputPath("debug_maps/blocker");
  fs::create_directories(fs::path(blocker).parent_path());
  std::ofstream(blocker) << "a file, not a directory";
  const std::string dir = blocker + "/sub";
  try {
    writeDebugMap(dir, "m", std::vector<float>{1.0f}, 1, 1, "test", continuousLegend(0.0f, 1.0f));
    FAIL() << "expected ImageIoError";
  } catch (const ImageIoError& error) {
    EXPECT_NE(std::string(error.what()).find(dir), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace penumbra
