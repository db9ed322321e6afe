// What the viewer shows, computed on the CPU so that the window, the headless screenshots
// and the tests agree: the display transform (exposure, sRGB or filmic), the overlays (a
// snapshot's debug maps in false colour, each with its legend) and how an overlay is
// blended over the image. The GL shaders (shaders/composite.frag) implement the same
// formulas; composeFrame is their reference.
#pragma once

#include "methods/progressive.h"
#include "present/debug_maps.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// ---- Display transform ---------------------------------------------------------------

enum class ToneCurve {
  Srgb,   // clamp to [0, 1], sRGB encode
  Filmic  // a filmic shoulder (Narkowicz's fit of the ACES curve), then sRGB encode
};

struct DisplaySettings {
  float exposure = 0.0f;  // stops
  ToneCurve curve = ToneCurve::Srgb;
};

// Linear radiance to the display-encoded colour in [0, 1] (NaN and inf shown as 0 and 1).
vec3 displayTransform(vec3 linear, const DisplaySettings& settings);
float filmicCurve(float x);

// ---- Overlays ------------------------------------------------------------------------

enum class Overlay {
  None,
  Bias,            // the method's error estimate
  Selected,        // pixels (and, zoomed in, slices B and C) sampled in the last round
  FilterScale,     // alpha chosen per pixel
  SampleCount,     // kept samples per pixel
  TracedCount,     // traced camera samples per pixel
  NetworkError,    // er
  ReferenceError,  // relative squared error of the shown image against a reference
};

struct OverlayInfo {
  Overlay overlay;
  const char* name;   // for --overlay and file names
  const char* label;  // for the panel
};
// Every overlay but None, in the order of the number keys 1, 2, ...
std::span<const OverlayInfo> overlayList();
std::optional<Overlay> overlayByName(std::string_view name);
const char* overlayName(Overlay overlay);  // "none" for None

struct OverlayImage {
  Overlay overlay = Overlay::None;
  Image colors;      // per pixel, linear RGB; empty when unavailable
  MapLegend legend;  // what the colours mean
  std::vector<float> values;
  std::string unavailable;  // why there is no such map (empty when there is)
  bool available() const { return !colors.empty(); }
};

// The overlay's colours and legend for `snapshot`. `shown` is the image on screen (raw or
// reconstructed), which the reference error compares with `reference` (null: none given).
// `alphas` labels the filter scales.
OverlayImage buildOverlay(const Snapshot& snapshot, Overlay overlay, const Image& shown,
                          const Image* reference, const std::vector<float>& alphas);

// The overlay blended over a display-encoded image colour: mix in display space with weight
// `blend` in [0, 1], the overlay colour sRGB encoded first.
vec3 composePixel(vec3 display, vec3 overlayLinear, float blend);

// The frame the display shader draws at zoom 1 with no pan: every pixel through
// displayTransform, then the overlay (if any) blended in. Display-encoded, same size as
// `image`. Throws std::invalid_argument when the overlay's size differs.
Image composeFrame(const Image& image, const DisplaySettings& settings, const OverlayImage* overlay,
                   float blend);

}  // namespace penumbra
