// Tests for the report's time-to-quality curves (report/report_curves.cpp and
// report_charts.cpp): the mean over seeds at matching checkpoints, the time to reach an MSE,
// the two log-log charts of report.html (one bold polyline per method, points in order of
// time, log-spaced), the curves in results.json and curves.csv, the table of report.md, and a
// report without curves.
#include "report/report.h"
#include "report/report_detail.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace penumbra::report {
namespace {

namespace fs = std::filesystem;

using test::lines;
using test::readFile;

CurvePoint point(int checkpoint, double seconds, double mse, double keptSpp) {
  return {checkpoint, seconds, mse, 2 * mse, mse / 2, keptSpp};
}

// Checkpoints 0..3 at 0.1 * 2^k s and the end at 1.6 s; the MSE falls by 4 per checkpoint
// from `mse0`. Times are the same for every seed, so the mean's are too.
std::vector<CurvePoint> geometricCurve(double mse0, double speed = 1) {
  std::vector<CurvePoint> curve;
  for (int k = 0; k < 4; ++k)
    curve.push_back(point(k, 0.1 * std::exp2(k) * speed, mse0 / std::pow(4.0, k), std::exp2(k)));
  curve.push_back(point(kFinalCheckpoint, 1.6 * speed, mse0 / 256, 16));
  return curve;
}

MethodRun runWith(uint64_t seed, std::vector<CurvePoint> curve) {
  MethodRun r;
  r.seed = seed;
  r.metrics.mse = curve.back().mse;
  r.metrics.relMse = curve.back().relMse;
  r.metrics.toneMappedMse = curve.back().toneMappedMse;
  r.keptSpp = curve.back().keptSpp;
  r.seconds = curve.back().seconds;
  r.curve = std::move(curve);
  return r;
}

// "ld" and "bp", two seeds each, both ending at a mean MSE of 1e-4 (0.0256 / 4^4); bp reaches
// every MSE in half the time.
CompareReport curveReport() {
  CompareReport r;
  r.title = "curves";
  r.mode = "equal time (1.6 s per run)";
  r.reference = Image(8, 8);
  for (vec3& c : r.reference.pixels) c = vec3(0.5f);
  MethodResult ld, bp;
  ld.label = "ld";
  bp.label = "bp";
  ld.runs = {runWith(1, geometricCurve(0.0128)), runWith(2, geometricCurve(0.0384))};
  bp.runs = {runWith(1, geometricCurve(0.0128, 0.5)), runWith(2, geometricCurve(0.0384, 0.5))};
  ld.image = bp.image = r.reference;
  r.methods = {ld, bp};
  return r;
}

// The parts of `text` between each `open` and the next `close`.
std::vector<std::string> between(const std::string& text, const std::string& open,
                                 const std::string& close) {
  std::vector<std::string> parts;
  for (size_t at = text.find(open); at != std::string::npos; at = text.find(open, at + 1)) {
    const size_t end = text.find(close, at);
    parts.push_back(text.substr(at, end == std::string::npos ? end : end - at));
  }
  return parts;
}

struct Xy {
  double x, y;
};
std::vector<Xy> polylinePoints(const std::string& element) {
  const size_t at = element.find("points=\"");
  EXPECT_NE(at, std::string::npos) << element;
  std::stringstream in(element.substr(at + 8, element.find('"', at + 8) - at - 8));
  std::vector<Xy> points;
  for (std::string pair; in >> pair;) {
    const size_t comma = pair.find(',');
    points.push_back({std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1))});
  }
  return points;
}

// ---- meanCurve and timeToReach -------------------------------------------------------------
TEST(ReportCurves, MeanIsOverMatchingCheckpoints) {
  MethodResult m;
  // Seed 2 skipped checkpoint 1 (a long round): the mean leaves it out.
  m.runs = {runWith(1, {point(0, 0.1, 0.04, 1), point(1, 0.2, 0.02, 2),
                        point(kFinalCheckpoint, 0.4, 0.01, 4)}),
            runWith(2, {point(0, 0.3, 0.08, 1), point(kFinalCheckpoint, 0.5, 0.03, 4)}),
            MethodRun{}};  // a run without a curve is left out
  const std::vector<CurvePoint> mean = detail::meanCurve(m);
  ASSERT_EQ(mean.size(), 2u);
  EXPECT_EQ(mean[0].checkpoint, 0);
  EXPECT_DOUBLE_EQ(mean[0].seconds, 0.2);
  EXPECT_DOUBLE_EQ(mean[0].mse, 0.06);
  EXPECT_DOUBLE_EQ(mean[0].relMse, 0.12);
  EXPECT_DOUBLE_EQ(mean[0].toneMappedMse, 0.03);
  EXPECT_DOUBLE_EQ(mean[0].keptSpp, 1);
  EXPECT_EQ(mean[1].checkpoint, kFinalCheckpoint);
  EXPECT_DOUBLE_EQ(mean[1].seconds, 0.45);
  EXPECT_DOUBLE_EQ(mean[1].mse, 0.02);
  EXPECT_TRUE(detail::meanCurve(MethodResult{}).empty());
}

