// Debug maps as pictures: per-pixel values in false colour (viridis, or a qualitative palette
// for categories) above a legend strip drawn with a built-in 5x7 bitmap font, plus the
// EXR (raw values) + PNG (picture) pair that writeDebugMap leaves on disk.
#include "present/debug_maps.h"

#include "core/image_io.h"
#include "eval/metrics.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// ---- Font ---------------------------------------------------------------------------------
// One glyph per printable ASCII character ' '..'~': 7 rows of 5 bits, bit 4 the leftmost
// column. A glyph sits in a 6x9 cell, so strings need no explicit spacing: the sixth column
// separates letters and the two rows under the baseline take the tails of g, p, q and y, which
// are drawn shifted down by two rows (their table entries start at the x-height).
constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 7;
constexpr int kCellWidth = 6;
constexpr int kDescenderShift = 2;
constexpr char kFirstGlyph = ' ';
constexpr char kLastGlyph = '~';

constexpr std::array<std::array<uint8_t, kGlyphHeight>, kLastGlyph - kFirstGlyph + 1> kFont = {{
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00},  // space
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04},  // !
    {0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00},  // "
    {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A},  // #
    {0x04, 0x0F, 0x14, 0x0E, 0x05, 0x1E, 0x04},  // $
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03},  // %
    {0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D},  // &
    {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00},  // '
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02},  // (
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08},  // )
    {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00},  // *
    {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00},  // +
    {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08},  // ,
    {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00},  // -
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C},  // .
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00},  // /
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E},  // 0
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E},  // 1
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F},  // 2
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E},  // 3
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02},  // 4
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E},  // 5
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E},  // 6
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08},  // 7
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E},  // 8
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C},  // 9
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00},  // :
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x04, 0x08},  // ;
    {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02},  // <
    {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00},  // =
    {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08},  // >
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04},  // ?
    {0x0E, 0x11, 0x01, 0x0D, 0x15, 0x15, 0x0E},  // @
    {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11},  // A
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E},  // B
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E},  // C
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C},  // D
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F},  // E
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10},  // F
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F},  // G
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11},  // H
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E},  // I
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C},  // J
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11},  // K
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F},  // L
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11},  // M
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11},  // N
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E},  // O
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10},  // P
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D},  // Q
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11},  // R
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E},  // S
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04},  // T
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E},  // U
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04},  // V
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A},  // W
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11},  // X
    {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04},  // Y
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F},  // Z
    {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E},  // [
    {0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00},  // backslash
    {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E},  // ]
    {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00},  // ^
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F},  // _
    {0x08, 0x04, 0x02, 0x00, 0x00, 0x00, 0x00},  // `
    {0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F},  // a
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E},  // b
    {0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E},  // c
    {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F},  // d
    {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E},  // e
    {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08},  // f
    {0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E},  // g
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11},  // h
    {0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E},  // i
    {0x02, 0x00, 0x06, 0x02, 0x02, 0x12, 0x0C},  // j
    {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12},  // k
    {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E},  // l
    {0x00, 0x00, 0x1A, 0x15, 0x15, 0x15, 0x15},  // m
    {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11},  // n
    {0x00, 0x00, 0x0E, 0x11, 0x11, 0x11, 0x0E},  // o
    {0x1E, 0x11, 0x11, 0x11, 0x1E, 0x10, 0x10},  // p
    {0x0F, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x01},  // q
    {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10},  // r
    {0x00, 0x00, 0x0F, 0x10, 0x0E, 0x01, 0x1E},  // s
    {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06},  // t
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D},  // u
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04},  // v
    {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0A},  // w
    {0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11},  // x
    {0x11, 0x11, 0x11, 0x11, 0x0F, 0x01, 0x0E},  // y
    {0x00, 0x00, 0x1F, 0x02, 0x04, 0x08, 0x1F},  // z
    {0x03, 0x04, 0x04, 0x08, 0x04, 0x04, 0x03},  // {
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04},  // |
    {0x18, 0x04, 0x04, 0x02, 0x04, 0x04, 0x18},  // }
    {0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00},  // ~
}};

