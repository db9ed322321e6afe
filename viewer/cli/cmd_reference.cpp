// `penumbra reference`: a converged low-discrepancy render to compare methods against
// (ALGORITHM.md §11), with its per-pixel variance of the mean and a JSON record of how
// converged it is, so a user can tell whether a reference is good enough for the errors
// they want to measure.
#include "core/image_io.h"
#include "eval/metrics.h"
#include "eval/reference.h"
#include "methods/render.h"
#include "trace/integrator.h"
#include "viewer/cli/commands.h"
#include "viewer/cli/progress.h"
#include "viewer/cli/scene_options.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>

namespace penumbra {

namespace {

struct ReferenceFlags {
  SceneOptions scene;
  std::string output, variancePath, statsPath;
  int spp = 8192;
  uint64_t seed = 999;  // far from the seeds the comparisons use (1, 2, ...)
  int threads = 0;
  bool quiet = false;
};

std::string siblingPath(const std::string& path, const std::string& suffix,
                        const std::string& extension) {
  std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix + extension)).string();
}

void run(ReferenceFlags flags) {
  try {
    checkWritableImagePath(flags.output);
  } catch (const ImageIoError& e) {
    throw CommandError(std::string("--output ") + e.what());
  }
  if (lowercaseExtension(flags.output) == ".png")
    throw CommandError("--output " + flags.output +
                       ": a reference must be linear: use .exr or .pfm");
  if (flags.variancePath.empty()) flags.variancePath = siblingPath(flags.output, "_var", ".exr");
  if (flags.statsPath.empty()) flags.statsPath = siblingPath(flags.output, "", ".json");
  const std::filesystem::path parent = std::filesystem::path(flags.output).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec) throw CommandError(flags.output + ": cannot create directory: " + ec.message());

  flags.scene.spp = flags.spp;
  Scene scene = loadSceneWithOptions(flags.scene);
  auto prepared = prepareScene(std::move(scene));
  const Scene& s = prepared->scene;
  ProgressBar bar("reference " + std::to_string(s.settings.width) + "x" +
                  std::to_string(s.settings.height) + " " + std::to_string(flags.spp) + " spp");
  std::function<void(double)> progress;
  if (!flags.quiet) progress = [&bar](double f) { bar.update(f); };
  const Reference ref = renderReference(*prepared, flags.spp, flags.seed, flags.threads, progress);
  bar.finish();
  const RenderResult& r = ref.render;
  const Convergence& converged = ref.convergence;
  writeImage(flags.output, r.image);
  writeImage(flags.variancePath, r.varianceOfMean);
  nlohmann::json j;
  j["scene"] = flags.scene.scenePath;
  j["image"] = flags.output;
  j["variance"] = flags.variancePath;
  j["width"] = s.settings.width;
  j["height"] = s.settings.height;
  j["spp"] = flags.spp;
  j["seed"] = flags.seed;
  j["max_depth"] = s.settings.maxDepth;
  j["time_seconds"] = r.seconds;
  j["rays"] = r.rays;
  j["nan_samples"] = r.nonFiniteSamples;
  j["mean_relative_standard_error"] = converged.meanRelativeError;
  j["residual_mse"] = converged.residualMse;
  writeJson(flags.statsPath, j);
  if (!flags.quiet)
    std::printf(
        "%s: %dx%d, %d spp, %.1f s; variance %s; residual MSE %.3g (mean relative "
        "error %.3g)\n",
        flags.output.c_str(), s.settings.width, s.settings.height, flags.spp, r.seconds,
        flags.variancePath.c_str(), converged.residualMse, converged.meanRelativeError);
  if (r.nonFiniteSamples > 0)
    std::fprintf(stderr, "penumbra reference: warning: %llu NaN or infinite samples were dropped\n",
                 static_cast<unsigned long long>(r.nonFiniteSamples));
}

}  // namespace

void registerReferenceCommand(CLI::App& app) {
  auto flags = std::make_shared<ReferenceFlags>();
  CLI::App* c = app.add_subcommand(
      "reference",
      "Render a converged low-discrepancy reference (.exr) with its variance image and a JSON "
      "record of its residual error, for `penumbra compare` and `penumbra diff`");
  addSceneOptions(*c, flags->scene);
  // Scene options define --spp as an override of the scene's; here it has its own default.
  c->remove_option(c->get_option("--spp"));
  c->add_option("--spp", flags->spp, "Samples per pixel")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  c->add_option("-o,--output", flags->output, "Reference image (.exr or .pfm)")->required();
  c->add_option("--variance-out", flags->variancePath,
                "Per-pixel variance of the mean (default: OUTPUT_var.exr)");
  c->add_option("--stats", flags->statsPath, "JSON record (default: OUTPUT with .json)");
  c->add_option("--seed", flags->seed, "Random seed")->capture_default_str();
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_flag("-q,--quiet", flags->quiet, "No progress bar or summary line");
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
