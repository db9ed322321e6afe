// The SVG charts of the `penumbra compare` report (report.html): the bar charts of the
// results section and the time-to-quality section's log-log curves, all on one logarithmic
// axis (LogAxis), and that section's time-to-reach table.
#include "report/report_detail.h"

#include "present/debug_maps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::report::detail {
namespace {

// A logarithmic axis: values in [lo, hi] onto pixels [from, to] (to < from for a y axis, up).
// The bounds come from the positive finite values, widened to whole decades (Snap::Decades, at
// least one apart: the bars start at the left end) or by 4% of the span on each side
// (Snap::Padded, the curves: no empty decades), at least a factor of 1.5 each way when the
// values are all equal.
class LogAxis {
 public:
  enum class Snap { Decades, Padded };
  struct Tick {
    double value;
    bool major;     // a power of ten
    bool labelled;  // drawn with its value
  };

  // nullopt when no value is positive and finite.
  static std::optional<LogAxis> over(const std::vector<double>& values, Snap snap, double from,
                                     double to) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (double v : values)
      if (v > 0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!(hi > 0)) return std::nullopt;
    LogAxis axis;
    axis.from_ = from, axis.to_ = to;
    if (snap == Snap::Decades) {
      const int lo10 = int(std::floor(std::log10(lo)));
      const int hi10 = std::max(lo10 + 1, int(std::ceil(std::log10(hi))));
      axis.lo_ = std::pow(10.0, lo10), axis.hi_ = std::pow(10.0, hi10);
    } else if (hi > lo) {
      const double pad = std::pow(hi / lo, 0.04);
      axis.lo_ = lo / pad, axis.hi_ = hi * pad;
    } else {
      axis.lo_ = lo / 1.5, axis.hi_ = hi * 1.5;
    }
    return axis;
  }

  // The pixel of v, clamped to the axis.
  double at(double v) const {
    const double t = v > 0 ? std::log(v / lo_) / std::log(hi_ / lo_) : 0.0;
    return from_ + (to_ - from_) * std::clamp(t, 0.0, 1.0);
  }

  // Within 0.7 decades every 1..9 × 10^k, labelled; within 2.3 decades 1, 2 and 5 × 10^k,
  // labelled; within five decades 1, 2 and 5 × 10^k, the powers of ten labelled; beyond, the
  // powers of ten (every other one beyond eight decades).
  std::vector<Tick> ticks() const {
    const double span = std::log10(hi_ / lo_);
    const int e0 = int(std::floor(std::log10(lo_) + 1e-9)),
              e1 = int(std::ceil(std::log10(hi_) - 1e-9));
    std::vector<Tick> ticks;
    for (int e = e0; e <= e1; ++e)
      for (int m = 1; m <= 9; ++m) {
        const double v = m * std::pow(10.0, e);
        if (v < lo_ * (1 - 1e-9) || v > hi_ * (1 + 1e-9)) continue;
        const bool major = m == 1, oneTwoFive = m == 1 || m == 2 || m == 5;
        if (span <= 0.7)
          ticks.push_back({v, major, true});
        else if (span <= 2.3 + 1e-9 && oneTwoFive)
          ticks.push_back({v, major, true});
        else if (span <= 5 + 1e-9 && oneTwoFive)
          ticks.push_back({v, major, major});
        else if (span > 5 + 1e-9 && major && (span <= 8 || (e - e0) % 2 == 0))
          ticks.push_back({v, true, true});
      }
    return ticks;
  }

 private:
  double lo_ = 1, hi_ = 10, from_ = 0, to_ = 1;
};

// A tick's value: "1e-3", "2e-3".
std::string sciTick(double v) {
  int e = int(std::floor(std::log10(v) + 1e-9));
  long m = std::lround(v / std::pow(10.0, e));
  if (m >= 10) m /= 10, ++e;
  return format("%lde%d", m, e);
}

// A tick's time: "20 ms", "0.5 s", "10 s".
std::string secondsTick(double v) {
  if (v >= 1 - 1e-9) return format("%g s", v);
  if (v >= 1e-3 * (1 - 1e-9)) return format("%g ms", v * 1e3);
  return format("%g µs", v * 1e6);
}