TEST(ReportCurves, TimeToReachInterpolatesLogLog) {
  const std::vector<CurvePoint> curve = {point(0, 1, 1e-2, 1), point(1, 4, 1e-4, 4)};
  // 1e-3 is halfway in log MSE, so halfway in log time: 2 s.
  const detail::Reach half = detail::timeToReach(curve, 1e-3);
  EXPECT_NEAR(half.seconds, 2.0, 1e-12);
  EXPECT_FALSE(half.atFirst);
  EXPECT_EQ(detail::reachText(half), "2 s");
  const detail::Reach first = detail::timeToReach(curve, 5e-2);
  EXPECT_DOUBLE_EQ(first.seconds, 1.0);
  EXPECT_TRUE(first.atFirst);
  EXPECT_EQ(detail::reachText(first), "≤ 1 s");
  EXPECT_TRUE(std::isnan(detail::timeToReach(curve, 1e-5).seconds));
  EXPECT_EQ(detail::reachText(detail::timeToReach(curve, 1e-5)), "never");
  EXPECT_DOUBLE_EQ(detail::timeToReach(curve, 1e-4).seconds, 4.0);  // exactly the last point
}

// ---- report.html ---------------------------------------------------------------------------
TEST(ReportCurves, HtmlHasTwoLogLogChartsWithOnePolylinePerMethod) {
  const fs::path dir = test::freshFolder("curves");
  writeReport(dir.string(), curveReport());
  const std::string html = readFile(dir / "report.html");
  // The headline section comes before the results table.
  const size_t section = html.find("<h2>Time to quality</h2>");
  ASSERT_NE(section, std::string::npos);
  EXPECT_LT(section, html.find("<h2>Results</h2>"));
  EXPECT_NE(html.find("own wall time"), std::string::npos);  // the timing rule is stated
  // The legend: each label with its colour.
  EXPECT_NE(html.find("<div class=\"legend\"><span class=\"line\" style=\"background:#"),
            std::string::npos);
  EXPECT_NE(html.find("\"></span>ld<span"), std::string::npos);
  EXPECT_NE(html.find("\"></span>bp</div>"), std::string::npos);

  const std::vector<std::string> charts = between(html, "<svg class=\"chart curve\"", "</svg>");
  ASSERT_EQ(charts.size(), 2u);
  EXPECT_NE(charts[0].find("data-metric=\"mse\""), std::string::npos);
  EXPECT_NE(charts[1].find("data-metric=\"rel_mse\""), std::string::npos);
  for (const std::string& chart : charts) {
    // Readable log ticks: 1, 2, 5 steps of the times 50 ms to 1.6 s (no empty decade beyond),
    // the MSE's powers of ten.
    for (const char* tick : {">50 ms<", ">100 ms<", ">200 ms<", ">500 ms<", ">1 s<", ">1e-4<"})
      EXPECT_NE(chart.find(tick), std::string::npos) << tick;
    for (const char* tick : {">20 ms<", ">2 s<"}) EXPECT_EQ(chart.find(tick), std::string::npos);
    for (const char* label : {"ld", "bp"}) {
      const std::vector<std::string> groups =
          between(chart, "<g data-method=\"" + std::string(label) + "\">", "</g>");
      ASSERT_EQ(groups.size(), 1u) << label;
      const std::vector<std::string> means = between(groups[0], "<polyline class=\"mean\"", "/>");
      ASSERT_EQ(means.size(), 1u) << label;
      EXPECT_EQ(between(groups[0], "<polyline class=\"seed\"", "/>").size(), 2u) << label;
      EXPECT_EQ(between(groups[0], "<circle", "</circle>").size(), 5u) << label;
      const std::vector<Xy> points = polylinePoints(means[0]);
      ASSERT_EQ(points.size(), 5u) << label;
      for (size_t i = 1; i < points.size(); ++i) {
        EXPECT_GT(points[i].x, points[i - 1].x) << label << " point " << i;  // in order of time
        EXPECT_GT(points[i].y, points[i - 1].y) << label << " point " << i;  // falling (y down)
      }
      // Log-log: times doubling and errors falling by 4 are equally spaced on both axes.
      for (size_t i = 2; i < points.size(); ++i) {
        EXPECT_NEAR(points[i].x - points[i - 1].x, points[1].x - points[0].x, 0.15) << i;
        EXPECT_NEAR(points[i].y - points[i - 1].y, points[1].y - points[0].y, 0.15) << i;
      }
    }
  }
  // The seeds' own curves are ordered by time too.
  for (const std::string& seed : between(html, "<polyline class=\"seed\"", "/>")) {
    const std::vector<Xy> points = polylinePoints(seed);
    for (size_t i = 1; i < points.size(); ++i) EXPECT_GT(points[i].x, points[i - 1].x);
  }
  // The time-to-reach table: bp reaches ld's final MSE in half ld's 1.6 s.
  EXPECT_NE(html.find("<th>ld&#39;s 1.000e-04</th>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"best\">800 ms</td>"), std::string::npos);
}

