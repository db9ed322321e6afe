// Tests for engine/report: statistics over seeds, base64, the choice of crops where methods
// differ, and the files writeReport leaves (CSV values, JSON means, a self-contained and
// escaped HTML page), including that a bad report writes nothing.
#include "report/report.h"

#include "core/image_io.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::report {
namespace {

namespace fs = std::filesystem;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

using test::lines;
using test::readFile;

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) out.push_back(field);
  return out;
}

// A smooth reference: a gradient that is nowhere black.
Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      image.at(x, y) = vec3(0.2f + 0.6f * x / w, 0.5f, 0.2f + 0.6f * y / h);
  return image;
}

MethodRun run(uint64_t seed, double mse, double seconds) {
  MethodRun r;
  r.seed = seed;
  r.metrics.mse = mse;
  r.metrics.relMse = 2 * mse;
  r.metrics.toneMappedMse = mse / 2;
  r.metrics.psnr = 10 * std::log10(1 / mse);
  r.keptSpp = 16;
  r.tracedSpp = 20;
  r.seconds = seconds;
  r.trace = seconds / 2;
  r.train = seconds / 4;
  r.select = seconds / 8;
  r.reconstruct = seconds / 8;
  r.network = seconds / 16;
  return r;
}

// Two methods, two seeds each, on a 16x16 gradient; "bp" has maps, "ld" has none.
CompareReport smallReport() {
  CompareReport r;
  r.title = "tiny.json";
  r.scenePath = "scenes/tiny.json";
  r.referencePath = "out/ref/tiny.exr";
  r.mode = "equal kept spp (16)";
  r.commandLine = "penumbra compare scenes/tiny.json --methods ld,bp";
  r.threads = 2;
  r.reference = gradient(16, 16);

  MethodResult ld;
  ld.label = "ld";
  ld.description = "Low discrepancy (box)";
  ld.spp = 16;
  ld.runs = {run(1, 0.004, 1.0), run(2, 0.006, 3.0)};
  ld.image = r.reference;
  for (vec3& c : ld.image.pixels) c *= 1.1f;

  MethodResult bp;
  bp.label = "bp";
  bp.description = "Neural per-pixel (paper)";
  bp.spp = 16;
  bp.runs = {run(1, 0.001, 2.0), run(2, 0.003, 2.5)};
  bp.image = r.reference;
  for (vec3& c : bp.image.pixels) c *= 1.02f;
  const size_t n = r.reference.pixels.size();
  std::vector<float> density(n, 8.0f);
  for (size_t i = 0; i < n / 2; ++i) density[i] = 32.0f;
  std::vector<float> filterScale(n, 0.0f);
  for (size_t i = 0; i < n; i += 3) filterScale[i] = 1.0f;
  bp.maps = {
      {maps::SampleCount, "kept spp", density, MapLegend::sequential(0, 32, "samples")},
      {maps::ErrorEstimate, "bias", std::vector<float>(n, 0.01f), MapLegend::sequential(0, 1)},
      {maps::FilterScale, "filter alpha", filterScale, MapLegend::categorical({"α=0.1", "α=0.5"})},
  };
  r.methods = {ld, bp};
  return r;
}

// ---- summarize -----------------------------------------------------------------------------
// 1, 2, 3, 6: mean 3, squared deviations 4 + 1 + 0 + 9 = 14, sample variance 14 / 3.
TEST(ReportSummarize, MeanAndSampleStddev) {
  const Stat s = summarize({1, 2, 3, 6});
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_NEAR(s.stddev, std::sqrt(14.0 / 3.0), 1e-12);
}

TEST(ReportSummarize, NaNsAreSkipped) {
  const Stat s = summarize({kNaN, 2, kNaN, 4});
  EXPECT_EQ(s.count, 2);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_NEAR(s.stddev, std::sqrt(2.0), 1e-12);
}

TEST(ReportSummarize, OneOrNoValue) {
  const Stat one = summarize({kNaN, 5});
  EXPECT_EQ(one.count, 1);
  EXPECT_DOUBLE_EQ(one.mean, 5.0);
  EXPECT_EQ(one.stddev, 0.0);
  const Stat none = summarize({kNaN});
  EXPECT_EQ(none.count, 0);
  EXPECT_TRUE(std::isnan(none.mean));
  EXPECT_EQ(none.stddev, 0.0);
}

