// What a progressive method publishes after a round: the image, raw and reconstructed, and a
// list of labelled debug maps that explain its sampling decisions. The method fills each map
// itself: its values, its label (a baseline's score is labelled as that score) and its legend
// (units, range, colour map, category labels). How a map is drawn (false colour, legend strips)
// is engine/present's business; what a map is called and how the viewer and the report show it
// is its MapKind's.
//
// Adding a debug map: a MapKind beside the method that makes it, listed in the method's
// descriptor (methods/method.h), and Snapshot::addMap in its snapshot(). Nothing else changes:
// the files, the overlays (a kind with a key), the report and the viewer follow the kinds.
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

// ---- Map kinds ------------------------------------------------------------------------
// A map's kind is its metadata, defined once beside the code that makes it: its names, its
// place among the viewer's overlays, how compare's report shows it and whether the viewer draws
// it as sub-pixel slices. A method lists the kinds it publishes in its descriptor
// (methods/method.h); the overlays, --aov-dir, the report and the shaders read them there.

// How compare's report shows a map: one row of pictures, one per method that has it.
enum class ReportScale : uint8_t {
  Shared,         // Sequential, one colour bar from 0 to the largest value of all methods
  OwnPercentile,  // Sequential, each method's own colour bar from 0 to its 99th percentile
  Categories,     // Categorical, the method's category labels
};
struct MapReport {
  int order;            // the rows' order
  const char* stem;     // images/<method>_<stem>.png
  const char* jsonKey;  // results.json: methods[].images.<jsonKey>
  const char* rowName;  // report.md
  const char* title;    // the legend's title; nullptr: the map's label
  const char* heading;  // report.html
  const char* note;     // report.html, under the heading
  ReportScale scale;
};

// A map of one slice index per pixel that the viewer draws inside the zoomed-in pixels over
// the "selected" overlay: the first role filled blue, the second orange.
enum class SliceRole : uint8_t { None, First, Second };

struct MapKind {
  const char* name;        // --overlay NAME, the --aov-dir file stem, the stats' key
  const char* alias;       // another name --overlay accepts, or nullptr
  const char* panelLabel;  // the viewer's overlay list
  int key;  // overlay order, 1...: keys 1-9 are the viewer's number keys; 0: files only
  const MapReport* report = nullptr;  // how compare's report shows it; nullptr: not shown
  SliceRole slices = SliceRole::None;
};

// Which map: its kind, or none (the viewer's "no overlay"). A MapKind converts to its id.
class MapId {
 public:
  constexpr MapId() = default;
  constexpr MapId(const MapKind& kind) : kind_(&kind) {}  // NOLINT: an id of its kind
  constexpr const MapKind* kind() const { return kind_; }
  constexpr bool none() const { return kind_ == nullptr; }
  const char* name() const { return kind_ ? kind_->name : "none"; }
  friend constexpr bool operator==(MapId a, MapId b) { return a.kind_ == b.kind_; }

 private:
  const MapKind* kind_ = nullptr;
};

