// Writing a progressive snapshot's debug maps ("AOVs") to a directory: each map as EXR
// (raw values) and as a false-colour PNG with a legend, plus the raw and reconstructed
// images. Used by `penumbra render --aov-dir`.
#pragma once

#include "engine/progressive.h"

#include <string>
#include <vector>

namespace penumbra {

// Writes the maps the snapshot has; returns the file names written (relative to dir).
// `alphas` labels the filter-scale map. Throws ImageIoError naming the file on failure.
std::vector<std::string> writeSnapshotMaps(const std::string& dir, const Snapshot& snapshot,
                                           const std::vector<float>& alphas);

// Counts of `values` in `bins` equal bins over [0, maxValue), plus a last bin for
// values >= maxValue (NaN counted there too).
std::vector<uint64_t> histogram(const std::vector<float>& values, int bins, float maxValue);

}  // namespace penumbra
