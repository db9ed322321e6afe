// The `penumbra compare` report: statistics over seeds, the choice of crops where methods
// differ, and the writers of results.json, results.csv, curves.csv, report.md and the PNG
// images (the self-contained report.html is written by report_html.cpp). Every file goes through
// writeFileAtomically.
#include "report/report.h"

#include "core/stats.h"

#include "core/image_io.h"
#include "methods/factory.h"
#include "present/debug_maps.h"
#include "report/report_detail.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>

namespace penumbra::report {

// ---- Shared with report_html.cpp (declared in report_detail.h) ----------------------------
namespace detail {

// ---- Metrics table ------------------------------------------------------------------------
const std::array<Metric, 13> kMetrics = {{
    {"mse", [](const MethodRun& r) { return r.metrics.mse; }, Better::Lower},
    {"rel_mse", [](const MethodRun& r) { return r.metrics.relMse; }, Better::Lower},
    {"tone_mapped_mse", [](const MethodRun& r) { return r.metrics.toneMappedMse; }, Better::Lower},
    {"psnr", [](const MethodRun& r) { return r.metrics.psnr; }, Better::Higher},
    {"kept_spp", [](const MethodRun& r) { return r.keptSpp; }, Better::Unranked},
    {"traced_spp", [](const MethodRun& r) { return r.tracedSpp; }, Better::Unranked},
    {"seconds", [](const MethodRun& r) { return r.seconds; }, Better::Lower},
    {"trace", [](const MethodRun& r) { return r.trace; }, Better::Unranked},
    {"train", [](const MethodRun& r) { return r.train; }, Better::Unranked},
    {"select", [](const MethodRun& r) { return r.select; }, Better::Unranked},
    {"reconstruct", [](const MethodRun& r) { return r.reconstruct; }, Better::Unranked},
    {"network", [](const MethodRun& r) { return r.network; }, Better::Unranked},
    {"speckles", [](const MethodRun& r) { return r.speckleShare; }, Better::Lower},
}};

int winnerOf(const StatTable& stats, size_t k) {
  if (kMetrics[k].better == Better::Unranked) return -1;
  int best = -1;
  for (size_t m = 0; m < stats.size(); ++m) {
    const double v = stats[m][k].mean;
    if (std::isnan(v)) continue;
    if (best < 0) {
      best = int(m);
      continue;
    }
    const double b = stats[size_t(best)][k].mean;
    if (kMetrics[k].better == Better::Lower ? v < b : v > b) best = int(m);
  }
  return best;
}

// ---- Text formatting ----------------------------------------------------------------------
std::string sci(double v) {
  return std::isfinite(v) ? format("%.3e", v) : std::isnan(v) ? "n/a" : "inf";
}
std::string sciSd(double v) { return std::isfinite(v) ? format("%.1e", v) : "n/a"; }
std::string decibels(double v) {
  return std::isfinite(v) ? format("%.2f", v) : std::isnan(v) ? "n/a" : "inf";
}
std::string samples(double v) {
  if (!std::isfinite(v)) return "n/a";
  return std::abs(v - std::round(v)) < 1e-9 ? format("%.0f", v) : format("%.1f", v);
}
// A time, in milliseconds below a second, the sd in the mean's unit: "660 ms ± 60", "2.1 s".
std::string seconds(const Stat& s) {
  if (!std::isfinite(s.mean)) return "n/a";
  const bool ms = std::abs(s.mean) < 1;
  const double mean = ms ? s.mean * 1e3 : s.mean, sd = ms ? s.stddev * 1e3 : s.stddev;
  std::string text = format(std::abs(mean) < 100 ? "%.3g" : "%.0f", mean) + (ms ? " ms" : " s");
  // Equal times give an sd of rounding noise (1e-15), shown as the 0 it is.
  const double shownSd = std::abs(sd) <= 1e-9 * std::abs(mean) ? 0.0 : sd;
  if (s.count > 1)
    text += " ± " + (std::isfinite(sd) ? format("%.2g", shownSd) : std::string("n/a"));
  return text;
}
std::string ratio(double v) { return std::isfinite(v) ? format("%.2f×", v) : "n/a"; }

// "mean ± sd" (the sd only where there are at least two seeds).
std::string meanSd(const Stat& s, std::string (*mean)(double), std::string (*sd)(double)) {
  std::string text = mean(s.mean);
  if (s.count > 1) text += " ± " + sd(s.stddev);
  return text;
}

std::string htmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Inside a Markdown table cell: pipes and newlines would end the cell.
std::string markdownCell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else if (c == '<')
      out += "&lt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

// sRGB hex colour of a linear colour, for HTML and SVG.
std::string hexColor(vec3 linear) {
  const auto byte = [](float v) { return int(std::lround(255.0f * linearToSrgb(v))); };
  return format("#%02x%02x%02x", byte(linear.x), byte(linear.y), byte(linear.z));
}

vec3 cropColor(size_t index, size_t count) { return categoryColor(int(index), int(count)); }

std::span<const ReportMap> reportMaps() {
  static const std::vector<ReportMap> rows = [] {
    std::vector<ReportMap> out;
    for (const MapKind* kind : builtinMethods().maps())
      if (kind->report) out.push_back({*kind, kind->report});
    std::stable_sort(out.begin(), out.end(), [](const ReportMap& a, const ReportMap& b) {
      return a.report->order < b.report->order;
    });
    return out;
  }();
  return rows;
}

// ---- Summary sentence ---------------------------------------------------------------------
// "ld wins on MSE with 1.2e-03 ± 3e-05 (4 seeds); bp has 2.41× its MSE."
std::string summarySentence(const Prepared& p) {
  const CompareReport& r = p.r;
  if (r.methods.empty()) return "No methods were compared.";
  const auto sentenceFor = [&](size_t k, const char* name) {
    const int w = winnerOf(p.stats, k);
    if (w < 0) return std::string("No method has a finite ") + name + ".";
    const Stat& best = p.stats[size_t(w)][k];
    std::string s = r.methods[size_t(w)].label + (r.methods.size() > 1 ? " wins on " : ": ") +
                    name + (r.methods.size() > 1 ? " with " : " ") + meanSd(best, sci, sciSd);
    s += best.count == 1 ? " (1 seed)" : " (" + std::to_string(best.count) + " seeds)";
    bool first = true;
    for (size_t m = 0; m < r.methods.size(); ++m) {
      if (int(m) == w) continue;
      s += (first ? "; " : ", ") + r.methods[m].label + (first ? " has " : " ") +
           ratio(p.stats[m][k].mean / best.mean) + (first ? " its " + std::string(name) : "");
      first = false;
    }
    return s + ".";
  };
  std::string text = sentenceFor(kMse, "MSE");
  const int mseWinner = winnerOf(p.stats, kMse), toneWinner = winnerOf(p.stats, kToneMse);
  if (toneWinner >= 0 && toneWinner != mseWinner)
    text += " " + sentenceFor(kToneMse, "tone-mapped MSE");
  return text;
}

}  // namespace detail

using namespace detail;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---- Statistics ---------------------------------------------------------------------------
StatTable statsOf(const CompareReport& r) {
  StatTable table(r.methods.size());
  for (size_t m = 0; m < r.methods.size(); ++m)
    for (size_t k = 0; k < kMetrics.size(); ++k) {
      std::vector<double> values;
      for (const MethodRun& run : r.methods[m].runs) values.push_back(kMetrics[k].value(run));
      table[m][k] = summarize(values);
    }
  return table;
}

// ---- Text formatting ----------------------------------------------------------------------
// Shortest text that reads back to the same double ("inf", "nan" where not finite).
std::string exact(double v) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// The bitmap font draws printable ASCII only; spell the Greek letters the labels use.
std::string asciiForBitmap(const std::string& text) {
  static const std::array<std::pair<const char*, const char*>, 6> kReplacements = {
      {{"α", "a"}, {"σ", "s"}, {"μ", "u"}, {"±", "+-"}, {"×", "x"}, {"–", "-"}}};
  std::string out;
  for (size_t i = 0; i < text.size();) {
    bool replaced = false;
    for (const auto& [from, to] : kReplacements) {
      const size_t n = std::strlen(from);
      if (text.compare(i, n, from) == 0) {
        out += to, i += n, replaced = true;
        break;
      }
    }
    if (replaced) continue;
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      out += char(c), ++i;
    } else {  // skip the whole UTF-8 sequence
      out += '?', ++i;
      while (i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) ++i;
    }
  }
  return out;
}

