// Internal to report*.cpp: what report.cpp (statistics, images, results, report.md),
// report_curves.cpp (time to quality), report_charts.cpp (the SVG charts) and report_html.cpp
// (report.html) share. Not part of the public API, which is report/report.h.
#pragma once

#include "report/report.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace penumbra::report::detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- Metrics table ------------------------------------------------------------------------
// One entry per reported quantity; drives the JSON statistics, the winners and the tables.
enum class Better { Lower, Higher, Unranked };

struct Metric {
  const char* key;
  double (*value)(const MethodRun&);
  Better better;
};

extern const std::array<Metric, 13> kMetrics;  // defined in report.cpp

enum MetricIndex {
  kMse,
  kRelMse,
  kToneMse,
  kPsnr,
  kKept,
  kTraced,
  kSeconds,
  kTrace,
  kTrain,
  kSelect,
  kReconstruct
};

// stats[method][metric]
using StatTable = std::vector<std::array<Stat, kMetrics.size()>>;

// Index of the best method by mean of metric k (first on ties), -1 if none has a value.
int winnerOf(const StatTable& stats, size_t k);

// ---- Text formatting ----------------------------------------------------------------------
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  const int n = std::snprintf(nullptr, 0, fmt, args...);
  if (n <= 0) return {};
  std::string text(size_t(n) + 1, '\0');
  std::snprintf(text.data(), text.size(), fmt, args...);
  text.resize(size_t(n));
  return text;
}

// "1.234e-03"; "n/a" for NaN, "inf" for infinity.
std::string sci(double v);
std::string sciSd(double v);  // a standard deviation: "1.2e-04", "n/a" where not finite
std::string decibels(double v);
std::string samples(double v);  // a sample count: "16", "15.5"
// A time, in milliseconds below a second, the sd in the mean's unit: "660 ms ± 60", "2.1 s".
std::string seconds(const Stat& s);
std::string ratio(double v);  // "2.41×"
// "mean ± sd" (the sd only where there are at least two seeds).
std::string meanSd(const Stat& s, std::string (*mean)(double), std::string (*sd)(double));
std::string htmlEscape(const std::string& text);
std::string markdownCell(const std::string& text);  // inside a Markdown table cell
// sRGB hex colour of a linear colour, for HTML and SVG.
std::string hexColor(vec3 linear);
vec3 cropColor(size_t index, size_t count);  // the colour of crop `index` of `count`

// ---- Everything the writers share ---------------------------------------------------------
// A PNG written under images/ and kept in memory for embedding in the HTML page.
struct Png {
  std::string file;  // relative to the report folder: "images/ld.png"
  std::vector<uint8_t> bytes;
  int width = 0, height = 0;
};

// The methods' maps the report shows, one row each (report.md, report.html) and one PNG per
// method that has the map: the map kinds that say how (MapKind::report), in their order.
struct ReportMap {
  MapId id;
  const MapReport* report;
};
std::span<const ReportMap> reportMaps();

struct MethodImages {
  Png image, error;       // empty file: not present
  std::vector<Png> maps;  // one per reportMaps() row
};

struct Prepared {
  explicit Prepared(const CompareReport& report) : r(report) {}
  const CompareReport& r;
  std::vector<Crop> crops;
  StatTable stats;
  std::vector<std::string> stems;      // per method, for file names
  std::vector<std::string> cropStems;  // per crop
  float errorScale = 1;                // shared top of the error maps' colour bar
  Png reference, overview;
  std::vector<MethodImages> images;
  std::vector<std::vector<Png>> cropImages;         // [crop][0: reference, 1 + method]
  std::vector<std::vector<double>> cropMse;         // [crop][method]
  std::vector<std::vector<CurvePoint>> meanCurves;  // per method, meanCurve()
};

// ---- Time to quality (report_curves.cpp) --------------------------------------------------
// How the curves' times are measured, for report.html and report.md.
extern const char* const kCurveTimingNote;

// A method's curve averaged over its seeds: at each checkpoint that every seed's curve has
// (CurvePoint::checkpoint), the mean of their points; in order of time. Runs without a curve
// are left out; empty when no run has one.
std::vector<CurvePoint> meanCurve(const MethodResult& m);
bool anyCurve(const CompareReport& r);

// When a curve first reaches an MSE: interpolated linearly in log time and log MSE between the
// checkpoint before and the first checkpoint at or below the level. `atFirst`: the first
// checkpoint is already there, so the level was reached at or before `seconds`. NaN seconds:
// never within the run.
struct Reach {
  double seconds = kNaN;
  bool atFirst = false;
};
Reach timeToReach(const std::vector<CurvePoint>& curve, double mse);
std::string reachText(const Reach& reach);  // "840 ms", "≤ 31 ms", "never"

// The "## Time to quality" section of report.md: each method's time to reach every method's
// final MSE. Empty when no run has a curve.
std::string curvesMarkdown(const Prepared& p);

// ---- Charts (report_charts.cpp) -----------------------------------------------------------
// Horizontal bars of the mean of metric k on a log axis, with whiskers at mean ± sd.
std::string barChart(const Prepared& p, size_t k, const std::string& title);
// The "Time to quality" section of report.html: the log-log charts of MSE and relMSE against
// the methods' own wall seconds, their legend and the time-to-reach table. Empty when no run
// has a curve.
std::string curvesHtml(const Prepared& p);

// "ld wins on MSE with 1.2e-03 ± 3e-05 (4 seeds); bp has 2.41× its MSE."
std::string summarySentence(const Prepared& p);

// The self-contained report.html (report_html.cpp).
std::string reportHtml(const Prepared& p);

}  // namespace penumbra::report::detail
