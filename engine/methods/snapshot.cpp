#include "methods/snapshot.h"

#include "core/stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace penumbra {

const SnapshotMap* findMap(std::span<const SnapshotMap> maps, MapId id) {
  for (const SnapshotMap& m : maps)
    if (m.id == id) return &m;
  return nullptr;
}

const SnapshotMap* Snapshot::map(MapId id) const { return findMap(maps, id); }

SnapshotMap& Snapshot::addMap(MapId id, std::string label, std::vector<float> values,
                              MapLegend legend) {
  if (id.none()) throw std::invalid_argument("Snapshot::addMap: a map needs a kind");
  SnapshotMap m{id, std::move(label), std::move(values), std::move(legend)};
  const size_t expected = size_t(width) * size_t(height) * m.channels();
  if (width < 0 || height < 0 || m.values.size() != expected)
    throw std::invalid_argument("Snapshot::addMap: map '" + std::string(id.name()) + "' has " +
                                std::to_string(m.values.size()) + " values for a " +
                                std::to_string(width) + "x" + std::to_string(height) + " image");
  if (!withMaps) return notKept_ = std::move(m);
  for (SnapshotMap& existing : maps)
    if (existing.id == id) return existing = std::move(m);
  return maps.emplace_back(std::move(m));
}

const SnapshotStat* Snapshot::stat(std::string_view key) const {
  for (const SnapshotStat& s : stats)
    if (s.key == key) return &s;
  return nullptr;
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
  if (!snap.withMaps) return;
  for (auto [id, label, counts] : {std::tuple{MapId(maps::SampleCount), "kept spp", &kept},
                                   std::tuple{MapId(maps::TracedCount), "traced spp", &traced}}) {
    std::vector<float> values = asFloats(*counts);
    const float top = std::max(1.0f, finiteMax(values));
    snap.addMap(id, label, std::move(values), MapLegend::sequential(0.0f, top, "samples"));
  }
}

void addSelectedMap(Snapshot& snap, const std::vector<uint8_t>& selected) {
  if (!snap.withMaps) return;
  snap.addMap(maps::Selected, "sampled last round", asFloats(selected),
              MapLegend::categorical({"no", "yes"}));
}

}  // namespace penumbra
