#include "methods/snapshot.h"

#include "core/stats.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace penumbra {

namespace {

// The one table of map names. The overlays (key > 0) come first, in key order: the viewer's
// number keys (1-9; overlays past 9 are in the panel's list and --overlay only), its overlay
// list and --overlay follow it; the --aov-dir files are named by it.
constexpr std::array<MapInfo, 15> kMaps = {{
    {MapId::ErrorEstimate, "bias", nullptr, "Bias (error estimate)", 1},
    {MapId::Selected, "selected", "slices", "Selected pixels and slices", 2},
    {MapId::FilterScale, "alpha", "filter-scale", "Filter scale (alpha)", 3},
    {MapId::SampleCount, "samples", nullptr, "Kept samples", 4},
    {MapId::TracedCount, "traced", nullptr, "Traced samples", 5},
    {MapId::NetworkError, "network_error", nullptr, "Network error er", 6},
    {MapId::ReferenceError, "reference_error", nullptr, "Error vs reference", 7},
    {MapId::Albedo, "albedo", nullptr, "Albedo (first hit)", 8},
    {MapId::Normal, "normal", nullptr, "Normal (first hit)", 9},
    {MapId::Depth, "depth", nullptr, "Depth (first hit)", 10},
    {MapId::Emission, "emission", nullptr, "Directly seen emission", 11},
    {MapId::RawError, "raw_error", nullptr, "Raw estimate's relMSE (estimated)", 12},
    {MapId::Prediction, "prediction", nullptr, "Network prediction I'", 0},
    {MapId::SliceB, "slice_b", nullptr, "Slice B", 0},
    {MapId::SliceC, "slice_c", nullptr, "Slice C", 0},
}};

}  // namespace

std::span<const MapInfo> mapTable() { return kMaps; }

const MapInfo* findMapInfo(MapId id) {
  for (const MapInfo& m : kMaps)
    if (m.id == id) return &m;
  return nullptr;
}

const char* mapName(MapId id) {
  const MapInfo* info = findMapInfo(id);
  return info ? info->name : "none";
}

std::optional<MapId> mapByName(std::string_view name) {
  if (name == "none") return MapId::None;
  for (const MapInfo& m : kMaps)
    if (name == m.name || (m.alias && name == m.alias)) return m.id;
  return std::nullopt;
}

const SnapshotMap* findMap(std::span<const SnapshotMap> maps, MapId id) {
  for (const SnapshotMap& m : maps)
    if (m.id == id) return &m;
  return nullptr;
}

const SnapshotMap* Snapshot::map(MapId id) const { return findMap(maps, id); }

SnapshotMap& Snapshot::addMap(MapId id, std::string label, std::vector<float> values,
                              MapLegend legend) {
  if (!findMapInfo(id))
    throw std::invalid_argument("Snapshot::addMap: map id " + std::to_string(int(id)) +
                                " has no row in mapTable()");
  SnapshotMap m{id, std::move(label), std::move(values), std::move(legend)};
  const size_t expected = size_t(width) * size_t(height) * m.channels();
  if (width < 0 || height < 0 || m.values.size() != expected)
    throw std::invalid_argument("Snapshot::addMap: map '" + std::string(mapName(id)) + "' has " +
                                std::to_string(m.values.size()) + " values for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " image");
  for (SnapshotMap& existing : maps)
    if (existing.id == id) return existing = std::move(m);
  return maps.emplace_back(std::move(m));
}

float finiteMax(std::span<const float> values) {
  float m = 0.0f;
  for (float v : values)
    if (std::isfinite(v)) m = std::max(m, v);
  return m;
}

float percentileOf(std::span<const float> values, float q) {
  const std::optional<float> v = nearestRankQuantile(values, q);
  if (!v) return 1.0f;
  return *v > 0 ? *v : std::max(1e-12f, finiteMax(values));
}

void addSampleCountMaps(Snapshot& snap, const std::vector<uint32_t>& kept,
                        const std::vector<uint32_t>& traced) {
  for (auto [id, label, counts] : {std::tuple{MapId::SampleCount, "kept spp", &kept},
                                   std::tuple{MapId::TracedCount, "traced spp", &traced}}) {
    std::vector<float> values = asFloats(*counts);
    const float top = std::max(1.0f, finiteMax(values));
    snap.addMap(id, label, std::move(values), MapLegend::sequential(0.0f, top, "samples"));
  }
}

void addSelectedMap(Snapshot& snap, const std::vector<uint8_t>& selected) {
  snap.addMap(MapId::Selected, "sampled last round", asFloats(selected),
              MapLegend::categorical({"no", "yes"}));
}

}  // namespace penumbra