bool descends(char c) { return c == 'g' || c == 'p' || c == 'q' || c == 'y'; }

// Layout width of `count` characters: whole cells, less the spacing column after the last one.
int64_t textWidth(size_t count, int scale) {
  return count == 0 ? 0 : (int64_t(count) * kCellWidth - 1) * scale;
}

int textWidth(const std::string& text, int scale) {
  return int(std::min<int64_t>(textWidth(text.size(), scale), INT_MAX));
}

// ---- Colours ------------------------------------------------------------------------------
// Chosen in sRGB (what a viewer shows) and stored linear, since writeImage encodes to sRGB.
vec3 fromSrgb8(int r, int g, int b) {
  return vec3(srgbToLinear(r / 255.0f), srgbToLinear(g / 255.0f), srgbToLinear(b / 255.0f));
}

vec3 backgroundColor() { return fromSrgb8(36, 36, 36); }  // strip and padding
// Lighter than the background so "none" pixels read as data, not as padding.
vec3 noneColor() { return fromSrgb8(84, 84, 84); }
vec3 textColor() { return fromSrgb8(235, 235, 235); }
vec3 outlineColor() { return fromSrgb8(150, 150, 150); }  // keeps dark swatches visible
// Magenta, as falseColor uses: no viridis colour is near it.
const vec3 kNaNColor(1.0f, 0.0f, 1.0f);

vec3 viridisLinear(float t) {
  const vec3 srgb = colormapViridis(t);
  return vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
}

// ---- Drawing helpers ----------------------------------------------------------------------
// 64-bit coordinates so that clipping far-off text or huge scales cannot overflow.
void fillRect(Image& image, int64_t x, int64_t y, int64_t w, int64_t h, vec3 color) {
  const int64_t x0 = std::max<int64_t>(x, 0), x1 = std::min<int64_t>(x + w, image.width);
  const int64_t y0 = std::max<int64_t>(y, 0), y1 = std::min<int64_t>(y + h, image.height);
  for (int64_t py = y0; py < y1; ++py)
    for (int64_t px = x0; px < x1; ++px) image.at(int(px), int(py)) = color;
}

// %.3g keeps labels short ("0", "0.05", "1.2e+03"); adding 0.0 turns -0 into 0.
std::string formatValue(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", v + 0.0);
  return buffer;
}

// `text` cut down (ending in "..") to at most maxWidth pixels; empty if not even that fits.
std::string fitText(const std::string& text, int maxWidth, int scale) {
  if (maxWidth < 0) return std::string();
  // n characters take (6n - 1) * scale pixels.
  const size_t fits = size_t((int64_t(maxWidth) / scale + 1) / kCellWidth);
  if (text.size() <= fits) return text;
  return fits >= 3 ? text.substr(0, fits - 2) + ".." : std::string();
}

// ---- Legend layout (in units of the legend scale) -----------------------------------------
constexpr int kMinStripWidth = 200;
constexpr int kStripHeight = 34;
constexpr int kPad = 4;        // strip border
constexpr int kTitleGap = 10;  // title to bar / swatches
// Continuous: colour bar, tick marks under it, labels under the ticks.
constexpr int kBarTop = 7;
constexpr int kBarHeight = 9;
constexpr int kTickLength = 2;
constexpr int kTickLabelTop = kBarTop + kBarHeight + kTickLength + 1;
constexpr int kTitleTop = kBarTop + 1;  // centred on the bar
constexpr int kMinBarLength = 80;
// Categorical: rows of [swatch label] items.
constexpr int kSwatchSize = 7;  // as tall as a capital letter; outlined one pixel outside
constexpr int kSwatchToLabel = 4;
constexpr int kItemGap = 10;
constexpr int kRowPitch = 12;
constexpr int kMinItemArea = 60;