TEST(ReportSummarize, InfiniteValues) {
  const double inf = std::numeric_limits<double>::infinity();
  const Stat same = summarize({inf, inf});
  EXPECT_TRUE(std::isinf(same.mean));
  EXPECT_EQ(same.stddev, 0.0);
  EXPECT_TRUE(std::isnan(summarize({inf, 3}).stddev));
}

// ---- base64 --------------------------------------------------------------------------------
std::vector<uint8_t> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

// RFC 4648, section 10.
TEST(ReportBase64, KnownVectors) {
  EXPECT_EQ(base64({}), "");
  EXPECT_EQ(base64(bytesOf("f")), "Zg==");
  EXPECT_EQ(base64(bytesOf("fo")), "Zm8=");
  EXPECT_EQ(base64(bytesOf("foo")), "Zm9v");
  EXPECT_EQ(base64(bytesOf("foob")), "Zm9vYg==");
  EXPECT_EQ(base64(bytesOf("fooba")), "Zm9vYmE=");
  EXPECT_EQ(base64(bytesOf("foobar")), "Zm9vYmFy");
  EXPECT_EQ(base64({0xFB, 0xFF, 0xBF}), "+/+/");
}

// ---- chooseCrops ---------------------------------------------------------------------------
bool overlap(const Crop& a, const Crop& b) {
  return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
}

// 64x64: "good" is close everywhere, "blob" has a large error in a 10x10 patch at (44, 6).
// The default size is 16, stride 8; the first crop must contain the whole patch.
TEST(ReportChooseCrops, FirstCropCoversTheErrorBlob) {
  CompareReport r;
  r.reference = gradient(64, 64);
  MethodResult good, blob;
  good.label = "good";
  good.image = r.reference;
  for (vec3& c : good.image.pixels) c *= 1.01f;
  blob.label = "blob";
  blob.image = good.image;
  for (int y = 6; y < 16; ++y)
    for (int x = 44; x < 54; ++x) blob.image.at(x, y) = vec3(3.0f);
  r.methods = {good, blob};

  const std::vector<Crop> crops = chooseCrops(r);
  ASSERT_EQ(crops.size(), 3u);
  EXPECT_EQ(crops[0].name, "A");
  EXPECT_EQ(crops[1].name, "B");
  EXPECT_EQ(crops[2].name, "C");
  EXPECT_EQ(crops[0].w, 16);
  EXPECT_EQ(crops[0].h, 16);
  EXPECT_LE(crops[0].x, 44);
  EXPECT_GE(crops[0].x + crops[0].w, 54);
  EXPECT_LE(crops[0].y, 6);
  EXPECT_GE(crops[0].y + crops[0].h, 16);
  for (size_t i = 0; i < crops.size(); ++i) {
    EXPECT_GE(crops[i].x, 0);
    EXPECT_GE(crops[i].y, 0);
    EXPECT_LE(crops[i].x + crops[i].w, 64);
    EXPECT_LE(crops[i].y + crops[i].h, 64);
    for (size_t j = 0; j < i; ++j) EXPECT_FALSE(overlap(crops[i], crops[j])) << i << " " << j;
  }
  // Deterministic.
  const std::vector<Crop> again = chooseCrops(r);
  ASSERT_EQ(again.size(), crops.size());
  for (size_t i = 0; i < crops.size(); ++i) {
    EXPECT_EQ(again[i].x, crops[i].x);
    EXPECT_EQ(again[i].y, crops[i].y);
  }
}

// One method, an image smaller than the default crop: one crop, the whole image.
TEST(ReportChooseCrops, TinyImageAndOneMethod) {
  CompareReport r;
  r.reference = gradient(8, 8);
  MethodResult m;
  m.label = "ld";
  m.image = r.reference;
  m.image.at(2, 3) = vec3(1.0f);
  r.methods = {m};
  const std::vector<Crop> crops = chooseCrops(r);
  ASSERT_EQ(crops.size(), 1u);
  EXPECT_EQ(crops[0].x, 0);
  EXPECT_EQ(crops[0].y, 0);
  EXPECT_EQ(crops[0].w, 8);
  EXPECT_EQ(crops[0].h, 8);
}

