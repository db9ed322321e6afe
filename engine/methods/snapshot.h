// What a progressive method publishes after a round: the image, raw and reconstructed, and a
// list of labelled debug maps that explain its sampling decisions. The method fills each map
// itself: its values, its label (a baseline's score is labelled as that score) and its legend
// (units, range, colour map, category labels). How a map is drawn (false colour, legend strips)
// is engine/present's business; which maps exist and what they are called is mapTable()'s, the
// one table the overlays, `render --aov-dir`, the report and the viewer read.
//
// Adding a debug map: a MapId and a row of mapTable() (snapshot.cpp), then the method's
// snapshot() publishes it with Snapshot::addMap. Nothing else changes: the files, the
// overlays (a row with a key) and the viewer follow the list.
#pragma once

#include "core/image.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra {

// Every debug map a snapshot can hold, and the viewer's "no overlay".
enum class MapId : uint8_t {
  None,  // no map: the viewer's "none" overlay
  // The error estimate or score that drives sampling: BP's bias, a baseline's own score.
  ErrorEstimate,
  Selected,      // 1 where the last round added samples, else 0
  FilterScale,   // the reconstruction filter chosen per pixel (BP's alpha, GEM's sigma)
  SampleCount,   // kept samples per pixel
  TracedCount,   // traced camera samples per pixel
  NetworkError,  // er of the pixel's network (BP)
  // The relative squared error against a reference: computed in present/, not by a method.
  ReferenceError,
  Prediction,  // I', the network's prediction, tone-mapped RGB (BP)
  SliceB,      // the slice B the last round chose, -1 for none (BP)
  SliceC,      // the slice C the last round chose, -1 for none (BP)
  // The film's first-hit features and buffers (methods/film.h), for methods that filter:
  Albedo,    // mean albedo at the first non-specular hit, linear RGB
  Normal,    // mean shading normal there, shown as 0.5 + 0.5 n
  Depth,     // mean distance to it over the image's mean
  Emission,  // directly seen emission, linear RGB
  RawError,  // estimated relative squared error of the unfiltered pixel mean
};

// How a map's values become colours.
enum class ColorMapKind : uint8_t {
  Sequential,   // low to high: viridis from minValue to maxValue; NaN magenta
  Diverging,    // around the middle of [minValue, maxValue]: blue, light grey, red; NaN magenta
  Categorical,  // the value is an integer index into categories; < 0 or NaN: "none"
  Rgb,          // three values per pixel, linear RGB, shown as they are
};

struct MapLegend {
  ColorMapKind kind = ColorMapKind::Sequential;
  float minValue = 0.0f, maxValue = 1.0f;  // Sequential, Diverging: the colour range
  std::vector<std::string> categories;     // Categorical: one label per index
  std::string units;                       // what the values count or measure; empty: unitless

  static MapLegend sequential(float minValue, float maxValue, std::string units = {}) {
    return {ColorMapKind::Sequential, minValue, maxValue, {}, std::move(units)};
  }
  static MapLegend diverging(float minValue, float maxValue, std::string units = {}) {
    return {ColorMapKind::Diverging, minValue, maxValue, {}, std::move(units)};
  }
  static MapLegend categorical(std::vector<std::string> categories) {
    return {ColorMapKind::Categorical, 0.0f, 1.0f, std::move(categories), {}};
  }
  static MapLegend rgb() { return {ColorMapKind::Rgb, 0.0f, 1.0f, {}, {}}; }
};

struct SnapshotMap {
  MapId id = MapId::None;
  std::string label;          // what the values are: the legend's title ("bias", a score's name)
  std::vector<float> values;  // per pixel, rows top first; Rgb: three per pixel
  MapLegend legend;
  size_t channels() const { return legend.kind == ColorMapKind::Rgb ? 3 : 1; }
};

// ---- The map table --------------------------------------------------------------------

struct MapInfo {
  MapId id;
  const char* name;        // --overlay NAME and the --aov-dir file stem
  const char* alias;       // another name --overlay accepts, or nullptr
  const char* panelLabel;  // the viewer's overlay list
  int key;  // overlay order, 1...: keys 1-9 are the viewer's number keys; 0: files only
};

// Every map but None: the overlays first, in the order of their keys, then the others.
std::span<const MapInfo> mapTable();
// The row of `id`; nullptr for None (or an id without a row, which a test rules out).
const MapInfo* findMapInfo(MapId id);
const char* mapName(MapId id);  // "none" for None
// A map by its name or alias; "none" gives None.
std::optional<MapId> mapByName(std::string_view name);

// ---- Snapshots ------------------------------------------------------------------------

// Wall time per phase, summed over the rounds so far (seconds).
struct PhaseTimes {
  double trace = 0;        // path tracing, including candidate samples
  double train = 0;        // network (re)training and the bias estimate
  double select = 0;       // ranking pixels, slice choice, candidate scoring
  double reconstruct = 0;  // pixel estimates and the filter
  double total() const { return trace + train + select + reconstruct; }
};

enum class SnapshotSource : uint8_t {
  Method,   // a round of a progressive method
  Preview,  // the viewer's block preview after a restart (no maps)
};

struct Snapshot {
  int round = 0;  // rounds completed; 1 after the coarse pass
  bool final = false;
  int width = 0, height = 0;
  SnapshotSource source = SnapshotSource::Method;
  std::string method;   // the method's name, for display
  Image raw;            // per-pixel estimate, linear RGB
  Image reconstructed;  // after the method's filter (equals raw without one)

  // The method's debug maps, in the order it publishes them (a map it lacks is absent).
  std::vector<SnapshotMap> maps;
  int slicesPerSide = 0;  // slices per pixel side of the SliceB and SliceC maps; 0: none

  uint64_t keptSamples = 0, tracedSamples = 0, rays = 0;
  uint64_t nonFiniteSamples = 0;  // NaN or infinite samples dropped
  uint64_t rejectedSamples = 0;   // traced but removed as outliers
  PhaseTimes times;
  uint64_t trainingFlops = 0;        // multiply-add flops spent in network training
  double trainingKernelSeconds = 0;  // time inside the training kernel alone
  double seconds = 0;                // wall time since the method started

  // The map `id`, or nullptr when the snapshot has none.
  const SnapshotMap* map(MapId id) const;
  // Appends a map (replacing one of the same id). Throws std::invalid_argument when the
  // values are not one per pixel (Rgb: three), or the id is None or has no row in mapTable().
  SnapshotMap& addMap(MapId id, std::string label, std::vector<float> values, MapLegend legend);
};

// The map `id` of a list of maps, or nullptr.
const SnapshotMap* findMap(std::span<const SnapshotMap> maps, MapId id);

// ---- Helpers for the methods' maps ----------------------------------------------------

template <typename T>
std::vector<float> asFloats(const std::vector<T>& values) {
  return std::vector<float>(values.begin(), values.end());
}
// The largest finite value, or 0 (none, or all below 0).
float finiteMax(std::span<const float> values);
// The q-quantile (0..1) of the finite values, for a colour scale; positive (the largest
// value, or 1e-12, when the quantile is 0; 1 when nothing is finite).
float percentileOf(std::span<const float> values, float q);

// The maps every method has: kept and traced samples per pixel, and the pixels the last round
// sampled.
void addSampleCountMaps(Snapshot& snap, const std::vector<uint32_t>& kept,
                        const std::vector<uint32_t>& traced);
void addSelectedMap(Snapshot& snap, const std::vector<uint8_t>& selected);

}  // namespace penumbra