// A file-name-safe version of `name` ("ld@64" -> "ld_64"), made unique among `used`.
// Crop stems use '-' only, so "crop_<crop>_<method>" can never be read two ways.
std::string uniqueStem(const std::string& name, const char* fallback, std::set<std::string>& used,
                       char replacement = '_') {
  std::string stem;
  for (char c : name)
    stem += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : replacement;
  if (stem.empty()) stem = fallback;
  const std::string base = stem;
  for (int i = 2; used.count(stem); ++i) stem = base + "-" + std::to_string(i);
  used.insert(stem);
  return stem;
}

// ---- Validation ---------------------------------------------------------------------------
void requireImageSize(const Image& image, const Image& reference, const std::string& what) {
  if (image.width != reference.width || image.height != reference.height ||
      image.pixels.size() != size_t(image.width) * image.height)
    throw std::invalid_argument(what + " is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + ", the reference " +
                                std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
}

void requireMapSize(const SnapshotMap& map, const Image& reference, const std::string& what) {
  const size_t expected = size_t(reference.width) * reference.height * map.channels();
  if (map.values.size() != expected)
    throw std::invalid_argument(what + " has " + std::to_string(map.values.size()) +
                                " values, the " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height) + " reference " +
                                std::to_string(expected));
}

void validate(const CompareReport& r) {
  const Image& ref = r.reference;
  if (ref.width <= 0 || ref.height <= 0 || ref.pixels.size() != size_t(ref.width) * ref.height)
    throw std::invalid_argument("the report has no reference image");
  std::set<std::string> labels;
  for (const MethodResult& m : r.methods) {
    const std::string name = "method '" + m.label + "'";
    if (!labels.insert(m.label).second)
      throw std::invalid_argument("method label '" + m.label + "' is used twice");
    requireImageSize(m.image, ref, name + " image");
    for (const SnapshotMap& map : m.maps)
      requireMapSize(map, ref, name + " " + map.id.name() + " map");
  }
  for (const Crop& c : r.crops)
    if (c.w <= 0 || c.h <= 0 || c.x < 0 || c.y < 0 || c.x + c.w > ref.width ||
        c.y + c.h > ref.height)
      throw std::invalid_argument("crop '" + c.name + "' lies outside the reference");
}

