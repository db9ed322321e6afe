#include "present/overlays.h"

#include "core/stats.h"

#include "eval/metrics.h"
#include "present/snapshot_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {

constexpr std::array<OverlayInfo, 7> kOverlays = {{
    {Overlay::Bias, "bias", "Bias (error estimate)"},
    {Overlay::Selected, "selected", "Selected pixels and slices"},
    {Overlay::FilterScale, "alpha", "Filter scale (alpha)"},
    {Overlay::SampleCount, "samples", "Kept samples"},
    {Overlay::TracedCount, "traced", "Traced samples"},
    {Overlay::NetworkError, "network_error", "Network error er"},
    {Overlay::ReferenceError, "reference_error", "Error vs reference"},
}};

// The snapshot map behind each overlay (snapshotMaps' names).
const char* mapNameOf(Overlay overlay) {
  switch (overlay) {
    case Overlay::Bias:
      return "bias";
    case Overlay::Selected:
      return "selected";
    case Overlay::FilterScale:
      return "alpha";
    case Overlay::SampleCount:
      return "samples";
    case Overlay::TracedCount:
      return "traced";
    case Overlay::NetworkError:
      return "network_error";
    default:
      return "";
  }
}

float displayChannel(float linear, const DisplaySettings& s, float scale) {
  if (std::isnan(linear)) return 0.0f;
  float x = linear * scale;
  if (s.curve == ToneCurve::Filmic) x = filmicCurve(x);
  return linearToSrgb(x);
}

}  // namespace

float filmicCurve(float x) {
  if (!(x > 0.0f)) return 0.0f;
  if (std::isinf(x)) return 1.0f;
  const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return std::clamp(y, 0.0f, 1.0f);
}

vec3 displayTransform(vec3 linear, const DisplaySettings& settings) {
  const float scale = std::exp2(settings.exposure);
  return {displayChannel(linear.x, settings, scale), displayChannel(linear.y, settings, scale),
          displayChannel(linear.z, settings, scale)};
}

std::span<const OverlayInfo> overlayList() { return kOverlays; }

std::optional<Overlay> overlayByName(std::string_view name) {
  if (name == "none") return Overlay::None;
  for (const OverlayInfo& o : kOverlays)
    if (name == o.name) return o.overlay;
  return std::nullopt;
}

const char* overlayName(Overlay overlay) {
  for (const OverlayInfo& o : kOverlays)
    if (o.overlay == overlay) return o.name;
  return "none";
}

OverlayImage buildOverlay(const Snapshot& snapshot, Overlay overlay, const Image& shown,
                          const Image* reference, const std::vector<float>& alphas) {
  OverlayImage out;
  out.overlay = overlay;
  if (overlay == Overlay::None) return out;
  const int w = snapshot.width, h = snapshot.height;
  if (overlay == Overlay::ReferenceError) {
    if (!reference) {
      out.unavailable = "no reference image (--reference FILE)";
      return out;
    }
    if (reference->width != shown.width || reference->height != shown.height || shown.width != w ||
        shown.height != h) {
      out.unavailable = "the reference is " + std::to_string(reference->width) + "x" +
                        std::to_string(reference->height) + ", the image " + std::to_string(w) +
                        "x" + std::to_string(h);
      return out;
    }
    double maxValue = 0.0;
    const Image error = errorImage(shown, *reference, maxValue);
    out.values.resize(error.pixels.size());
    for (size_t i = 0; i < error.pixels.size(); ++i) out.values[i] = error.pixels[i].x;
    // The 99th percentile keeps a few fireflies from turning the rest of the map dark.
    const float top = std::max(1e-6f, lowerQuantile(out.values, 0.99).value_or(0.0f));
    out.legend = {"relative squared error", MapStyle::Continuous, 0.0f, top, {}};
  } else {
    for (SnapshotMap& m : snapshotMaps(snapshot, alphas)) {
      if (m.name != mapNameOf(overlay)) continue;
      out.values = std::move(m.values);
      out.legend = std::move(m.legend);
    }
    if (out.values.empty()) {
      out.unavailable = "the " + snapshot.method + " method has no " + mapNameOf(overlay) + " map";
      return out;
    }
  }
  out.colors = mapColors(out.values, w, h, out.legend);
  return out;
}

vec3 composePixel(vec3 display, vec3 overlayLinear, float blend) {
  const float b = std::clamp(blend, 0.0f, 1.0f);
  const vec3 o(linearToSrgb(overlayLinear.x), linearToSrgb(overlayLinear.y),
               linearToSrgb(overlayLinear.z));
  return display * (1.0f - b) + o * b;
}

Image composeFrame(const Image& image, const DisplaySettings& settings, const OverlayImage* overlay,
                   float blend) {
  const bool blendIn = overlay && overlay->available();
  if (blendIn && (overlay->colors.width != image.width || overlay->colors.height != image.height))
    throw std::invalid_argument("composeFrame: overlay is " +
                                std::to_string(overlay->colors.width) + "x" +
                                std::to_string(overlay->colors.height) + ", image " +
                                std::to_string(image.width) + "x" + std::to_string(image.height));
  Image out(image.width, image.height);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const vec3 d = displayTransform(image.pixels[i], settings);
    out.pixels[i] = blendIn ? composePixel(d, overlay->colors.pixels[i], blend) : d;
  }
  return out;
}

}  // namespace penumbra