// An explicit size on a non-square image: crops stay inside and apart, and there are only as
// many as fit.
TEST(ReportChooseCrops, ExplicitSizeStaysInside) {
  CompareReport r;
  r.reference = gradient(40, 20);
  MethodResult m;
  m.label = "ld";
  m.image = r.reference;
  m.image.at(39, 19) = vec3(5.0f);
  r.methods = {m};
  const std::vector<Crop> crops = chooseCrops(r, 5, 12);
  ASSERT_EQ(crops.size(), 3u);             // three 12-wide columns fit in 40, one 12-high row in 20
  EXPECT_EQ(crops[0].x + crops[0].w, 40);  // the window flush with the corner holds the error
  EXPECT_EQ(crops[0].y + crops[0].h, 20);
  for (size_t i = 0; i < crops.size(); ++i) {
    EXPECT_LE(crops[i].x + crops[i].w, 40);
    EXPECT_LE(crops[i].y + crops[i].h, 20);
    for (size_t j = 0; j < i; ++j) EXPECT_FALSE(overlap(crops[i], crops[j]));
  }
}

TEST(ReportChooseCrops, SizeMismatchThrows) {
  CompareReport r;
  r.reference = gradient(16, 16);
  MethodResult m;
  m.image = gradient(8, 16);
  r.methods = {m};
  EXPECT_THROW(chooseCrops(r), std::invalid_argument);
}

// ---- writeReport ---------------------------------------------------------------------------
TEST(ReportWrite, WritesAllFiles) {
  const fs::path dir = test::freshFolder("report");
  writeReport(dir.string(), smallReport());
  for (const char* name :
       {"results.json", "results.csv", "report.md", "report.html", "images/reference.png",
        "images/ld.png", "images/bp.png", "images/ld_error.png", "images/bp_density.png",
        "images/bp_estimate.png", "images/bp_filter.png", "images/overview.png"})
    EXPECT_TRUE(fs::is_regular_file(dir / name)) << name;
  EXPECT_FALSE(fs::exists(dir / "images/ld_density.png"));  // ld has no density map
  // The crops (one: the 16x16 image is as small as a crop) for the reference and each method.
  EXPECT_TRUE(fs::is_regular_file(dir / "images/crop_A_reference.png"));
  EXPECT_TRUE(fs::is_regular_file(dir / "images/crop_A_bp.png"));
  // The images are what writeImage would write: the method's output, readable back.
  const Image ld = readImage((dir / "images/ld.png").string());
  EXPECT_EQ(ld.width, 16);
  EXPECT_EQ(ld.height, 16);
  int w = 0, h = 0;
  readPng8((dir / "images/crop_A_ld.png").string(), w, h);
  EXPECT_EQ(w, 128);  // 16 px upscaled by 8
  // No temporary left behind.
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST(ReportWrite, CsvHasOneRowPerRun) {
  const fs::path dir = test::freshFolder("report");
  writeReport(dir.string(), smallReport());
  const std::vector<std::string> rows = lines(readFile(dir / "results.csv"));
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0],
            "label,seed,spp,kept_spp,traced_spp,mse,rel_mse,tone_mapped_mse,psnr,seconds,trace,"
            "train,select,reconstruct,network");
  const std::vector<std::string> header = splitCsv(rows[0]);
  const auto column = [&](const std::vector<std::string>& row, const std::string& name) {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return row.at(i);
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  const std::vector<std::string> labels = {"ld", "ld", "bp", "bp"};
  const std::vector<std::string> seeds = {"1", "2", "1", "2"};
  const std::vector<double> mse = {0.004, 0.006, 0.001, 0.003};
  const std::vector<double> secs = {1.0, 3.0, 2.0, 2.5};
  for (size_t i = 0; i < 4; ++i) {
    const std::vector<std::string> row = splitCsv(rows[i + 1]);
    ASSERT_EQ(row.size(), header.size()) << rows[i + 1];
    EXPECT_EQ(column(row, "label"), labels[i]);
    EXPECT_EQ(column(row, "seed"), seeds[i]);
    EXPECT_EQ(column(row, "spp"), "16");
    EXPECT_DOUBLE_EQ(std::stod(column(row, "kept_spp")), 16.0);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "traced_spp")), 20.0);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "mse")), mse[i]);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "rel_mse")), 2 * mse[i]);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "tone_mapped_mse")), mse[i] / 2);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "psnr")), 10 * std::log10(1 / mse[i]));
    EXPECT_DOUBLE_EQ(std::stod(column(row, "seconds")), secs[i]);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "trace")), secs[i] / 2);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "reconstruct")), secs[i] / 8);
    EXPECT_DOUBLE_EQ(std::stod(column(row, "network")), secs[i] / 16);
  }
}