// ---- Pixel helpers ------------------------------------------------------------------------
Image cropOf(const Image& image, const Crop& c) {
  Image out(c.w, c.h);
  for (int y = 0; y < c.h; ++y)
    for (int x = 0; x < c.w; ++x) out.at(x, y) = image.at(c.x + x, c.y + y);
  return out;
}

Image upscaleNearest(const Image& image, int factor) {
  Image out(image.width * factor, image.height * factor);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.at(x, y) = image.at(x / factor, y / factor);
  return out;
}

std::vector<float> channelX(const Image& image) {
  std::vector<float> values(image.pixels.size());
  for (size_t i = 0; i < values.size(); ++i) values[i] = image.pixels[i].x;
  return values;
}

// The q-quantile (0..1) of the finite values, NaN if there are none.
double quantile(const std::vector<float>& values, double q) {
  const std::optional<float> v = nearestRankQuantile(values, float(q));
  return v ? double(*v) : kNaN;
}

void outlineRect(Image& image, const Crop& c, vec3 color, int thickness) {
  for (int t = 0; t < thickness; ++t) {
    const int x0 = c.x + t, y0 = c.y + t, x1 = c.x + c.w - 1 - t, y1 = c.y + c.h - 1 - t;
    if (x0 > x1 || y0 > y1) return;
    for (int x = x0; x <= x1; ++x) image.at(x, y0) = image.at(x, y1) = color;
    for (int y = y0; y <= y1; ++y) image.at(x0, y) = image.at(x1, y) = color;
  }
}