// Big renders get bigger text, so the legend stays legible when a viewer fits the image to
// the window; up to 639 pixels wide everything is drawn at the nominal size.
int legendScale(int stripWidth) { return std::clamp(stripWidth / 640, 1, 4); }

int clampToInt(int64_t v) { return int(std::clamp<int64_t>(v, INT_MIN, INT_MAX)); }

vec3 divergingLinear(float t) {
  const vec3 srgb = colormapDiverging(t);
  return vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
}

// The colour of t in [0, 1] on a Sequential or Diverging map's bar.
vec3 rampColor(ColorMapKind kind, float t) {
  return kind == ColorMapKind::Diverging ? divergingLinear(t) : viridisLinear(t);
}

// The strip of a map without a scale (Rgb): its title alone.
void drawTitleStrip(Image& image, int top, int scale, const std::string& fullTitle) {
  const int s = scale;
  const std::string title = fitText(fullTitle, image.width - 2 * kPad * s, s);
  if (!title.empty())
    drawText(image, kPad * s, top + (kStripHeight - kGlyphHeight) / 2 * s, title, textColor(), s);
}

void drawContinuousStrip(Image& image, int top, int scale, const std::string& fullTitle,
                         const MapLegend& legend) {
  const int s = scale, width = image.width;
  const std::string low = formatValue(legend.minValue);
  const std::string middle = formatValue((double(legend.minValue) + legend.maxValue) / 2.0);
  const std::string high = formatValue(legend.maxValue);
  const int lowWidth = textWidth(low, s), middleWidth = textWidth(middle, s);
  const int highWidth = textWidth(high, s);
  // Long enough that the centred middle label cannot touch the end labels, which are aligned
  // to the bar's ends; the title gives way (is shortened) before the bar does.
  const int minBar =
      std::max(kMinBarLength * s, 2 * std::max(lowWidth, highWidth) + middleWidth + 8 * s);
  const std::string title = fitText(fullTitle, width - 2 * kPad * s - kTitleGap * s - minBar, s);
  if (!title.empty()) drawText(image, kPad * s, top + kTitleTop * s, title, textColor(), s);

  const int barStart = kPad * s + (title.empty() ? 0 : textWidth(title, s) + kTitleGap * s);
  const int barEnd = width - kPad * s - 1;  // inclusive, so both ends show the exact extremes
  const int barLength = std::max(barEnd - barStart, 1);
  for (int x = barStart; x <= barEnd; ++x)
    fillRect(image, x, top + kBarTop * s, 1, kBarHeight * s,
             rampColor(legend.kind, float(x - barStart) / float(barLength)));

  const int barMiddle = barStart + barLength / 2;
  const int tickTop = top + (kBarTop + kBarHeight) * s;
  fillRect(image, barStart, tickTop, s, kTickLength * s, textColor());
  fillRect(image, barMiddle - s / 2, tickTop, s, kTickLength * s, textColor());
  fillRect(image, barEnd - s + 1, tickTop, s, kTickLength * s, textColor());
  const int labelTop = top + kTickLabelTop * s;
  drawText(image, barStart, labelTop, low, textColor(), s);
  drawText(image, barMiddle - middleWidth / 2, labelTop, middle, textColor(), s);
  drawText(image, barEnd + 1 - highWidth, labelTop, high, textColor(), s);
}

struct LegendItem {
  bool hasSwatch = true;  // false for the "+N more" note
  vec3 color{0.0f};
  std::string label;
  int width(int s) const {
    return (hasSwatch ? (kSwatchSize + kSwatchToLabel) * s : 0) + textWidth(label, s);
  }
};

struct ItemLayout {
  std::string title;
  int areaStart = 0;
  std::vector<std::pair<int, int>> positions;  // (x, row) per item
  int rows = 0;
};

