#include "cli/render_stats.h"

#include "present/snapshot_io.h"

#include <algorithm>

namespace penumbra {

namespace {

// A map's histogram: its categories' counts, or 20 bins over its colour range and one for the
// values at or above its top (ALGORITHM.md §5 and §9.5: the spread of the error estimate and
// of the filter scale decides how selective sampling and filtering are).
nlohmann::json mapHistogram(const SnapshotMap& map) {
  const MapLegend& legend = map.legend;
  if (legend.kind == ColorMapKind::Categorical) {
    std::vector<uint64_t> counts(legend.categories.size(), 0);
    for (float v : map.values)
      if (v >= 0 && size_t(v) < counts.size()) ++counts[size_t(v)];
    return {{"labels", legend.categories}, {"counts", counts}};
  }
  constexpr int kBins = 20;
  const float top = legend.maxValue > 0 ? legend.maxValue : 1.0f;
  return {{"bin_width", double(top) / kBins}, {"counts", histogram(map.values, kBins, top)}};
}

void addMethodFigures(nlohmann::json& j, const Snapshot& snap, bool numbersOnly) {
  for (const SnapshotStat& s : snap.stats) {
    if (!s.text.empty()) {
      if (!numbersOnly) j[s.key] = s.text;
    } else {
      j[s.key] = s.value;
    }
  }
}

}  // namespace

nlohmann::json roundStats(const Snapshot& snap) {
  const double pixels = std::max(1.0, double(snap.width) * snap.height);
  const SnapshotMap* selected = snap.map(maps::Selected);
  nlohmann::json j = {
      {"round", snap.round},
      {"kept_spp", double(snap.keptSamples) / pixels},
      {"traced_spp", double(snap.tracedSamples) / pixels},
      {"pixels_sampled",
       selected ? std::count(selected->values.begin(), selected->values.end(), 1.0f) : 0},
      {"seconds", snap.seconds}};
  addMethodFigures(j, snap, true);
  return j;
}

nlohmann::json methodRunStats(const MethodSpec& spec, const std::string& preset,
                              const Snapshot& snap, size_t memoryBytes) {
  const MethodDescriptor& method = spec.method();
  const double pixels = std::max(1.0, double(snap.width) * snap.height);
  nlohmann::json j;
  j["method"] = method.name();
  if (!method.algorithm().empty()) j["algorithm"] = method.algorithm();
  const MethodDescriptor::Preset* named = method.defaultPreset();
  if (!preset.empty())
    j["preset"] = preset;
  else if (named)
    j["preset"] = named->name;
  j["description"] = method.description();
  j["kept_spp"] = double(snap.keptSamples) / pixels;
  j["traced_spp"] = double(snap.tracedSamples) / pixels;
  j["rounds"] = snap.round;
  j["nan_samples"] = snap.nonFiniteSamples;
  j["rejected_samples"] = snap.rejectedSamples;
  j["phases"] = {{"trace", snap.times.trace},
                 {"train", snap.times.train},
                 {"select", snap.times.select},
                 {"reconstruct", snap.times.reconstruct},
                 {"network", snap.times.network}};
  j["adaptive_overhead"] =
      snap.times.total() > 0 ? (snap.times.total() - snap.times.trace) / snap.times.total() : 0.0;
  j["memory_bytes_per_pixel"] = double(memoryBytes) / pixels;
  j["config"] = paramsJson(spec.method().params(), spec.config);
  addMethodFigures(j, snap, false);
  for (const SnapshotMap& map : snap.maps)
    if (const MapReport* report = map.id.kind()->report)
      j[std::string(report->jsonKey) + "_histogram"] = mapHistogram(map);
  return j;
}

}  // namespace penumbra
