// `penumbra diff`: compares an image with a reference (MSE, relative MSE, PSNR, max error)
// and optionally writes a false-colour map of where they differ.
#include "cli/commands.h"
#include "core/image_io.h"
#include "eval/metrics.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace penumbra {

namespace {
struct DiffFlags {
  std::string testPath, referencePath, outPath;
  bool json = false;
  float exposure = 0.0f;
  double colourMax = 0.0;  // 0: use the largest error in the image
};

std::string sizeText(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

// JSON has no NaN or infinity; null marks "undefined" (no finite pixels, or identical images
// for PSNR) rather than a misleading number.
nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

void run(const DiffFlags& flags) {
  Image test = readImage(flags.testPath);
  Image reference = readImage(flags.referencePath);
  if (test.width != reference.width || test.height != reference.height)
    throw CommandError("image sizes differ: " + flags.testPath + " is " + sizeText(test) + ", " +
                       flags.referencePath + " is " + sizeText(reference));
  if (flags.exposure != 0.0f) {
    // Compare what a display at this exposure shows; this matters for PSNR, which clamps.
    const float scale = std::exp2(flags.exposure);
    for (vec3& p : test.pixels) p *= scale;
    for (vec3& p : reference.pixels) p *= scale;
  }
  const ImageMetrics m = compareImages(test, reference);

  // Written before anything is printed, so a failed write leaves no half report behind.
  std::string legend;
  double colourMax = 0.0;
  if (!flags.outPath.empty()) {
    double largest = 0.0;
    const Image error = errorImage(test, reference, largest);
    colourMax = flags.colourMax > 0.0 ? flags.colourMax : largest;
    writeImage(flags.outPath, falseColor(error, float(colourMax)));
    char range[64];
    std::snprintf(range, sizeof range, "0 (dark) .. %.1e (bright)", colourMax);
    legend = flags.outPath + ": relative squared error, " + range +
             (m.nonFinite > 0 ? ", magenta = NaN/inf" : "");
  }

  if (flags.json) {
    nlohmann::json j;
    j["mse"] = finiteOrNull(m.mse);
    j["rel_mse"] = finiteOrNull(m.relMse);
    j["tone_mapped_mse"] = finiteOrNull(m.toneMappedMse);
    j["psnr"] = finiteOrNull(m.psnr);
    j["max_abs_error"] = finiteOrNull(m.maxAbsError);
    j["non_finite"] = m.nonFinite;
    j["width"] = test.width;
    j["height"] = test.height;
    if (!flags.outPath.empty()) {
      j["diff_image"] = flags.outPath;
      j["diff_max"] = colourMax;
    }
    std::printf("%s\n", j.dump().c_str());
    // stdout stays a single JSON object; the human-readable legend goes to stderr.
    if (!legend.empty()) std::fprintf(stderr, "%s\n", legend.c_str());
    return;
  }
  std::printf("mse %.3e\n", m.mse);
  std::printf("rel_mse %.3e\n", m.relMse);
  std::printf("tone_mapped_mse %.3e\n", m.toneMappedMse);
  std::printf("psnr %.2f dB\n", m.psnr);
  std::printf("max_abs_error %.3e\n", m.maxAbsError);
  std::printf("non_finite %zu\n", m.nonFinite);
  if (!legend.empty()) std::printf("%s\n", legend.c_str());
}
}  // namespace

void registerDiffCommand(CLI::App& app) {
  auto flags = std::make_shared<DiffFlags>();
  CLI::App* c = app.add_subcommand(
      "diff", "Compare an image with a reference: MSE, relative MSE, PSNR and max abs error");
  c->add_option("image", flags->testPath, "Image to evaluate (.exr .pfm .hdr .png .jpg .tga .bmp)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("reference", flags->referencePath, "Reference image of the same size")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("-o,--out", flags->outPath,
                "Write a false-colour map of the per-pixel relative squared error "
                "(.png, .exr or .pfm); dark = small, bright = large, magenta = NaN/inf");
  c->add_flag("--json", flags->json,
              "Print one JSON object (mse, rel_mse, tone_mapped_mse, psnr, max_abs_error, "
              "non_finite, width, "
              "height) instead of one metric per line; undefined values are null");
  c->add_option("--exposure", flags->exposure,
                "Scale both images by 2^STOPS before comparing, as `render --exposure` does for "
                "PNG; PSNR is computed on values clamped to [0,1] after this scale")
      ->type_name("STOPS")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--max", flags->colourMax,
                "Error value shown brightest in --out (default: the largest error in the image); "
                "set it to compare several diff images on one scale")
      ->type_name("VALUE")
      ->check(CLI::PositiveNumber);
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