std::string methodColor(size_t m, size_t count) {
  return hexColor(categoryColor(int(m), int(count)));
}

bool drawable(double seconds, double value) {
  return seconds > 0 && std::isfinite(seconds) && value > 0 && std::isfinite(value);
}

// "x,y x,y ...": the drawable points of a curve in order of time.
std::string polylinePoints(std::vector<CurvePoint> curve, double CurvePoint::*value,
                           const LogAxis& x, const LogAxis& y) {
  std::stable_sort(curve.begin(), curve.end(),
                   [](const CurvePoint& a, const CurvePoint& b) { return a.seconds < b.seconds; });
  std::string points;
  for (const CurvePoint& q : curve)
    if (drawable(q.seconds, q.*value)) {
      if (!points.empty()) points += ' ';
      points += format("%.1f,%.1f", x.at(q.seconds), y.at(q.*value));
    }
  return points;
}

// The grid, tick labels, frame and axis names of a curve chart.
std::string curveAxes(const LogAxis& x, const LogAxis& y, int left, int top, int plotWidth,
                      int plotHeight, const std::string& yName) {
  const int bottom = top + plotHeight, right = left + plotWidth;
  std::string svg;
  for (const LogAxis::Tick& tick : x.ticks()) {
    const double px = x.at(tick.value);
    svg += format("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"%s\"/>", px, top, px,
                  bottom, tick.major ? "#46464c" : "#2e2e33");
    if (tick.labelled)
      svg += format("<text class=\"axis\" x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">", px,
                    bottom + 16) +
             secondsTick(tick.value) + "</text>";
  }
  for (const LogAxis::Tick& tick : y.ticks()) {
    const double py = y.at(tick.value);
    svg += format("<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"%s\"/>", left, py,
                  right, py, tick.major ? "#46464c" : "#2e2e33");
    if (tick.labelled)
      svg += format("<text class=\"axis\" x=\"%d\" y=\"%.1f\" text-anchor=\"end\">", left - 6,
                    py + 4) +
             sciTick(tick.value) + "</text>";
  }
  svg += format(
      "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"#5a5a60\"/>", left,
      top, plotWidth, plotHeight);
  svg += format("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">", left + plotWidth / 2.0,
                bottom + 38) +
         "wall seconds, the method's own (log)</text>";
  svg += format("<text transform=\"rotate(-90)\" x=\"%.1f\" y=\"14\" text-anchor=\"middle\">",
                -(top + plotHeight / 2.0)) +
         htmlEscape(yName) + " (log)</text>";
  return svg;
}

// A log-log chart of one metric of the curves against the methods' own wall seconds: per
// method each seed's curve thin (with two or more seeds), the mean over seeds (meanCurves)
// bold, with a marker per checkpoint whose tooltip gives its values.
std::string curveChart(const Prepared& p, double CurvePoint::*value, const std::string& key,
                       const std::string& title, const std::string& yName) {
  const CompareReport& r = p.r;
  std::vector<double> xs, ys;
  const auto collect = [&](const std::vector<CurvePoint>& curve) {
    for (const CurvePoint& q : curve)
      if (drawable(q.seconds, q.*value)) xs.push_back(q.seconds), ys.push_back(q.*value);
  };
  for (size_t m = 0; m < r.methods.size(); ++m) {
    for (const MethodRun& run : r.methods[m].runs) collect(run.curve);
    collect(p.meanCurves[m]);
  }
  const int left = 70, plotWidth = 430, right = 16, top = 32, plotHeight = 260;
  const int width = left + plotWidth + right, height = top + plotHeight + 48;
  const auto x = LogAxis::over(xs, LogAxis::Snap::Padded, left, left + plotWidth);
  const auto y = LogAxis::over(ys, LogAxis::Snap::Padded, top + plotHeight, top);
  if (!x || !y) return "";
  std::string svg = format(
                        "<svg class=\"chart curve\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d "
                        "%d\" role=\"img\" data-metric=\"",
                        width, height, width, height) +
                    key + "\"><text x=\"0\" y=\"16\" font-weight=\"700\">" + htmlEscape(title) +
                    "</text>";
  svg += curveAxes(*x, *y, left, top, plotWidth, plotHeight, yName);
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const std::string color = methodColor(m, r.methods.size());
    svg += "<g data-method=\"" + htmlEscape(r.methods[m].label) + "\">";
    size_t withCurve = 0;
    for (const MethodRun& run : r.methods[m].runs) withCurve += run.curve.empty() ? 0 : 1;
    if (withCurve > 1)
      for (const MethodRun& run : r.methods[m].runs)
        if (!run.curve.empty())
          svg += "<polyline class=\"seed\" fill=\"none\" stroke=\"" + color +
                 "\" stroke-width=\"1\" stroke-opacity=\"0.45\" points=\"" +
                 polylinePoints(run.curve, value, *x, *y) + "\"/>";
    const std::vector<CurvePoint>& mean = p.meanCurves[m];
    if (mean.empty()) {
      svg += "</g>";
      continue;
    }
    svg += "<polyline class=\"mean\" fill=\"none\" stroke=\"" + color +
           "\" stroke-width=\"2.4\" stroke-linejoin=\"round\" points=\"" +
           polylinePoints(mean, value, *x, *y) + "\"/>";
    for (const CurvePoint& q : mean) {
      if (!drawable(q.seconds, q.*value)) continue;
      svg += format("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.2\" fill=\"", x->at(q.seconds),
                    y->at(q.*value)) +
             color + "\" stroke=\"#1b1b1d\"><title>" +
             htmlEscape(r.methods[m].label + ": " + seconds(Stat{q.seconds, 0, 1}) + ", " + yName +
                        " " + sci(q.*value) + ", " + samples(q.keptSpp) + " kept spp") +
             "</title></circle>";
    }
    svg += "</g>";
  }
  return svg + "</svg>";
}