// ---- Files --------------------------------------------------------------------------------
void writeBytesAtomically(const std::string& path, const void* data, size_t size) {
  writeFileAtomically(path, [&](const std::string& tmpPath) {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(tmpPath.c_str(), "wb"), &std::fclose);
    if (!file) throw ImageIoError(path + ": cannot write file: " + std::strerror(errno));
    if (size > 0 && std::fwrite(data, 1, size, file.get()) != size)
      throw ImageIoError(path + ": cannot write file: " + std::strerror(errno));
    if (std::fclose(file.release()) != 0)
      throw ImageIoError(path + ": cannot write file: " + std::strerror(errno));
  });
}

void writeText(const fs::path& path, const std::string& text) {
  writeBytesAtomically(path.string(), text.data(), text.size());
}

Png savePng(const fs::path& dir, const std::string& name, const Image& image, float exposure) {
  Png png{"images/" + name + ".png", {}, image.width, image.height};
  const std::string path = (dir / png.file).string();
  try {
    png.bytes = encodePng8(image.width, image.height, 3, toSrgb8(image, exposure));
  } catch (const ImageIoError& e) {
    throw ImageIoError(path + ": " + e.what());
  }
  writeBytesAtomically(path, png.bytes.data(), png.bytes.size());
  return png;
}

// ---- Images -------------------------------------------------------------------------------
// A method's map as the report draws it: its values with the report's colour bar or labels.
Image reportMapPicture(const ReportMap& row, const SnapshotMap& map, int w, int h,
                       float sharedMax) {
  MapLegend legend;
  std::string title = row.report->title   ? row.report->title
                      : map.label.empty() ? "error estimate"
                                          : map.label;
  if (row.report->scale == ReportScale::Shared) {
    legend.maxValue = sharedMax;
  } else if (row.report->scale == ReportScale::OwnPercentile) {
    double top = quantile(map.values, 0.99);
    if (!(top > 0)) top = 1;
    legend.maxValue = float(top);
  } else {
    legend.kind = ColorMapKind::Categorical;
    for (const std::string& label : map.legend.categories)
      legend.categories.push_back(asciiForBitmap(label));
    float maxIndex = -1;
    for (float v : map.values)
      if (std::isfinite(v)) maxIndex = std::max(maxIndex, std::round(v));
    // Unlabelled categories get their index (a few: a wild value must not make millions).
    while (float(legend.categories.size()) <= std::min(maxIndex, 63.0f))
      legend.categories.push_back(std::to_string(legend.categories.size()));
  }
  return drawMapWithLegend(map.values, w, h, asciiForBitmap(title), legend);
}