// ---- results.json, curves.csv and report.md -----------------------------------------------
TEST(ReportCurves, JsonAndCsvHoldTheCurves) {
  const fs::path dir = test::freshFolder("curves");
  const CompareReport r = curveReport();
  writeReport(dir.string(), r);
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "results.json"));
  for (size_t m = 0; m < 2; ++m)
    for (size_t s = 0; s < 2; ++s) {
      const auto& curve = j["methods"][m]["runs"][s]["curve"];
      const std::vector<CurvePoint>& want = r.methods[m].runs[s].curve;
      ASSERT_EQ(curve.size(), want.size());
      for (size_t i = 0; i < want.size(); ++i) {
        EXPECT_EQ(curve[i]["checkpoint"], want[i].checkpoint);
        EXPECT_DOUBLE_EQ(curve[i]["seconds"].get<double>(), want[i].seconds);
        EXPECT_DOUBLE_EQ(curve[i]["mse"].get<double>(), want[i].mse);
        EXPECT_DOUBLE_EQ(curve[i]["rel_mse"].get<double>(), want[i].relMse);
        EXPECT_DOUBLE_EQ(curve[i]["tone_mapped_mse"].get<double>(), want[i].toneMappedMse);
        EXPECT_DOUBLE_EQ(curve[i]["kept_spp"].get<double>(), want[i].keptSpp);
      }
    }
  EXPECT_EQ(j["methods"][0]["runs"][0]["curve"][4]["checkpoint"], kFinalCheckpoint);

  const std::vector<std::string> rows = lines(readFile(dir / "curves.csv"));
  ASSERT_EQ(rows.size(), 1u + 4 * 5);
  EXPECT_EQ(rows[0], "label,seed,checkpoint,seconds,mse,rel_mse,tone_mapped_mse,kept_spp");
  // Row by row: each run's points in order, the values as written to results.json.
  size_t row = 1;
  for (const MethodResult& m : r.methods)
    for (const MethodRun& run : m.runs)
      for (const CurvePoint& want : run.curve) {
        std::vector<std::string> fields;
        std::stringstream in(rows.at(row++));
        for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
        ASSERT_EQ(fields.size(), 8u);
        EXPECT_EQ(fields[0], m.label);
        EXPECT_EQ(fields[1], std::to_string(run.seed));
        EXPECT_EQ(fields[2], std::to_string(want.checkpoint));
        EXPECT_DOUBLE_EQ(std::stod(fields[3]), want.seconds);
        EXPECT_DOUBLE_EQ(std::stod(fields[4]), want.mse);
        EXPECT_DOUBLE_EQ(std::stod(fields[5]), want.relMse);
        EXPECT_DOUBLE_EQ(std::stod(fields[6]), want.toneMappedMse);
        EXPECT_DOUBLE_EQ(std::stod(fields[7]), want.keptSpp);
      }
  EXPECT_EQ(rows[1], "ld,1,0,0.1,0.0128,0.0256,0.0064,1");

  const std::string md = readFile(dir / "report.md");
  EXPECT_NE(md.find("## Time to quality"), std::string::npos);
  EXPECT_NE(md.find("| method | final time | ld's MSE 1.000e-04 | bp's MSE 1.000e-04 |"),
            std::string::npos);
  EXPECT_NE(md.find("| ld | 1.6 s | 1.6 s | 1.6 s |"), std::string::npos);
  EXPECT_NE(md.find("| bp | 800 ms | 800 ms | 800 ms |"), std::string::npos);
  EXPECT_NE(md.find("[curves.csv](curves.csv)"), std::string::npos);
}

TEST(ReportCurves, WithoutCurvesThereIsNoSection) {
  const fs::path dir = test::freshFolder("curves");
  CompareReport r = curveReport();
  for (MethodResult& m : r.methods)
    for (MethodRun& run : m.runs) run.curve.clear();
  writeReport(dir.string(), r);
  EXPECT_EQ(lines(readFile(dir / "curves.csv")).size(), 1u);  // the header
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "results.json"));
  EXPECT_TRUE(j["methods"][0]["runs"][0]["curve"].is_array());
  EXPECT_TRUE(j["methods"][0]["runs"][0]["curve"].empty());
  const std::string html = readFile(dir / "report.html");
  EXPECT_EQ(html.find("Time to quality"), std::string::npos);
  EXPECT_EQ(html.find("chart curve"), std::string::npos);
  EXPECT_EQ(readFile(dir / "report.md").find("Time to quality"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::report
