// The report of `penumbra compare`: several methods (each over several seeds) against one
// reference, written as machine-readable results (JSON, CSV), a Markdown summary with PNG
// images, and one self-contained HTML page (images embedded, inline CSS and SVG, no network)
// that shows the numbers, the images side by side, zoomed crops where the methods differ and
// each method's debug maps.
#pragma once

#include "core/image.h"
#include "eval/metrics.h"
#include "methods/snapshot.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::report {

// Mean and sample standard deviation (n - 1) of the non-NaN values; stddev is 0 for n <= 1.
// An infinite value makes the mean infinite; stddev is then 0 if all values are equal, else NaN.
struct Stat {
  double mean = 0, stddev = 0;
  int count = 0;
};
Stat summarize(const std::vector<double>& values);

// One point of a run's time-to-quality curve: the image the method's user gets (reconstructed
// unless the entry is raw) measured against the reference during the run.
struct CurvePoint {
  // Which of the run's scheduled checkpoints this is (0, 1, ...: the k-th time of an
  // equal-time run, or kept spp 2^k of an equal-spp run); kFinalCheckpoint for the run's end.
  // Seeds are averaged at equal checkpoints.
  int checkpoint = 0;
  double seconds = 0;  // the method's own wall time (see `penumbra compare`: no measuring)
  double mse = 0, relMse = 0, toneMappedMse = 0;
  double keptSpp = 0;
};
inline constexpr int kFinalCheckpoint = -1;

// One seed of one method.
struct MethodRun {
  uint64_t seed = 0;
  ImageMetrics metrics;  // against the reference
  double keptSpp = 0, tracedSpp = 0;
  double seconds = 0;                                        // total wall time
  double trace = 0, train = 0, select = 0, reconstruct = 0;  // phase times, seconds
  double network = 0;  // bp --networks 1: the networks' training and correction, seconds
  // Speckles: the share of pixels whose relative squared error exceeds the 99.9th percentile
  // of the first method's (the same seed); NaN where it was not measured.
  double speckleShare = NAN;
  // Time to quality, in order of time, the last point the run's end (the metrics above);
  // empty when compare ran without curves.
  std::vector<CurvePoint> curve;
};

struct MethodResult {
  std::string label;            // unique, short: "ld", "bp", "ld@64", "gem"
  std::string description;      // "Low discrepancy (box)", "Fuzzy (re-implemented)", ...
  int spp = 0;                  // requested kept spp
  std::vector<MethodRun> runs;  // one per seed
  // Images of the first seed, all width*height of the report's reference:
  Image image;  // the method's output, linear RGB
  // The method's debug maps as its snapshot published them (labelled, with their legends);
  // the report shows its kept samples, its error estimate and its filter scale, each where
  // the method has it (detail::reportMaps()).
  std::vector<SnapshotMap> maps;
};

// A square region of the image, in pixels, top-left corner (x, y).
struct Crop {
  std::string name;
  int x = 0, y = 0, w = 0, h = 0;
};

struct CompareReport {
  std::string title;                           // e.g. scene file name
  std::string scenePath, referencePath, mode;  // mode: "equal kept spp (16)", "equal time (10 s)"
  std::string commandLine;
  int threads = 0;
  Image reference;
  std::vector<MethodResult> methods;  // the first is the baseline the ratios refer to
  std::vector<Crop> crops;            // chosen regions; empty: the writer calls chooseCrops
  float exposure = 0;                 // stops, for the PNG images
};

// Up to `count` non-overlapping square crops (side `size`, default max(16, min(w,h)/6),
// clamped to the image) where the methods differ most: every window on a grid of stride
// size/2 (plus the last row and column) is scored by the spread (max - min) across methods of
// the first seed's mean relative squared error in the window, plus the mean of those errors;
// the best windows are taken greedily. Deterministic; named "A", "B", ... in order of score.
// Fewer crops come back when no more fit without overlapping (a tiny image holds one).
// Throws std::invalid_argument when a method's image size differs from the reference's.
std::vector<Crop> chooseCrops(const CompareReport& r, int count = 3, int size = 0);

// Writes into `dir` (created if missing), each file atomically:
//   results.json, results.csv (one row per method and seed), curves.csv (one row per curve
//   point: label, seed, checkpoint, seconds, mse, rel_mse, tone_mapped_mse, kept_spp; only
//   the header when no run has a curve), report.md,
//   images/*.png (each method's image, error, density, error-estimate and filter-scale maps,
//   the reference, an overview with the crops outlined, and the crops zoomed per method),
//   report.html (one self-contained page: images embedded as data: URLs).
// Uses r.crops, or chooseCrops(r) when it is empty.
// Throws std::invalid_argument, before writing anything, when an image or map size does not
// match the reference (or a crop lies outside it); ImageIoError naming the file on I/O failure.
void writeReport(const std::string& dir, const CompareReport& r);

// Standard base64 (RFC 4648, with '=' padding).
std::string base64(const std::vector<uint8_t>& bytes);

}  // namespace penumbra::report