void writeImages(const fs::path& dir, Prepared& p) {
  const CompareReport& r = p.r;
  const int w = r.reference.width, h = r.reference.height;
  std::vector<std::vector<float>> errors;
  std::vector<float> pooled;
  for (const MethodResult& m : r.methods) {
    double maxValue = 0;
    errors.push_back(channelX(errorImage(m.image, r.reference, maxValue)));
    pooled.insert(pooled.end(), errors.back().begin(), errors.back().end());
  }
  // The 99th percentile keeps one firefly from turning every other pixel dark.
  double scale = quantile(pooled, 0.99);
  if (!(scale > 0)) scale = quantile(pooled, 1.0);  // a few bad pixels: the largest error
  if (!(scale > 0)) scale = 1.0;                    // no error at all
  p.errorScale = float(scale);

  // The top of each Shared colour bar: the largest value of any method.
  std::vector<float> sharedMax(reportMaps().size(), 0.0f);
  for (size_t k = 0; k < reportMaps().size(); ++k) {
    for (const MethodResult& m : r.methods)
      if (const SnapshotMap* map = findMap(m.maps, reportMaps()[k].id))
        sharedMax[k] = std::max(sharedMax[k], finiteMax(map->values));
    if (!(sharedMax[k] > 0)) sharedMax[k] = 1;
  }

  p.reference = savePng(dir, "reference", r.reference, r.exposure);
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const MethodResult& method = r.methods[m];
    const std::string& stem = p.stems[m];
    MethodImages out;
    out.image = savePng(dir, stem, method.image, r.exposure);
    out.error = savePng(dir, stem + "_error",
                        drawMapWithLegend(errors[m], w, h, "rel. sq. error",
                                          MapLegend::sequential(0.0f, p.errorScale)),
                        0);
    for (size_t k = 0; k < reportMaps().size(); ++k) {
      const ReportMap& row = reportMaps()[k];
      const SnapshotMap* map = findMap(method.maps, row.id);
      out.maps.push_back(map ? savePng(dir, stem + "_" + row.report->stem,
                                       reportMapPicture(row, *map, w, h, sharedMax[k]), 0)
                             : Png{});
    }
    p.images.push_back(std::move(out));
  }

  // The reference with the crops outlined, for report.md (the HTML page draws them in SVG).
  Image overview = r.reference;
  const float gain = std::exp2(r.exposure);
  for (vec3& c : overview.pixels) c *= gain;
  const int thickness = std::min(w, h) >= 256 ? 2 : 1;
  for (size_t c = 0; c < p.crops.size(); ++c) {
    const vec3 color = cropColor(c, p.crops.size());
    outlineRect(overview, p.crops[c], color, thickness);
    drawText(overview, p.crops[c].x + thickness + 2, p.crops[c].y + thickness + 2,
             asciiForBitmap(p.crops[c].name), color, thickness);
  }
  p.overview = savePng(dir, "overview", overview, 0);

  for (size_t c = 0; c < p.crops.size(); ++c) {
    const Crop& crop = p.crops[c];
    const int factor = std::max(1, (128 + std::max(crop.w, crop.h) - 1) / std::max(crop.w, crop.h));
    const Image refCrop = cropOf(r.reference, crop);
    std::vector<Png> row = {savePng(dir, "crop_" + p.cropStems[c] + "_reference",
                                    upscaleNearest(refCrop, factor), r.exposure)};
    std::vector<double> mse;
    for (size_t m = 0; m < r.methods.size(); ++m) {
      const Image methodCrop = cropOf(r.methods[m].image, crop);
      mse.push_back(compareImages(methodCrop, refCrop).mse);
      row.push_back(savePng(dir, "crop_" + p.cropStems[c] + "_" + p.stems[m],
                            upscaleNearest(methodCrop, factor), r.exposure));
    }
    p.cropImages.push_back(std::move(row));
    p.cropMse.push_back(std::move(mse));
  }
}

// ---- results.csv and results.json ---------------------------------------------------------
std::string resultsCsv(const CompareReport& r) {
  std::string csv =
      "label,seed,spp,kept_spp,traced_spp,mse,rel_mse,tone_mapped_mse,psnr,seconds,trace,train,"
      "select,reconstruct,network\n";
  for (const MethodResult& m : r.methods)
    for (const MethodRun& run : m.runs) {
      csv += csvField(m.label) + "," + std::to_string(run.seed) + "," + std::to_string(m.spp);
      for (double v : {run.keptSpp, run.tracedSpp, run.metrics.mse, run.metrics.relMse,
                       run.metrics.toneMappedMse, run.metrics.psnr, run.seconds, run.trace,
                       run.train, run.select, run.reconstruct, run.network})
        csv += ',', csv += exact(v);
      csv += "\n";
    }
  return csv;
}

// One row per curve point of every run; only the header when no run has a curve.
std::string curvesCsv(const CompareReport& r) {
  std::string csv = "label,seed,checkpoint,seconds,mse,rel_mse,tone_mapped_mse,kept_spp\n";
  for (const MethodResult& m : r.methods)
    for (const MethodRun& run : m.runs)
      for (const CurvePoint& point : run.curve) {
        csv += csvField(m.label) + "," + std::to_string(run.seed) + "," +
               std::to_string(point.checkpoint);
        for (double v :
             {point.seconds, point.mse, point.relMse, point.toneMappedMse, point.keptSpp})
          csv += ',', csv += exact(v);
        csv += "\n";
      }
  return csv;
}

