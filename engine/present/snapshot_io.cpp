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
  for (const SnapshotMap& m : snap.maps) {
    const std::string name = mapName(m.id);
    writeDebugMap(dir, name, m.values, snap.width, snap.height, m.label, m.legend);
    written.push_back(name + ".exr");
    written.push_back(name + ".png");
  }
  return written;
}

}  // namespace penumbra
