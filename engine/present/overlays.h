// What the viewer shows, computed on the CPU so that the window, the headless screenshots
// and the tests agree: the display transform (exposure, sRGB or filmic), the overlays (a
// snapshot's debug maps in false colour, each with its legend) and how an overlay is
// blended over the image. The GL shaders (shaders/composite.frag) implement the same
// formulas; composeFrame is their reference.
#pragma once

#include "methods/factory.h"
#include "methods/snapshot.h"
#include "present/debug_maps.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// ---- Display transform ---------------------------------------------------------------

// The values are the shaders' too (TONE_CURVE_SRGB, TONE_CURVE_FILMIC, defined from these).
enum class ToneCurve : int {
  Srgb = 0,   // clamp to [0, 1], sRGB encode
  Filmic = 1  // a filmic shoulder (Narkowicz's fit of the ACES curve), then sRGB encode
};

struct DisplaySettings {
  float exposure = 0.0f;  // stops
  ToneCurve curve = ToneCurve::Srgb;
};

// Linear radiance to the display-encoded colour in [0, 1] (NaN and inf shown as 0 and 1).
vec3 displayTransform(vec3 linear, const DisplaySettings& settings);
float filmicCurve(float x);

// ---- Overlays ------------------------------------------------------------------------
// An overlay is one of the snapshot's maps (MapId, methods/snapshot.h), or none; the
// reference error is the one map computed here, from the shown image and a reference.

namespace maps {
// The relative squared error of the shown image against a reference.
inline constexpr MapKind ReferenceError{"reference_error", nullptr, "Error vs reference", 7};
}  // namespace maps

// The maps the viewer offers as overlays (the methods' maps with a key, and the reference
// error), in the order of the number keys 1, 2, ...
std::vector<const MapKind*> overlayList(const MethodRegistry& methods = builtinMethods());
// An overlay by its name or alias ("slices", "filter-scale"); "none" gives the empty id.
std::optional<MapId> overlayByName(std::string_view name,
                                   const MethodRegistry& methods = builtinMethods());
// The names --overlay accepts, for messages: "none, bias, selected (or slices), ...".
std::string overlayNames(const MethodRegistry& methods = builtinMethods());

struct OverlayImage {
  MapId overlay;
  std::string label;  // the map's label: the legend's title
  Image colors;       // per pixel, linear RGB; empty when unavailable
  MapLegend legend;   // what the colours mean
  std::vector<float> values;
  std::string unavailable;  // why there is no such map (empty when there is)
  bool available() const { return !colors.empty(); }
};

// The overlay's colours and legend for `snapshot`. `shown` is the image on screen (raw or
// reconstructed), which the reference error compares with `reference` (null: none given).
OverlayImage buildOverlay(const Snapshot& snapshot, MapId overlay, const Image& shown,
                          const Image* reference);

// The overlay blended over a display-encoded image colour: mix in display space with weight
// `blend` in [0, 1], the overlay colour sRGB encoded first.
vec3 composePixel(vec3 display, vec3 overlayLinear, float blend);

// The frame the display shader draws at zoom 1 with no pan: every pixel through
// displayTransform, then the overlay (if any) blended in. Display-encoded, same size as
// `image`. Throws std::invalid_argument when the overlay's size differs.
Image composeFrame(const Image& image, const DisplaySettings& settings, const OverlayImage* overlay,
                   float blend);

}  // namespace penumbra