// JSON has no NaN or infinity: those become null.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json resultsJson(const Prepared& p) {
  const CompareReport& r = p.r;
  json j;
  j["title"] = r.title;
  j["scene"] = r.scenePath;
  j["reference"] = r.referencePath;
  j["mode"] = r.mode;
  j["command_line"] = r.commandLine;
  j["threads"] = r.threads;
  j["width"] = r.reference.width;
  j["height"] = r.reference.height;
  j["exposure"] = r.exposure;
  j["error_map_scale"] = p.errorScale;
  j["methods"] = json::array();
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const MethodResult& method = r.methods[m];
    json jm;
    jm["label"] = method.label;
    jm["description"] = method.description;
    jm["spp"] = method.spp;
    jm["seeds"] = method.runs.size();
    for (size_t k = 0; k < kMetrics.size(); ++k) {
      const Stat& s = p.stats[m][k];
      jm[kMetrics[k].key] = {
          {"mean", number(s.mean)}, {"stddev", number(s.stddev)}, {"count", s.count}};
    }
    jm["mse_ratio_to_first"] = number(p.stats[m][kMse].mean / p.stats[0][kMse].mean);
    jm["runs"] = json::array();
    for (const MethodRun& run : method.runs) {
      json jr = {{"seed", run.seed}};
      for (const Metric& metric : kMetrics) jr[metric.key] = number(metric.value(run));
      jr["max_abs_error"] = number(run.metrics.maxAbsError);
      jr["non_finite_pixels"] = run.metrics.nonFinite;
      jr["curve"] = json::array();
      for (const CurvePoint& point : run.curve)
        jr["curve"].push_back({{"checkpoint", point.checkpoint},
                               {"seconds", number(point.seconds)},
                               {"mse", number(point.mse)},
                               {"rel_mse", number(point.relMse)},
                               {"tone_mapped_mse", number(point.toneMappedMse)},
                               {"kept_spp", number(point.keptSpp)}});
      jm["runs"].push_back(jr);
    }
    const MethodImages& images = p.images[m];
    json files = {{"image", images.image.file}, {"error", images.error.file}};
    for (size_t k = 0; k < reportMaps().size(); ++k)
      if (!images.maps[k].file.empty())
        files[reportMaps()[k].report->jsonKey] = images.maps[k].file;
    jm["images"] = files;
    j["methods"].push_back(jm);
  }
  json winners = json::object();
  for (size_t k = 0; k < kMetrics.size(); ++k) {
    if (kMetrics[k].better == Better::Unranked) continue;
    const int w = winnerOf(p.stats, k);
    winners[kMetrics[k].key] = w < 0 ? json(nullptr) : json(r.methods[size_t(w)].label);
  }
  j["winner"] = winners;
  j["crops"] = json::array();
  for (size_t c = 0; c < p.crops.size(); ++c) {
    const Crop& crop = p.crops[c];
    json mse = json::object();
    for (size_t m = 0; m < r.methods.size(); ++m) mse[r.methods[m].label] = number(p.cropMse[c][m]);
    j["crops"].push_back({{"name", crop.name},
                          {"x", crop.x},
                          {"y", crop.y},
                          {"w", crop.w},
                          {"h", crop.h},
                          {"mse", mse}});
  }
  return j;
}

