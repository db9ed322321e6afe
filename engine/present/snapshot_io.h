// Writing a progressive snapshot's debug maps ("AOVs") to a directory: each map as EXR
// (raw values) and as a false-colour PNG with a legend, plus the raw and reconstructed
// images. Used by `penumbra render --aov-dir`.
#pragma once

#include "methods/progressive.h"
#include "present/debug_maps.h"

#include <string>
#include <vector>

namespace penumbra {

// One scalar debug map of a snapshot with the legend that explains it.
struct SnapshotMap {
  std::string name;  // file stem: bias, network_error, selected, slice_b, slice_c, ...
  std::vector<float> values;
  MapLegend legend;
};
// The scalar maps the snapshot has (a method without a map leaves it out), in a fixed order.
// `alphas` labels the filter-scale map.
std::vector<SnapshotMap> snapshotMaps(const Snapshot& snapshot, const std::vector<float>& alphas);

// Writes the maps the snapshot has; returns the file names written (relative to dir).
// `alphas` labels the filter-scale map. Throws ImageIoError naming the file on failure.
std::vector<std::string> writeSnapshotMaps(const std::string& dir, const Snapshot& snapshot,
                                           const std::vector<float>& alphas);

// The q-quantile (0..1) of the finite values, for a colour scale; positive (the largest
// value, or 1e-12, when the quantile is 0; 1 when nothing is finite).
float percentileOf(const std::vector<float>& values, float q);

// Counts of `values` in `bins` equal bins over [0, maxValue), plus a last bin for
// values >= maxValue (NaN counted there too).
std::vector<uint64_t> histogram(const std::vector<float>& values, int bins, float maxValue);

}  // namespace penumbra
