// Debug maps as pictures: a per-pixel map (methods/snapshot.h: values and a MapLegend) drawn
// in false colour with a legend strip (the title, then a colour bar with labelled values or
// labelled swatches) under the image, so a PNG explains itself. Text uses a small built-in
// bitmap font (printable ASCII). An Rgb map's strip holds its title alone.
#pragma once

#include "core/image.h"
#include "methods/snapshot.h"

#include <span>
#include <string>
#include <vector>

namespace penumbra {

// Colour of category i of n (distinct, readable hues; linear RGB).
vec3 categoryColor(int index, int count);

// The map in false colour (linear RGB, so writeImage's sRGB encoding shows the intended
// colours), `width` x `height`, with a legend strip appended below that starts with `title`;
// the strip is at least 200 pixels wide (narrow maps are padded on the right with dark grey).
// With no values and height 0 the result is the legend strip alone, `width` wide.
// Throws std::invalid_argument if values.size() != width * height (Rgb: three times that).
Image drawMapWithLegend(std::span<const float> values, int width, int height,
                        const std::string& title, const MapLegend& legend);

// The map's per-pixel colours alone (linear RGB, as drawMapWithLegend draws them), for a
// viewer that draws the legend elsewhere. Throws std::invalid_argument on a size mismatch.
Image mapColors(std::span<const float> values, int width, int height, const MapLegend& legend);

// The diverging colour map over t in [0, 1] (clamped): blue, light grey at 0.5, red; sRGB.
vec3 colormapDiverging(float t);

// Draws `text` into `image` with the top-left corner at (x, y), clipped to the image, in
// `color`, at integer `scale`. Returns the width in pixels drawn.
int drawText(Image& image, int x, int y, const std::string& text, vec3 color, int scale = 1);

// Writes DIR/NAME.exr (the raw values, a scalar in all three channels; NaN kept) and
// DIR/NAME.png (drawMapWithLegend; an Rgb map: its values as they are).
// Throws ImageIoError naming the file on failure.
void writeDebugMap(const std::string& dir, const std::string& name, std::span<const float> values,
                   int width, int height, const std::string& title, const MapLegend& legend);

}  // namespace penumbra
