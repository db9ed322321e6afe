// Writing a progressive snapshot's debug maps ("AOVs") to a directory: the raw and
// reconstructed images, then every map the snapshot holds, each as EXR (raw values) and as a
// false-colour PNG with a legend, named by the map table (methods/snapshot.h). Used by
// `penumbra render --aov-dir`.
#pragma once

#include "methods/snapshot.h"

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

// Writes the images and maps the snapshot has, in the snapshot's order, each as its own file
// and all together as the layers of layers.exr (raw.R, albedo.G, samples.Y, ...); returns the file
// names written (relative to dir). Throws ImageIoError naming the file on failure.
std::vector<std::string> writeSnapshotMaps(const std::string& dir, const Snapshot& snapshot);

// Counts of `values` in `bins` equal bins over [0, maxValue), plus a last bin for
// values >= maxValue (NaN counted there too).
std::vector<uint64_t> histogram(const std::vector<float>& values, int bins, float maxValue);

}  // namespace penumbra
