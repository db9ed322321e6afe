#include "present/snapshot_io.h"

#include "core/stats.h"

#include "core/image_io.h"
#include "present/debug_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace penumbra {

namespace {

std::string compact(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

template <typename T>
std::vector<float> asFloats(const std::vector<T>& values) {
  return std::vector<float>(values.begin(), values.end());
}

float maxOf(const std::vector<float>& values) {
  float m = 0.0f;
  for (float v : values)
    if (std::isfinite(v)) m = std::max(m, v);
  return m;
}

}  // namespace

float percentileOf(const std::vector<float>& values, float q) {
  const std::optional<float> v = nearestRankQuantile(values, q);
  if (!v) return 1.0f;
  return *v > 0 ? *v : std::max(1e-12f, maxOf(values));
}

std::vector<uint64_t> histogram(const std::vector<float>& values, int bins, float maxValue) {
  std::vector<uint64_t> counts(size_t(bins) + 1, 0);
  for (float v : values) {
    if (!(v < maxValue)) {
      ++counts[bins];
      continue;
    }
    counts[std::clamp(int(std::floor(v / maxValue * bins)), 0, bins - 1)]++;
  }
  return counts;
}

std::vector<SnapshotMap> snapshotMaps(const Snapshot& snap, const std::vector<float>& alphas) {
  std::vector<SnapshotMap> maps;
  const size_t n = size_t(snap.width) * snap.height;
  auto map = [&](const std::string& name, std::vector<float> values, MapLegend legend) {
    if (values.size() == n) maps.push_back({name, std::move(values), std::move(legend)});
  };
  map("bias", snap.bias,
      {snap.biasLabel,
       MapStyle::Continuous,
       0.0f,
       snap.biasRange > 0 ? snap.biasRange : percentileOf(snap.bias, 0.99f),
       {}});
  map("network_error", snap.networkError,
      {"er", MapStyle::Continuous, 0.0f, std::max(1e-3f, maxOf(snap.networkError)), {}});
  map("selected", asFloats(snap.selected),
      {"sampled last round", MapStyle::Categorical, 0, 1, {"no", "yes"}});
  std::vector<std::string> sliceLabels;
  const int S = std::max(1, snap.slicesPerSide);
  for (int i = 0; i < S * S; ++i) {
    char label[32];
    std::snprintf(label, sizeof label, "(%d,%d)", i % S, i / S);
    sliceLabels.push_back(label);
  }
  map("slice_b", asFloats(snap.sliceB), {"slice B", MapStyle::Categorical, 0, 1, sliceLabels});
  map("slice_c", asFloats(snap.sliceC), {"slice C", MapStyle::Categorical, 0, 1, sliceLabels});
  std::vector<float> kept = asFloats(snap.keptCount);
  const float maxKept = std::max(1.0f, maxOf(kept));
  map("samples", std::move(kept), {"kept spp", MapStyle::Continuous, 0.0f, maxKept, {}});
  std::vector<float> traced = asFloats(snap.tracedCount);
  const float maxTraced = std::max(1.0f, maxOf(traced));
  map("traced", std::move(traced), {"traced spp", MapStyle::Continuous, 0.0f, maxTraced, {}});
  std::vector<std::string> alphaLabels = snap.filterScaleLabels;
  if (alphaLabels.empty())
    for (float a : alphas) alphaLabels.push_back("a=" + compact(a));
  map("alpha", asFloats(snap.alphaIndex),
      {snap.filterScaleLabels.empty() ? "filter alpha" : "filter scale", MapStyle::Categorical, 0,
       1, alphaLabels});
  return maps;
}

std::vector<std::string> writeSnapshotMaps(const std::string& dir, const Snapshot& snap,
                                           const std::vector<float>& alphas) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw ImageIoError(dir + ": cannot create directory: " + ec.message());
  std::vector<std::string> written;
  auto image = [&](const std::string& name, const Image& img) {
    if (img.empty()) return;
    writeImage(dir + "/" + name + ".exr", img);
    written.push_back(name + ".exr");
  };
  image("raw", snap.raw);
  image("reconstructed", snap.reconstructed);
  if (!snap.prediction.empty()) {
    // I' is already tone-mapped, so its PNG is the values themselves.
    writeImage(dir + "/prediction.exr", snap.prediction);
    writeImage(dir + "/prediction.png", snap.prediction);
    written.push_back("prediction.exr");
    written.push_back("prediction.png");
  }
  for (const SnapshotMap& m : snapshotMaps(snap, alphas)) {
    writeDebugMap(dir, m.name, m.values, snap.width, snap.height, m.legend);
    written.push_back(m.name + ".exr");
    written.push_back(m.name + ".png");
  }
  return written;
}

}  // namespace penumbra