TEST(ReportWrite, JsonHasMeansAndWinners) {
  const fs::path dir = test::freshFolder("report");
  writeReport(dir.string(), smallReport());
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "results.json"));
  EXPECT_EQ(j["scene"], "scenes/tiny.json");
  EXPECT_EQ(j["reference"], "out/ref/tiny.exr");
  EXPECT_EQ(j["mode"], "equal kept spp (16)");
  EXPECT_EQ(j["threads"], 2);
  ASSERT_EQ(j["methods"].size(), 2u);
  const auto& ld = j["methods"][0];
  const auto& bp = j["methods"][1];
  EXPECT_EQ(ld["label"], "ld");
  EXPECT_EQ(bp["description"], "Neural per-pixel (paper)");
  EXPECT_NEAR(ld["mse"]["mean"].get<double>(), 0.005, 1e-15);
  EXPECT_NEAR(ld["mse"]["stddev"].get<double>(), std::sqrt(2e-6), 1e-15);
  EXPECT_NEAR(bp["mse"]["mean"].get<double>(), 0.002, 1e-15);
  EXPECT_NEAR(bp["rel_mse"]["mean"].get<double>(), 0.004, 1e-15);
  EXPECT_NEAR(bp["seconds"]["mean"].get<double>(), 2.25, 1e-15);
  EXPECT_NEAR(bp["trace"]["mean"].get<double>(), 1.125, 1e-15);
  EXPECT_NEAR(bp["mse_ratio_to_first"].get<double>(), 0.4, 1e-12);
  EXPECT_EQ(bp["runs"].size(), 2u);
  EXPECT_EQ(bp["runs"][1]["seed"], 2);
  EXPECT_EQ(j["winner"]["mse"], "bp");
  EXPECT_EQ(j["winner"]["psnr"], "bp");
  EXPECT_EQ(j["winner"]["seconds"], "ld");  // 2.0 s mean against 2.25 s
  ASSERT_EQ(j["crops"].size(), 1u);
  EXPECT_EQ(j["crops"][0]["name"], "A");
  EXPECT_TRUE(j["crops"][0]["mse"].contains("bp"));
}