// When each method (row) reaches each method's final mean MSE (column); the fastest of each
// column highlighted.
std::string reachTable(const Prepared& p) {
  const CompareReport& r = p.r;
  const size_t n = r.methods.size();
  std::string html =
      "<h3>Time to reach each method's final MSE</h3><table><tr><th class=\"l\">method</th>"
      "<th>final time</th>";
  std::vector<std::vector<Reach>> reach(n, std::vector<Reach>(n));
  std::vector<int> fastest(n, -1);
  for (size_t c = 0; c < n; ++c) {
    const std::vector<CurvePoint>& target = p.meanCurves[c];
    html += "<th>" + htmlEscape(r.methods[c].label + "'s ") +
            (target.empty() ? std::string("n/a") : sci(target.back().mse)) + "</th>";
    for (size_t m = 0; m < n && !target.empty(); ++m) {
      if (p.meanCurves[m].empty()) continue;
      reach[m][c] = timeToReach(p.meanCurves[m], target.back().mse);
      const double t = reach[m][c].seconds;
      if (!std::isnan(t) && (fastest[c] < 0 || t < reach[size_t(fastest[c])][c].seconds))
        fastest[c] = int(m);
    }
  }
  html += "</tr>\n";
  for (size_t m = 0; m < n; ++m) {
    const std::vector<CurvePoint>& curve = p.meanCurves[m];
    html += "<tr><td class=\"l\"><b>" + htmlEscape(r.methods[m].label) + "</b></td><td>" +
            (curve.empty() ? std::string("n/a") : seconds(Stat{curve.back().seconds, 0, 1})) +
            "</td>";
    for (size_t c = 0; c < n; ++c)
      html +=
          std::string(fastest[c] == int(m) && n > 1 ? "<td class=\"best\">" : "<td>") +
          htmlEscape(curve.empty() || p.meanCurves[c].empty() ? "n/a" : reachText(reach[m][c])) +
          "</td>";
    html += "</tr>\n";
  }
  return html +
         "</table><p class=\"note\">On the mean curves, interpolated log-log between "
         "checkpoints; ≤: already at the first checkpoint; never: not within the run.</p>";
}

}  // namespace

