// The report.html of `penumbra compare`: one self-contained page (images embedded as data:
// URLs, inline CSS and SVG, no network) with the time-to-quality curves, the results table
// and charts, the images with the crops outlined, the zoomed crops and each method's maps (the
// charts are drawn by report_charts.cpp).
#include "report/report_detail.h"

#include "present/debug_maps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace penumbra::report::detail {
namespace {

const char* const kCss = R"(
:root { color-scheme: dark; }
body { margin: 0; padding: 24px 32px 48px; background: #1b1b1d; color: #e2e2e2;
       font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; }
h1 { font-size: 22px; margin: 0 0 10px; }
h2 { font-size: 17px; margin: 34px 0 12px; padding-bottom: 4px; border-bottom: 1px solid #333; }
h3 { font-size: 14px; margin: 20px 0 8px; color: #c8c8c8; }
code { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 12.5px;
       background: #26262a; padding: 1px 5px; border-radius: 3px; }
.meta { display: grid; grid-template-columns: max-content 1fr; gap: 3px 16px; margin: 0; }
.meta dt { color: #9a9a9a; } .meta dd { margin: 0; }
.cmd { white-space: pre-wrap; word-break: break-all; }
.summary { font-size: 15px; background: #212a22; border-left: 3px solid #6fbf73;
           padding: 10px 14px; margin: 20px 0; max-width: 70em; }
table { border-collapse: collapse; font-variant-numeric: tabular-nums; }
th, td { padding: 5px 10px; border-bottom: 1px solid #303033; text-align: right; white-space: nowrap; }
th { color: #a8a8a8; font-weight: 600; border-bottom: 1px solid #555; }
.l { text-align: left; }
td.best { color: #a6eaa9; font-weight: 700; background: #223123; }
.sd { color: #8c8c8c; font-weight: 400; }
.note { color: #9a9a9a; font-size: 12.5px; }
.row { display: flex; flex-wrap: wrap; gap: 16px; align-items: flex-start; }
figure { margin: 0; }
figcaption { font-size: 12.5px; color: #bdbdbd; margin-top: 5px; }
figcaption b { color: #e8e8e8; }
.frame { position: relative; display: inline-block; line-height: 0; }
.frame svg { position: absolute; left: 0; top: 0; width: 100%; height: 100%; overflow: visible; }
img { display: block; background: #000; }
img.px { image-rendering: pixelated; }
.crop img { border: 2px solid var(--c); }
.crop.best figcaption { color: #a6eaa9; font-weight: 700; }
.tag { display: inline-block; min-width: 1.4em; text-align: center; border-radius: 3px;
       color: #111; font-weight: 700; margin-right: 6px; }
.swatch { display: inline-block; width: 10px; height: 10px; margin: 0 4px 0 10px;
          vertical-align: -1px; border: 1px solid #777; }
.charts { display: flex; flex-wrap: wrap; gap: 24px; margin-top: 16px; }
svg.chart text { fill: #cfcfcf; font: 12px system-ui, sans-serif; }
svg.chart .axis { fill: #8c8c8c; font-size: 11px; }
.legend { margin: 10px 0 0; font-weight: 600; }
.legend .line { display: inline-block; width: 22px; height: 4px; border-radius: 2px;
                margin: 0 6px 0 16px; vertical-align: 3px; }
.legend .line:first-child { margin-left: 0; }
footer { margin-top: 40px; color: #777; font-size: 12px; }
)";

std::string dataUrl(const Png& png) { return "data:image/png;base64," + base64(png.bytes); }

// How much the full images are scaled on the page: small renders are enlarged by a whole
// factor (drawn pixelated), large ones shrunk so that several fit side by side.
struct DisplayScale {
  double factor = 1;
  bool pixelated = false;
};

DisplayScale displayScaleFor(int width) {
  if (width < 240) return {std::ceil(240.0 / width), true};
  return {std::min(1.0, 420.0 / width), false};
}

std::string imgTag(const Png& png, double factor, bool pixelated, const std::string& alt) {
  return format("<img width=\"%d\" height=\"%d\"", int(std::lround(png.width * factor)),
                int(std::lround(png.height * factor))) +
         (pixelated ? " class=\"px\"" : "") + " alt=\"" + htmlEscape(alt) + "\" src=\"" +
         dataUrl(png) + "\">";
}

// A full image with the crop rectangles drawn over it in SVG (crisp at any zoom).
std::string framedImage(const Prepared& p, const Png& png, const DisplayScale& s,
                        const std::string& alt) {
  const int w = p.r.reference.width, h = p.r.reference.height;
  std::string html = "<div class=\"frame\">" + imgTag(png, s.factor, s.pixelated, alt);
  if (!p.crops.empty()) {
    html += format("<svg viewBox=\"0 0 %d %d\" preserveAspectRatio=\"none\">", w, h);
    const double fontSize = 13.0 / s.factor;  // 13 px on the page
    for (size_t c = 0; c < p.crops.size(); ++c) {
      const Crop& crop = p.crops[c];
      const std::string color = hexColor(cropColor(c, p.crops.size()));
      html += format(
                  "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" "
                  "stroke-width=\"2\" vector-effect=\"non-scaling-stroke\" stroke=\"",
                  crop.x, crop.y, crop.w, crop.h) +
              color + "\"/>";
      html += format(
                  "<text x=\"%.2f\" y=\"%.2f\" font-size=\"%.2f\" font-weight=\"700\" "
                  "font-family=\"sans-serif\" stroke=\"#000\" stroke-width=\"%.2f\" "
                  "paint-order=\"stroke\" fill=\"",
                  crop.x + 3.0 / s.factor, crop.y + 3.0 / s.factor + fontSize, fontSize,
                  2.5 / s.factor) +
              color + "\">" + htmlEscape(crop.name) + "</text>";
    }
    html += "</svg>";
  }
  return html + "</div>";
}

// The maps: one section per kind (the error, then the rows of reportMaps()), each with only
// the methods that have it.
std::string mapSections(const Prepared& p, const DisplayScale& scale) {
  const CompareReport& r = p.r;
  std::string html;
  const auto mapRow = [&](const std::string& heading, const std::string& note, auto pngOf,
                          const ReportMap* map) {
    std::string row;
    for (size_t m = 0; m < r.methods.size(); ++m) {
      const Png& png = pngOf(p.images[m]);
      if (png.file.empty()) continue;
      std::string caption = "<b>" + htmlEscape(r.methods[m].label) + "</b>";
      const SnapshotMap* values = map ? findMap(r.methods[m].maps, map->id) : nullptr;
      if (values && map->report->scale == ReportScale::OwnPercentile && !values->label.empty())
        caption += " · " + htmlEscape(values->label);
      if (values && map->report->scale == ReportScale::Categories) {
        const auto& labels = values->legend.categories;
        caption += "<br>";
        for (size_t i = 0; i < labels.size(); ++i)
          caption += "<span class=\"swatch\" style=\"background:" +
                     hexColor(categoryColor(int(i), int(labels.size()))) + "\"></span>" +
                     htmlEscape(labels[i]);
      }
      // A map of a tiny render is padded to the legend's width: enlarge it less.
      const double factor =
          scale.pixelated ? std::min(scale.factor, std::max(1.0, std::floor(480.0 / png.width)))
                          : scale.factor;
      row += "<figure>" + imgTag(png, factor, scale.pixelated, heading) + "<figcaption>" + caption +
             "</figcaption></figure>";
    }
    if (row.empty()) return;
    html += "<section><h2>" + htmlEscape(heading) + "</h2>" +
            (note.empty() ? "" : "<p class=\"note\">" + htmlEscape(note) + "</p>") +
            "<div class=\"row\">" + row + "</div></section>\n";
  };
  mapRow(
      "Per-pixel error",
      "Relative squared error against the reference (first seed), one "
      "shared colour bar from 0 to " +
          sci(p.errorScale) + " (99th percentile over all methods).",
      [](const MethodImages& i) -> const Png& { return i.error; }, nullptr);
  for (size_t k = 0; k < reportMaps().size(); ++k)
    mapRow(
        reportMaps()[k].report->heading, reportMaps()[k].report->note,
        [k](const MethodImages& i) -> const Png& { return i.maps[k]; }, &reportMaps()[k]);
  return html;
}

}  // namespace

std::string reportHtml(const Prepared& p) {
  const CompareReport& r = p.r;
  const std::string title = r.title.empty() ? std::string("Comparison") : r.title;
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
      "<title>penumbra compare: " +
      htmlEscape(title) + "</title><style>" + kCss + "</style></head><body>\n";
  // Header.
  html += "<header><h1>" + htmlEscape(title) + "</h1><dl class=\"meta\">";
  const auto metaRow = [&](const char* name, const std::string& value, bool code) {
    if (value.empty()) return;
    html += std::string("<dt>") + name + "</dt><dd>" + (code ? "<code class=\"cmd\">" : "") +
            htmlEscape(value) + (code ? "</code>" : "") + "</dd>";
  };
  size_t seeds = 0;
  for (const MethodResult& m : r.methods) seeds = std::max(seeds, m.runs.size());
  metaRow("mode", r.mode, false);
  metaRow("scene", r.scenePath, true);
  metaRow("reference", r.referencePath, true);
  metaRow("image",
          format("%d × %d, exposure %+.1f stops", r.reference.width, r.reference.height,
                 double(r.exposure)),
          false);
  metaRow("runs",
          std::to_string(seeds) + (seeds == 1 ? " seed" : " seeds") + " per method, " +
              std::to_string(r.threads) + " threads",
          false);
  metaRow("command", r.commandLine, true);
  html += "</dl></header>\n<p class=\"summary\">" + htmlEscape(summarySentence(p)) + "</p>\n";
  html += curvesHtml(p);

  // Results table, best value per ranked column highlighted.
  const std::string first = r.methods.empty() ? "" : htmlEscape(r.methods[0].label);
  html +=
      "<section><h2>Results</h2><table><tr><th class=\"l\">method</th><th class=\"l\">"
      "description</th><th>spp</th><th>kept spp</th><th>traced spp</th><th>MSE</th>"
      "<th>relMSE</th><th>tone-mapped MSE</th><th>PSNR (dB)</th><th>time</th><th>MSE / " +
      first + "</th></tr>\n";
  std::array<int, kMetrics.size()> best{};
  for (size_t k = 0; k < kMetrics.size(); ++k) best[k] = winnerOf(p.stats, k);
  // `text` is "mean ± sd" (see meanSd); the sd is drawn dimmer.
  const auto cell = [&](size_t m, size_t k, const std::string& text) {
    std::string escaped = htmlEscape(text);
    const size_t pm = escaped.find(" ± ");
    if (pm != std::string::npos)
      escaped = escaped.substr(0, pm) + " <span class=\"sd\">" + escaped.substr(pm + 1) + "</span>";
    const bool isBest = best[k] == int(m) && r.methods.size() > 1;
    return (isBest ? "<td class=\"best\">" : "<td>") + escaped + "</td>";
  };
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const auto& s = p.stats[m];
    html += "<tr><td class=\"l\"><b>" + htmlEscape(r.methods[m].label) +
            "</b></td><td class=\"l\">" + htmlEscape(r.methods[m].description) + "</td><td>" +
            std::to_string(r.methods[m].spp) + "</td><td>" + samples(s[kKept].mean) + "</td><td>" +
            samples(s[kTraced].mean) + "</td>" + cell(m, kMse, meanSd(s[kMse], sci, sciSd)) +
            cell(m, kRelMse, meanSd(s[kRelMse], sci, sciSd)) +
            cell(m, kToneMse, meanSd(s[kToneMse], sci, sciSd)) +
            cell(m, kPsnr, meanSd(s[kPsnr], decibels, decibels)) +
            cell(m, kSeconds, seconds(s[kSeconds])) + "<td>" +
            htmlEscape(ratio(s[kMse].mean / p.stats[0][kMse].mean)) + "</td></tr>\n";
  }
  html +=
      "</table><p class=\"note\">Mean ± sample standard deviation over seeds; the best value "
      "of each column is highlighted. relMSE divides by ref² + 0.01; PSNR is on values "
      "clamped to [0, 1].</p>\n";
  html +=
      "<h3>Time per phase</h3><table><tr><th class=\"l\">method</th><th>trace</th>"
      "<th>train</th><th>select</th><th>reconstruct</th><th>total</th></tr>\n";
  for (size_t m = 0; m < r.methods.size(); ++m) {
    html += "<tr><td class=\"l\"><b>" + htmlEscape(r.methods[m].label) + "</b></td>";
    for (size_t k :
         {size_t(kTrace), size_t(kTrain), size_t(kSelect), size_t(kReconstruct), size_t(kSeconds)})
      html += "<td>" + htmlEscape(seconds(p.stats[m][k])) + "</td>";
    html += "</tr>\n";
  }
  html += "</table><div class=\"charts\">" + barChart(p, kMse, "MSE (log scale, ± sd)") +
          barChart(p, kToneMse, "Tone-mapped MSE (log scale, ± sd)") + "</div></section>\n";

  // Full images side by side, crops outlined.
  const DisplayScale scale = displayScaleFor(r.reference.width);
  html += "<section><h2>Images</h2><div class=\"row\"><figure>" +
          framedImage(p, p.reference, scale, "reference") +
          "<figcaption><b>reference</b></figcaption></figure>";
  for (size_t m = 0; m < r.methods.size(); ++m)
    html += "<figure>" + framedImage(p, p.images[m].image, scale, r.methods[m].label) +
            "<figcaption><b>" + htmlEscape(r.methods[m].label) + "</b> · MSE " +
            htmlEscape(sci(r.methods[m].runs.empty() ? kNaN : r.methods[m].runs[0].metrics.mse)) +
            " (first seed)</figcaption></figure>";
  html += "</div></section>\n";

  // Zoomed crops, one row per crop.
  if (!p.crops.empty()) {
    html += "<section><h2>Crops</h2>";
    for (size_t c = 0; c < p.crops.size(); ++c) {
      const Crop& crop = p.crops[c];
      const std::string color = hexColor(cropColor(c, p.crops.size()));
      html += "<h3><span class=\"tag\" style=\"background:" + color + "\">" +
              htmlEscape(crop.name) + "</span>" +
              format("x %d, y %d, %d × %d px", crop.x, crop.y, crop.w, crop.h) +
              "</h3><div class=\"row\">";
      int bestCrop = -1;
      for (size_t m = 0; m < p.cropMse[c].size(); ++m)
        if (std::isfinite(p.cropMse[c][m]) &&
            (bestCrop < 0 || p.cropMse[c][m] < p.cropMse[c][size_t(bestCrop)]))
          bestCrop = int(m);
      const auto tile = [&](const Png& png, const std::string& caption, bool isBest) {
        html += std::string("<figure class=\"crop") + (isBest ? " best" : "") +
                "\" style=\"--c:" + color + "\">" + imgTag(png, 1, true, caption) + "<figcaption>" +
                htmlEscape(caption) + "</figcaption></figure>";
      };
      tile(p.cropImages[c][0], "reference", false);
      for (size_t m = 0; m < r.methods.size(); ++m)
        tile(p.cropImages[c][m + 1], r.methods[m].label + " · MSE " + sci(p.cropMse[c][m]),
             int(m) == bestCrop && r.methods.size() > 1);
      html += "</div>";
    }
    html += "</section>\n";
  }

  html += mapSections(p, scale);

  html +=
      "<footer>Written by penumbra compare. Beside this page: results.json, results.csv, "
      "report.md and the PNG files in images/.</footer>\n</body></html>\n";
  return html;
}

}  // namespace penumbra::report::detail