// ---- report.md ----------------------------------------------------------------------------
std::string reportMarkdown(const Prepared& p) {
  const CompareReport& r = p.r;
  std::string md = "# " + (r.title.empty() ? std::string("Comparison") : r.title) + "\n\n";
  md += "- Mode: " + r.mode + "\n- Scene: `" + r.scenePath + "`\n- Reference: `" + r.referencePath +
        "`\n- Size: " + std::to_string(r.reference.width) + "x" +
        std::to_string(r.reference.height) + ", threads: " + std::to_string(r.threads) + "\n\n";
  if (!r.commandLine.empty()) md += "```\n" + r.commandLine + "\n```\n\n";
  const std::string first = r.methods.empty() ? "" : markdownCell(r.methods[0].label);
  md +=
      "| method | description | kept spp | traced spp | MSE | relMSE | tone-mapped MSE | PSNR (dB) "
      "| time | MSE / " +
      first + " |\n|---|---|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const auto& s = p.stats[m];
    md += "| " + markdownCell(r.methods[m].label) + " | " + markdownCell(r.methods[m].description) +
          " | " + samples(s[kKept].mean) + " | " + samples(s[kTraced].mean) + " | " +
          meanSd(s[kMse], sci, sciSd) + " | " + meanSd(s[kRelMse], sci, sciSd) + " | " +
          meanSd(s[kToneMse], sci, sciSd) + " | " + meanSd(s[kPsnr], decibels, decibels) + " | " +
          seconds(s[kSeconds]) + " | " + ratio(s[kMse].mean / p.stats[0][kMse].mean) + " |\n";
  }
  md += "\n" + summarySentence(p) + "\n\n" + curvesMarkdown(p) + "## Images\n\n| reference |";
  for (const MethodResult& m : r.methods) md += " " + markdownCell(m.label) + " |";
  md += "\n|---|";
  for (size_t m = 0; m < r.methods.size(); ++m) md += "---|";
  md += "\n| ![reference](" + p.reference.file + ") |";
  for (size_t m = 0; m < r.methods.size(); ++m)
    md += " ![" + markdownCell(r.methods[m].label) + "](" + p.images[m].image.file + ") |";
  const auto mapRow = [&](const char* name, auto which) {
    std::string row = "\n| " + std::string(name) + " |";
    bool any = false;
    for (const MethodImages& images : p.images) {
      const Png& png = which(images);
      any = any || !png.file.empty();
      row += png.file.empty() ? std::string(" |")
                              : " ![" + std::string(name) + "](" + png.file + ") |";
    }
    return any ? row : std::string();
  };
  md += mapRow("error", [](const MethodImages& i) -> const Png& { return i.error; });
  for (size_t k = 0; k < reportMaps().size(); ++k)
    md += mapRow(reportMaps()[k].report->rowName,
                 [k](const MethodImages& i) -> const Png& { return i.maps[k]; });
  md += "\n\nError maps: relative squared error, colour bar 0 to " + sci(p.errorScale) +
        " (99th percentile over all methods).\n";
  if (!p.crops.empty()) {
    md += "\n## Crops\n\n![overview](" + p.overview.file + ")\n\n| crop | reference |";
    for (const MethodResult& m : r.methods) md += " " + markdownCell(m.label) + " |";
    md += "\n|---|---|";
    for (size_t m = 0; m < r.methods.size(); ++m) md += "---|";
    for (size_t c = 0; c < p.crops.size(); ++c) {
      const Crop& crop = p.crops[c];
      md += "\n| " + markdownCell(crop.name) +
            format(" (%d, %d, %dx%d)", crop.x, crop.y, crop.w, crop.h) + " | ![](" +
            p.cropImages[c][0].file + ") |";
      for (size_t m = 0; m < r.methods.size(); ++m)
        md += " ![](" + p.cropImages[c][m + 1].file + ")<br>MSE " + sci(p.cropMse[c][m]) + " |";
    }
    md += "\n";
  }
  md +=
      "\nAlso: [report.html](report.html), [results.json](results.json), "
      "[results.csv](results.csv), [curves.csv](curves.csv).\n";
  return md;
}

// Start offsets of the windows along one axis: stride apart, plus one flush with the end.
std::vector<int> windowStarts(int extent, int size, int stride) {
  std::vector<int> starts;
  for (int s = 0; s + size <= extent; s += stride) starts.push_back(s);
  if (starts.empty() || starts.back() != extent - size) starts.push_back(extent - size);
  return starts;
}

}  // namespace