// Horizontal bars of the mean on a log axis, with whiskers at mean ± sd.
std::string barChart(const Prepared& p, size_t k, const std::string& title) {
  const CompareReport& r = p.r;
  std::vector<double> ends;  // of the bars and whiskers
  for (const auto& s : p.stats) {
    const Stat& st = s[k];
    if (!(st.mean > 0) || !std::isfinite(st.mean)) continue;
    const double sd = std::isfinite(st.stddev) ? st.stddev : 0;
    ends.push_back(st.mean - sd > 0 ? st.mean - sd : st.mean);
    ends.push_back(st.mean + sd);
  }
  const int left = 110, plotWidth = 380, right = 90, top = 30, rowHeight = 26;
  const auto axis = LogAxis::over(ends, LogAxis::Snap::Decades, left, left + plotWidth);
  if (!axis) return "";
  const int width = left + plotWidth + right, height = top + int(r.methods.size()) * rowHeight + 26;
  const auto xOf = [&](double v) { return axis->at(v); };
  const int best = winnerOf(p.stats, k);
  std::string svg = format(
      "<svg class=\"chart\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
      "role=\"img\">",
      width, height, width, height);
  svg += "<text x=\"0\" y=\"16\" font-weight=\"700\">" + htmlEscape(title) + "</text>";
  const int axisY = top + int(r.methods.size()) * rowHeight;
  for (const LogAxis::Tick& tick : axis->ticks()) {
    const double x = xOf(tick.value);
    svg += format("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"%s\"/>", x, top - 4,
                  x, axisY, tick.major ? "#3a3a3e" : "#2c2c30");
    if (tick.labelled)
      svg += format("<text class=\"axis\" x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">", x,
                    axisY + 16) +
             sciTick(tick.value) + "</text>";
  }
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const Stat& st = p.stats[m][k];
    const double y = top + double(m) * rowHeight;
    svg += format("<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">", left - 8, y + 17) +
           htmlEscape(r.methods[m].label) + "</text>";
    if (!(st.mean > 0) || !std::isfinite(st.mean)) {
      svg += format("<text class=\"axis\" x=\"%d\" y=\"%.1f\">n/a</text>", left + 4, y + 17);
      continue;
    }
    const double x = xOf(st.mean);
    svg += format("<rect x=\"%d\" y=\"%.1f\" width=\"%.1f\" height=\"16\" rx=\"2\" fill=\"%s\"/>",
                  left, y + 5, std::max(1.0, x - left), int(m) == best ? "#6fbf73" : "#5f84ad");
    if (st.count > 1 && std::isfinite(st.stddev) && st.stddev > 0) {
      const double x0 = xOf(st.mean - st.stddev), x1 = xOf(st.mean + st.stddev), yc = y + 13;
      svg += format(
          "<path d=\"M%.1f %.1fH%.1fM%.1f %.1fV%.1fM%.1f %.1fV%.1f\" stroke=\"#e6e6e6\" "
          "stroke-width=\"1.3\" fill=\"none\"/>",
          x0, yc, x1, x0, yc - 5, yc + 5, x1, yc - 5, yc + 5);
    }
    svg +=
        format("<text x=\"%.1f\" y=\"%.1f\">",
               std::max(x, xOf(st.mean + (std::isfinite(st.stddev) ? st.stddev : 0))) + 6, y + 17) +
        sci(st.mean) + "</text>";
  }
  return svg + "</svg>";
}

std::string curvesHtml(const Prepared& p) {
  const CompareReport& r = p.r;
  if (!anyCurve(r)) return "";
  size_t seeds = 0;
  for (const MethodResult& m : r.methods) seeds = std::max(seeds, m.runs.size());
  std::string html = "<section><h2>Time to quality</h2><p class=\"note\">";
  html += seeds > 1 ? "Bold: each method's mean over seeds at every checkpoint all its seeds "
                      "have, a marker per checkpoint (hover for its values); thin: each seed. "
                    : "Each method's curve, a marker per checkpoint (hover for its values). ";
  html += htmlEscape(kCurveTimingNote) + "</p><div class=\"legend\">";
  for (size_t m = 0; m < r.methods.size(); ++m)
    html += "<span class=\"line\" style=\"background:" + methodColor(m, r.methods.size()) +
            "\"></span>" + htmlEscape(r.methods[m].label);
  html += "</div><div class=\"charts\">" +
          curveChart(p, &CurvePoint::mse, "mse", "MSE against time", "MSE") +
          curveChart(p, &CurvePoint::relMse, "rel_mse", "relMSE against time", "relMSE") +
          "</div>" + reachTable(p) + "</section>\n";
  return html;
}

}  // namespace penumbra::report::detail