// Flows the items left to right after the title, starting a new row when one would cross the
// strip's right edge (an item wider than the whole area gets a row to itself and is clipped).
ItemLayout layoutItems(const std::vector<LegendItem>& items, const std::string& fullTitle,
                       int width, int s) {
  int widest = 0;
  for (const LegendItem& item : items) widest = std::max(widest, item.width(s));
  const int usable = width - 2 * kPad * s;
  const int minArea = std::clamp(widest, kMinItemArea * s, std::max(usable / 2, 1));
  ItemLayout layout;
  layout.title = fitText(fullTitle, usable - kTitleGap * s - minArea, s);
  layout.areaStart =
      kPad * s + (layout.title.empty() ? 0 : textWidth(layout.title, s) + kTitleGap * s);
  const int areaEnd = width - kPad * s;
  int x = layout.areaStart, row = 0;
  for (const LegendItem& item : items) {
    const int w = item.width(s);
    if (x > layout.areaStart && x + w > areaEnd) {
      ++row;
      x = layout.areaStart;
    }
    layout.positions.emplace_back(x, row);
    x += w + kItemGap * s;
  }
  layout.rows = items.empty() ? 0 : row + 1;
  return layout;
}

// Height of a categorical strip with `rows` rows of items (unscaled).
int categoricalStripHeight(int rows) { return std::max(kStripHeight, rows * kRowPitch + 10); }

void drawCategoricalStrip(Image& image, int top, int scale, const std::vector<LegendItem>& items,
                          const ItemLayout& layout) {
  const int s = scale;
  const int stripHeight = categoricalStripHeight(layout.rows);
  const int contentHeight = std::max(layout.rows * kRowPitch - (kRowPitch - kSwatchSize), 0);
  const int firstRowTop = top + (stripHeight - contentHeight) / 2 * s;
  // The title lines up with the first row of items.
  const int titleTop = layout.rows > 0 ? firstRowTop : top + (kStripHeight - kGlyphHeight) / 2 * s;
  if (!layout.title.empty()) drawText(image, kPad * s, titleTop, layout.title, textColor(), s);
  for (size_t i = 0; i < items.size(); ++i) {
    const auto [x, row] = layout.positions[i];
    const int y = firstRowTop + row * kRowPitch * s;
    int labelX = x;
    if (items[i].hasSwatch) {
      fillRect(image, x - 1, y - 1, kSwatchSize * s + 2, kSwatchSize * s + 2, outlineColor());
      fillRect(image, x, y, kSwatchSize * s, kSwatchSize * s, items[i].color);
      labelX += (kSwatchSize + kSwatchToLabel) * s;
    }
    drawText(image, labelX, y, items[i].label, textColor(), s);
  }
}

// Unlabelled category indices found in the map get their own swatches, up to this many; the
// rest are still coloured but only counted in the legend.
constexpr size_t kMaxUnlabelledSwatches = 16;

// The category index a value stands for, or -1 for "none": negative, NaN, or too large to be
// an index (including +inf). Values are rounded, so 2.9999 from a filter still means 3.
int categoryOf(float v) {
  if (!(v >= 0.0f) || v >= float(INT_MAX / 2)) return -1;
  return int(std::floor(v + 0.5f));
}

}  // namespace

vec3 categoryColor(int index, int count) {
  // A hand-picked qualitative palette: ten hues that are told apart easily on a dark strip
  // and from the grey of "none". Beyond ten, the hues repeat in lighter and darker
  // versions so neighbouring indices stay distinct. `count` does not change the colours, so a
  // category keeps its colour when more categories are added.
  (void)count;
  static constexpr std::array<std::array<int, 3>, 10> kPalette = {{
      {66, 133, 230},   // blue
      {245, 145, 30},   // orange
      {70, 180, 70},    // green
      {225, 55, 55},    // red
      {160, 110, 215},  // violet
      {160, 100, 60},   // brown
      {240, 125, 195},  // pink
      {205, 200, 45},   // olive yellow
      {45, 200, 210},   // cyan
      {150, 230, 120},  // pale green
  }};
  if (index < 0) return noneColor();
  const auto& base = kPalette[size_t(index) % kPalette.size()];
  // Lightness variants per cycle through the palette: as is, towards white, darker, paler.
  static constexpr std::array<float, 4> kMix = {0.0f, 0.45f, -0.4f, 0.7f};
  const float mix = kMix[(size_t(index) / kPalette.size()) % kMix.size()];
  vec3 srgb;
  for (int k = 0; k < 3; ++k) {
    const float c = float(base[k]) / 255.0f;
    srgb[k] = mix >= 0.0f ? c + (1.0f - c) * mix : c * (1.0f + mix);
  }
  return vec3(srgbToLinear(srgb.x), srgbToLinear(srgb.y), srgbToLinear(srgb.z));
}

