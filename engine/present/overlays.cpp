#include "present/overlays.h"

#include "core/stats.h"

#include "eval/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {

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

std::vector<const MapKind*> overlayList(const MethodRegistry& methods) {
  std::vector<const MapKind*> list;
  for (const MapKind* kind : methods.maps())
    if (kind->key > 0) list.push_back(kind);
  list.push_back(&maps::ReferenceError);
  std::stable_sort(list.begin(), list.end(),
                   [](const MapKind* a, const MapKind* b) { return a->key < b->key; });
  return list;
}

std::optional<MapId> overlayByName(std::string_view name, const MethodRegistry& methods) {
  const std::optional<MapId> id =
      name == maps::ReferenceError.name ? MapId(maps::ReferenceError) : methods.mapByName(name);
  if (!id || (!id->none() && id->kind()->key == 0)) return std::nullopt;  // files only
  return id;
}

std::string overlayNames(const MethodRegistry& methods) {
  std::string names = "none";
  for (const MapKind* o : overlayList(methods)) {
    names += std::string(", ") + o->name;
    if (o->alias) names += std::string(" (or ") + o->alias + ")";
  }
  return names;
}

namespace {

// The relative squared error of `shown` against `reference`, into `out`; false (with the
// reason in out.unavailable) when there is no reference or the sizes differ.
bool referenceError(const Image& shown, const Image* reference, int w, int h, OverlayImage& out) {
  if (!reference) {
    out.unavailable = "no reference image (--reference FILE)";
    return false;
  }
  if (reference->width != shown.width || reference->height != shown.height || shown.width != w ||
      shown.height != h) {
    out.unavailable = "the reference is " + std::to_string(reference->width) + "x" +
                      std::to_string(reference->height) + ", the image " + std::to_string(w) + "x" +
                      std::to_string(h);
    return false;
  }
  double maxValue = 0.0;
  const Image error = errorImage(shown, *reference, maxValue);
  out.values.resize(error.pixels.size());
  for (size_t i = 0; i < error.pixels.size(); ++i) out.values[i] = error.pixels[i].x;
  // The 99th percentile keeps a few fireflies from turning the rest of the map dark.
  const float top = std::max(1e-6f, lowerQuantile(out.values, 0.99).value_or(0.0f));
  out.label = "relative squared error";
  out.legend = MapLegend::sequential(0.0f, top);
  return true;
}

}  // namespace

OverlayImage buildOverlay(const Snapshot& snapshot, MapId overlay, const Image& shown,
                          const Image* reference) {
  OverlayImage out;
  out.overlay = overlay;
  if (overlay.none()) return out;
  const int w = snapshot.width, h = snapshot.height;
  if (overlay == maps::ReferenceError) {
    if (!referenceError(shown, reference, w, h, out)) return out;
  } else if (const SnapshotMap* m = snapshot.map(overlay)) {
    out.label = m->label;
    out.values = m->values;
    out.legend = m->legend;
  } else {
    // A snapshot made while no overlay was shown has no maps (Snapshot::withMaps): the next
    // picture has them.
    out.unavailable =
        snapshot.withMaps
            ? "the " + snapshot.method + " method has no " + std::string(overlay.name()) + " map"
            : "the " + std::string(overlay.name()) + " map comes with the next picture";
    return out;
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
