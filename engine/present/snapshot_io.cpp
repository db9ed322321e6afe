#include "present/snapshot_io.h"

#include "core/image_io.h"
#include "present/debug_maps.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace penumbra {

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

std::vector<std::string> writeSnapshotMaps(const std::string& dir, const Snapshot& snap) {
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
  // Every image and map again as the layers of one EXR, so that tev shows them together:
  // "raw.R", "albedo.G", "samples.Y", ...
  std::vector<ExrChannel> layers;
  const size_t pixels = size_t(snap.width) * size_t(snap.height);
  auto rgbLayer = [&](const std::string& name, const float* values, size_t stride) {
    const char* channel[3] = {".R", ".G", ".B"};
    for (size_t k = 0; k < 3; ++k) {
      std::vector<float> plane(pixels);
      for (size_t p = 0; p < pixels; ++p) plane[p] = values[p * stride + k];
      layers.emplace_back(name + channel[k], std::move(plane));
    }
  };
  if (!snap.raw.empty()) rgbLayer("raw", &snap.raw.pixels[0].x, 3);
  if (!snap.reconstructed.empty()) rgbLayer("reconstructed", &snap.reconstructed.pixels[0].x, 3);
  for (const SnapshotMap& m : snap.maps) {
    const std::string name = m.id.name();
    writeDebugMap(dir, name, m.values, snap.width, snap.height, m.label, m.legend);
    written.push_back(name + ".exr");
    written.push_back(name + ".png");
    if (m.channels() == 3)
      rgbLayer(name, m.values.data(), 3);
    else
      layers.emplace_back(name + ".Y", m.values);
  }
  if (!layers.empty() && pixels > 0) {
    writeExrLayers(dir + "/layers.exr", snap.width, snap.height, layers);
    written.push_back("layers.exr");
  }
  return written;
}

}  // namespace penumbra