TEST(ReportWrite, HtmlIsSelfContainedAndEscaped) {
  const fs::path dir = test::freshFolder("report");
  CompareReport r = smallReport();
  r.methods[1].label = "<b>&";
  r.methods[1].description = "a \"quoted\" <i>description</i>";
  writeReport(dir.string(), r);
  const std::string html = readFile(dir / "report.html");
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  // The page bolds labels itself ("<b>&lt;b&gt;&amp;</b>"); the raw label never appears.
  for (size_t at = html.find("<b>&"); at != std::string::npos; at = html.find("<b>&", at + 1))
    EXPECT_EQ(html.compare(at + 3, 14, "&lt;b&gt;&amp;"), 0) << html.substr(at, 40);
  EXPECT_NE(html.find("&lt;b&gt;&amp;"), std::string::npos);
  EXPECT_EQ(html.find("<i>description"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);  // the bar chart and crop outlines
  // Every image is embedded: no src attribute points at a file.
  for (size_t at = html.find("src=\""); at != std::string::npos; at = html.find("src=\"", at + 1))
    EXPECT_EQ(html.compare(at + 5, 5, "data:"), 0);
  // The summary names the MSE winner and the ratio of the other: 0.005 / 0.002 = 2.5.
  EXPECT_NE(html.find("&lt;b&gt;&amp; wins on MSE"), std::string::npos);
  EXPECT_NE(html.find("2.50×"), std::string::npos);
  // The label is a file name too, made safe.
  EXPECT_TRUE(fs::is_regular_file(dir / "images/_b__.png"));
}

TEST(ReportWrite, MarkdownHasTableAndLinks) {
  const fs::path dir = test::freshFolder("report");
  writeReport(dir.string(), smallReport());
  const std::string md = readFile(dir / "report.md");
  EXPECT_NE(md.find("# tiny.json"), std::string::npos);
  EXPECT_NE(md.find("equal kept spp (16)"), std::string::npos);
  EXPECT_NE(md.find("| ld | Low discrepancy (box) |"), std::string::npos);
  EXPECT_NE(md.find("bp wins on MSE"), std::string::npos);
  EXPECT_NE(md.find("](images/bp.png)"), std::string::npos);
  EXPECT_NE(md.find("](images/bp_density.png)"), std::string::npos);
}

TEST(ReportWrite, SizeMismatchThrowsAndWritesNothing) {
  const fs::path dir = test::freshFolder("report");
  CompareReport r = smallReport();
  r.methods[1].image = gradient(16, 15);
  EXPECT_THROW(writeReport(dir.string(), r), std::invalid_argument);
  r = smallReport();
  r.methods[0].maps = {
      {maps::SampleCount, "kept spp", std::vector<float>(10, 1.0f), MapLegend::sequential(0, 1)}};
  EXPECT_THROW(writeReport(dir.string(), r), std::invalid_argument);
  r = smallReport();
  r.crops = {{"A", 10, 10, 8, 8}};  // reaches past the 16x16 image
  EXPECT_THROW(writeReport(dir.string(), r), std::invalid_argument);
  for (const char* name : {"results.json", "results.csv", "report.md", "report.html"})
    EXPECT_FALSE(fs::exists(dir / name)) << name;
}

TEST(ReportWrite, UnwritableFolderThrowsImageIoError) {
  const fs::path dir = test::freshFolder("report");
  fs::create_directories(dir);
  std::ofstream(dir / "file") << "not a folder";
  try {
    writeReport((dir / "file" / "report").string(), smallReport());
    FAIL() << "no exception";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find("file"), std::string::npos) << e.what();
  }
}

// One method without runs or maps, an image of odd size, NaN pixels: still a whole report.
TEST(ReportWrite, SparseReportStillWrites) {
  const fs::path dir = test::freshFolder("report");
  CompareReport r;
  r.reference = gradient(9, 5);
  MethodResult m;
  m.label = "only";
  m.image = r.reference;
  m.image.at(4, 2) = vec3(std::numeric_limits<float>::quiet_NaN());
  r.methods = {m};
  writeReport(dir.string(), r);
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "results.json"));
  EXPECT_TRUE(j["methods"][0]["mse"]["mean"].is_null());  // no runs: no mean
  EXPECT_TRUE(j["winner"]["mse"].is_null());
  EXPECT_EQ(lines(readFile(dir / "results.csv")).size(), 1u);
  EXPECT_TRUE(fs::is_regular_file(dir / "report.html"));
  EXPECT_TRUE(fs::is_regular_file(dir / "images/only_error.png"));
}

// Given crops are used as they are.
TEST(ReportWrite, UsesGivenCrops) {
  const fs::path dir = test::freshFolder("report");
  CompareReport r = smallReport();
  r.crops = {{"left", 0, 4, 6, 6}, {"right", 10, 4, 6, 6}};
  writeReport(dir.string(), r);
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "results.json"));
  ASSERT_EQ(j["crops"].size(), 2u);
  EXPECT_EQ(j["crops"][1]["name"], "right");
  EXPECT_EQ(j["crops"][1]["x"], 10);
  EXPECT_TRUE(fs::is_regular_file(dir / "images/crop_right_ld.png"));
}

}  // namespace
}  // namespace penumbra::report