// The maps of the framework every method shares (the film's are in
// methods/film_reconstruction.h, the reference error in present/overlays.h, a method's own in
// its folder).
namespace maps {
inline constexpr MapReport kErrorEstimateReport{
    2,
    "estimate",
    "error_estimate",
    "error estimate",
    nullptr,
    "Error estimates",
    "Each method's own per-pixel error estimate; colour bar 0 to its 99th percentile.",
    ReportScale::OwnPercentile};
inline constexpr MapReport kFilterScaleReport{3,
                                              "filter",
                                              "filter_scale",
                                              "filter scale",
                                              "filter",
                                              "Filter scale",
                                              "Reconstruction filter chosen per pixel.",
                                              ReportScale::Categories};
inline constexpr MapReport kSampleCountReport{1,
                                              "density",
                                              "density",
                                              "kept spp",
                                              "kept spp",
                                              "Kept samples per pixel",
                                              "Shared colour bar across methods.",
                                              ReportScale::Shared};
// The error estimate or score that drives sampling: BP's bias, a baseline's own score.
inline constexpr MapKind ErrorEstimate{"bias", nullptr, "Bias (error estimate)", 1,
                                       &kErrorEstimateReport};
// 1 where the last round added samples, else 0.
inline constexpr MapKind Selected{"selected", "slices", "Selected pixels and slices", 2};
// The reconstruction filter chosen per pixel (BP's alpha, GEM's sigma, the film's window).
inline constexpr MapKind FilterScale{"alpha", "filter-scale", "Filter scale (alpha)", 3,
                                     &kFilterScaleReport};
inline constexpr MapKind SampleCount{"samples", nullptr, "Kept samples", 4, &kSampleCountReport};
inline constexpr MapKind TracedCount{"traced", nullptr, "Traced samples", 5};
// Every map above, in the order of their keys.
inline constexpr const MapKind* kShared[] = {&ErrorEstimate, &Selected, &FilterScale, &SampleCount,
                                             &TracedCount};
}  // namespace maps

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
  MapId id;
  std::string label;          // what the values are: the legend's title ("bias", a score's name)
  std::vector<float> values;  // per pixel, rows top first; Rgb: three per pixel
  MapLegend legend;
  int slicesPerSide = 0;  // a map of slice indices (its kind has a SliceRole): S of S x S
  size_t channels() const { return legend.kind == ColorMapKind::Rgb ? 3 : 1; }
};

// ---- Snapshots ------------------------------------------------------------------------

// Wall time per phase, summed over the rounds so far (seconds).
struct PhaseTimes {
  double trace = 0;        // path tracing, including candidate samples
  double train = 0;        // network (re)training and the bias estimate
  double select = 0;       // ranking pixels, slice choice, candidate scoring
  double reconstruct = 0;  // pixel estimates and the filter
  double network = 0;      // the networks that reconstruct: their training and their candidates
  double total() const { return trace + train + select + reconstruct + network; }
};

enum class SnapshotSource : uint8_t {
  Method,   // a round of a progressive method
  Preview,  // the viewer's block preview after a restart (no maps)
};

// A figure of the method's own, by name: a number, or a text when `text` is not empty.
struct SnapshotStat {
  std::string key;
  double value = 0;
  std::string text;
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
  // Whether the method made its maps: false when they were not wanted
  // (ProgressiveMethod::setMapsWanted; a viewer showing no overlay), and then `maps` is empty
  // and addMap keeps nothing.
  bool withMaps = true;

  uint64_t keptSamples = 0, tracedSamples = 0, rays = 0;
  uint64_t nonFiniteSamples = 0;  // NaN or infinite samples dropped
  uint64_t rejectedSamples = 0;   // traced but removed as outliers
  PhaseTimes times;
  double seconds = 0;  // wall time since the method started
  // The method's own figures for `render --stats` (e.g. BP's "coarse_spp", "training_gflops"),
  // in the order it adds them.
  std::vector<SnapshotStat> stats;

  // The map `id`, or nullptr when the snapshot has none.
  const SnapshotMap* map(MapId id) const;
  // Appends a map (replacing one of the same id); without maps (withMaps false), returns a
  // map that is not kept. Throws std::invalid_argument when the values are not one per pixel
  // (Rgb: three), or the id is none.
  SnapshotMap& addMap(MapId id, std::string label, std::vector<float> values, MapLegend legend);
  // The figure `key` (nullptr when the method has none).
  const SnapshotStat* stat(std::string_view key) const;
  void addStat(std::string key, double value) { stats.push_back({std::move(key), value, {}}); }
  void addStat(std::string key, std::string text) {
    stats.push_back({std::move(key), 0, std::move(text)});
  }

 private:
  SnapshotMap notKept_;  // what addMap returns without maps
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