int drawText(Image& image, int x, int y, const std::string& text, vec3 color, int scale) {
  if (scale < 1) return 0;
  const int64_t s = scale;
  for (size_t i = 0; i < text.size(); ++i) {
    const int64_t left = x + int64_t(i) * kCellWidth * s;
    if (left >= image.width) break;  // the rest of the string is clipped as well
    if (left + kGlyphWidth * s <= 0) continue;
    char c = text[i];
    if (c < kFirstGlyph || c > kLastGlyph) c = '?';  // control characters, UTF-8 bytes
    const auto& glyph = kFont[size_t(c - kFirstGlyph)];
    const int64_t glyphTop = y + (descends(c) ? kDescenderShift * s : 0);
    for (int row = 0; row < kGlyphHeight; ++row)
      for (int column = 0; column < kGlyphWidth; ++column)
        if ((glyph[row] >> (kGlyphWidth - 1 - column)) & 1)
          fillRect(image, left + column * s, glyphTop + row * s, s, s, color);
  }
  // The layout width, whether or not clipping hid some of it, so callers can place what follows.
  return clampToInt(textWidth(text.size(), scale));
}

namespace {

size_t channelsOf(const MapLegend& legend) { return legend.kind == ColorMapKind::Rgb ? 3 : 1; }

void requireMapSize(std::span<const float> values, int width, int height, const MapLegend& legend,
                    const std::string& title) {
  if (width < 0 || height < 0 ||
      values.size() != size_t(width) * size_t(height) * channelsOf(legend))
    throw std::invalid_argument("debug map '" + title + "': " + std::to_string(values.size()) +
                                " values for a " + std::to_string(width) + "x" +
                                std::to_string(height) + " map");
}

// Per-pixel colours and the legend items (categorical maps) of a map.
std::vector<vec3> colorsAndItems(std::span<const float> values, const MapLegend& legend,
                                 std::vector<LegendItem>* items) {
  if (legend.kind == ColorMapKind::Rgb) {
    std::vector<vec3> colors(values.size() / 3);
    for (size_t i = 0; i < colors.size(); ++i)
      colors[i] = vec3(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
    return colors;
  }
  std::vector<vec3> colors(values.size());
  if (legend.kind != ColorMapKind::Categorical) {
    const float span = legend.maxValue - legend.minValue;
    for (size_t i = 0; i < values.size(); ++i) {
      const float v = values[i];
      if (std::isnan(v)) {
        colors[i] = kNaNColor;
        continue;
      }
      // colormapViridis clamps t to [0,1]; a zero span would divide 0 by 0.
      const float t = span != 0.0f ? (v - legend.minValue) / span : (v > legend.minValue ? 1 : 0);
      colors[i] = rampColor(legend.kind, t);
    }
    return colors;
  }
  const int labelled = int(std::min<size_t>(legend.categories.size(), INT_MAX));
  bool anyNone = false;
  std::set<int> unlabelled;
  for (size_t i = 0; i < values.size(); ++i) {
    const int category = categoryOf(values[i]);
    if (category < 0) {
      anyNone = true;
      colors[i] = noneColor();
      continue;
    }
    colors[i] = categoryColor(category, std::max(labelled, category + 1));
    if (category >= labelled) unlabelled.insert(category);
  }
  if (!items) return colors;
  const int count = std::max(labelled, unlabelled.empty() ? 0 : *unlabelled.rbegin() + 1);
  for (int i = 0; i < labelled; ++i)
    items->push_back({true, categoryColor(i, count), legend.categories[size_t(i)]});
  size_t shown = 0;
  for (int category : unlabelled) {
    if (shown++ == kMaxUnlabelledSwatches) break;
    items->push_back({true, categoryColor(category, count), std::to_string(category)});
  }
  if (unlabelled.size() > kMaxUnlabelledSwatches) {
    char more[40];
    std::snprintf(more, sizeof more, "+%zu more", unlabelled.size() - kMaxUnlabelledSwatches);
    items->push_back({false, vec3(0.0f), more});
  }
  if (anyNone) items->push_back({true, noneColor(), "none"});
  return colors;
}

}  // namespace

vec3 colormapDiverging(float t) {
  // Moreland's cool-warm end points around a light grey, interpolated in sRGB.
  static const vec3 kLow(59 / 255.0f, 76 / 255.0f, 192 / 255.0f);
  static const vec3 kMiddle(221 / 255.0f, 221 / 255.0f, 221 / 255.0f);
  static const vec3 kHigh(180 / 255.0f, 4 / 255.0f, 38 / 255.0f);
  const float u = std::clamp(std::isnan(t) ? 0.5f : t, 0.0f, 1.0f);
  return u < 0.5f ? kLow + (kMiddle - kLow) * (2.0f * u)
                  : kMiddle + (kHigh - kMiddle) * (2.0f * u - 1.0f);
}

Image mapColors(std::span<const float> values, int width, int height, const MapLegend& legend) {
  requireMapSize(values, width, height, legend, "");
  Image image(width, height);
  const std::vector<vec3> colors = colorsAndItems(values, legend, nullptr);
  image.pixels.assign(colors.begin(), colors.end());
  return image;
}

Image drawMapWithLegend(std::span<const float> values, int width, int height,
                        const std::string& title, const MapLegend& legend) {
  requireMapSize(values, width, height, legend, title);
  const int stripWidth = std::max(width, kMinStripWidth);
  const int s = legendScale(stripWidth);
  std::vector<LegendItem> items;
  const std::vector<vec3> colors = colorsAndItems(values, legend, &items);

  ItemLayout layout;
  int stripHeight = kStripHeight * s;
  if (legend.kind == ColorMapKind::Categorical) {
    layout = layoutItems(items, title, stripWidth, s);
    stripHeight = categoricalStripHeight(layout.rows) * s;
  }
  Image image(stripWidth, height + stripHeight, backgroundColor());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.at(x, y) = colors[size_t(y) * width + x];
  if (legend.kind == ColorMapKind::Categorical)
    drawCategoricalStrip(image, height, s, items, layout);
  else if (legend.kind == ColorMapKind::Rgb)
    drawTitleStrip(image, height, s, title);
  else
    drawContinuousStrip(image, height, s, title, legend);
  return image;
}

void writeDebugMap(const std::string& dir, const std::string& name, std::span<const float> values,
                   int width, int height, const std::string& title, const MapLegend& legend) {
  // Drawing first validates the size before anything touches the disk. An Rgb map is its
  // own picture.
  const bool rgb = legend.kind == ColorMapKind::Rgb;
  const Image picture = rgb ? mapColors(values, width, height, legend)
                            : drawMapWithLegend(values, width, height, title, legend);
  if (name.empty()) throw ImageIoError(dir + ": empty debug map name");
  if (!dir.empty()) {
    std::error_code error;
    fs::create_directories(dir, error);
    if (error) throw ImageIoError(dir + ": cannot create directory: " + error.message());
  }
  Image raw = rgb ? picture : Image(width, height);
  if (!rgb)
    for (size_t i = 0; i < values.size(); ++i) raw.pixels[i] = vec3(values[i]);
  const std::string base = (fs::path(dir) / name).string();
  writeImage(base + ".exr", raw);
  writeImage(base + ".png", picture);
}

}  // namespace penumbra