Stat summarize(const std::vector<double>& values) {
  Stat s;
  double sum = 0;
  for (double v : values)
    if (!std::isnan(v)) sum += v, ++s.count;
  if (s.count == 0) {
    s.mean = kNaN;
    return s;
  }
  s.mean = sum / s.count;
  if (s.count <= 1) return s;
  if (!std::isfinite(s.mean)) {  // infinite values: spread is 0 only if they all agree
    for (double v : values)
      if (!std::isnan(v) && v != s.mean) s.stddev = kNaN;
    return s;
  }
  double squares = 0;
  for (double v : values)
    if (!std::isnan(v)) squares += (v - s.mean) * (v - s.mean);
  s.stddev = std::sqrt(squares / (s.count - 1));
  return s;
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(bytes[i]) << 16 | uint32_t(bytes[i + 1]) << 8 | bytes[i + 2];
    for (int shift : {18, 12, 6, 0}) out += kAlphabet[(v >> shift) & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(bytes[i]) << 16;
    out += kAlphabet[v >> 18 & 63], out += kAlphabet[v >> 12 & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = uint32_t(bytes[i]) << 16 | uint32_t(bytes[i + 1]) << 8;
    out += kAlphabet[v >> 18 & 63], out += kAlphabet[v >> 12 & 63], out += kAlphabet[v >> 6 & 63];
    out += '=';
  }
  return out;
}

std::vector<Crop> chooseCrops(const CompareReport& r, int count, int size) {
  const int w = r.reference.width, h = r.reference.height;
  if (w <= 0 || h <= 0 || count <= 0) return {};
  for (const MethodResult& m : r.methods)
    requireImageSize(m.image, r.reference, "method '" + m.label + "' image");
  if (size <= 0) size = std::max(16, std::min(w, h) / 6);
  size = std::min({size, w, h});

  // Summed-area table of each method's per-pixel relative squared error (non-finite: 0).
  const size_t pitch = size_t(w) + 1;
  std::vector<std::vector<double>> tables;
  for (const MethodResult& m : r.methods) {
    double maxValue = 0;
    const Image error = errorImage(m.image, r.reference, maxValue);
    std::vector<double> table(pitch * (size_t(h) + 1), 0.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double e = error.at(x, y).x;
        table[(y + 1) * pitch + x + 1] = (std::isfinite(e) ? e : 0.0) + table[y * pitch + x + 1] +
                                         table[(y + 1) * pitch + x] - table[y * pitch + x];
      }
    tables.push_back(std::move(table));
  }

  struct Candidate {
    int x, y;
    double score;
  };
  std::vector<Candidate> candidates;
  const int stride = std::max(1, size / 2);
  const double area = double(size) * size;
  for (int y : windowStarts(h, size, stride))
    for (int x : windowStarts(w, size, stride)) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
      for (const auto& t : tables) {
        const size_t x1 = size_t(x) + size, y1 = size_t(y) + size;
        const double mean =
            (t[y1 * pitch + x1] - t[y * pitch + x1] - t[y1 * pitch + x] + t[y * pitch + x]) / area;
        lo = std::min(lo, mean), hi = std::max(hi, mean), sum += mean;
      }
      const double score = tables.empty() ? 0.0 : (hi - lo) + sum / double(tables.size());
      candidates.push_back({x, y, score});
    }
  // Stable: equal scores keep raster order, so the choice is deterministic.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });

  std::vector<Crop> crops;
  for (const Candidate& c : candidates) {
    if (int(crops.size()) == count) break;
    const bool overlaps = std::any_of(crops.begin(), crops.end(), [&](const Crop& o) {
      return c.x < o.x + o.w && o.x < c.x + size && c.y < o.y + o.h && o.y < c.y + size;
    });
    if (overlaps) continue;
    const size_t i = crops.size();
    const std::string name = i < 26 ? std::string(1, char('A' + i)) : "C" + std::to_string(i + 1);
    crops.push_back({name, c.x, c.y, size, size});
  }
  return crops;
}

void writeReport(const std::string& dir, const CompareReport& r) {
  validate(r);
  Prepared p(r);
  p.crops = r.crops.empty() ? chooseCrops(r) : r.crops;
  p.stats = statsOf(r);
  for (const MethodResult& m : r.methods) p.meanCurves.push_back(meanCurve(m));
  std::set<std::string> usedStems = {"reference", "overview"}, usedCropStems;
  for (const MethodResult& m : r.methods)
    p.stems.push_back(uniqueStem(m.label, "method", usedStems));
  for (const Crop& c : p.crops)
    p.cropStems.push_back(uniqueStem(c.name, "crop", usedCropStems, '-'));

  const fs::path root(dir);
  std::error_code ec;
  fs::create_directories(root / "images", ec);
  if (ec)
    throw ImageIoError((root / "images").string() + ": cannot create directory: " + ec.message());

  writeImages(root, p);
  writeText(root / "results.csv", resultsCsv(r));
  writeText(root / "curves.csv", curvesCsv(r));
  writeText(root / "results.json", resultsJson(p).dump(2) + "\n");
  writeText(root / "report.md", reportMarkdown(p));
  writeText(root / "report.html", reportHtml(p));
}

}  // namespace penumbra::report
