// `penumbra render`: renders a scene to an image file, with optional statistics.
#include "cli/commands.h"
#include "cli/json_file.h"
#include "cli/method_options.h"
#include "cli/progress.h"
#include "cli/render_stats.h"
#include "cli/run_options.h"
#include "cli/scene_options.h"
#include "cli/shard_record.h"
#include "core/image_io.h"
#include "core/large_pages.h"
#include "methods/factory.h"
#include "methods/ld/ld.h"
#include "methods/render.h"
#include "present/snapshot_io.h"
#include "scene/textures.h"
#include "trace/coverage.h"
#include "trace/integrator.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include <tbb/global_control.h>

namespace penumbra {

namespace {
struct RenderFlags {
  SceneOptions scene;
  MethodOptions method;
  RunOptions run;
  std::string output, statsPath, variancePath, rawPath, aovDir, region;
  int threads = 0;
  float exposure = 0;
  bool quiet = false;
  std::string shard;  // "K/N": plain LD, only shard K's tiles (docs/farm.md)
};

// The run's shape: a batch of the scene's spp, the flags given applied. A stopping rule makes
// it open-ended, an explicit --spp then capping it.
RunShape renderShape(const RenderFlags& flags, const Scene& scene) {
  RunShape shape = RunShape::batch(scene.settings.spp);
  flags.run.apply(shape);
  if (shape.hasStoppingRule()) {
    shape.openEnded = true;
    if (!flags.run.has("spp")) shape.spp = 0;
  }
  return shape;
}

// The statistics every method reports: the scene, the run's shape (every entry of its table:
// spp, seed, sampler, ...) and the counts.
nlohmann::json commonStats(const RenderFlags& flags, const Scene& scene, const RunShape& shape,
                           int threads, double seconds, uint64_t rays, uint64_t samples) {
  nlohmann::json j = paramsJson(runShapeParams().params(), shape);
  j["scene"] = flags.scene.scenePath;
  j["method"] = flags.method.method;
  j["width"] = scene.settings.width;
  j["height"] = scene.settings.height;
  j["threads"] = threads;
  j["max_depth"] = scene.settings.maxDepth;
  j["texture_bytes"] = textureBytes(scene);
  j["time_seconds"] = seconds;
  j["rays"] = rays;
  j["mrays_per_second"] = seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0;
  j["samples"] = samples;
  return j;
}

void createParentDirectory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec)
    throw CommandError(path + ": cannot create directory '" + parent.string() +
                       "': " + ec.message());
}

void checkImageExtension(const std::string& flag, const std::string& path) {
  try {
    checkWritableImagePath(path);
  } catch (const ImageIoError& e) {
    throw CommandError(flag + " " + e.what());
  }
}

// What the chosen method can do, asked before the scene loads, so that a flag it cannot honour
// fails at once.
void prepareOutputs(const RenderFlags& flags) {
  // Fail on a bad output name before spending minutes rendering.
  checkImageExtension("--output", flags.output);
  if (!flags.variancePath.empty()) checkImageExtension("--variance-out", flags.variancePath);
  if (!flags.rawPath.empty()) checkImageExtension("--raw-out", flags.rawPath);
  const MethodDescriptor& method = flags.method.descriptor();
  flags.method.requireRead({&method});
  const MethodAbilities can = method.abilities(flags.method.config(method, flags.method.preset));
  if (!can.filters && !can.adapts && !flags.rawPath.empty())
    throw CommandError(
        "--raw-out needs a method that filters or adapts (an adaptive --method, or --filter)");
  if (!can.keepsVariance && !flags.variancePath.empty())
    throw CommandError("--variance-out needs a method that keeps each pixel's variance: " +
                       method.title() + " does not");
  requireNoiseThresholdHonoured(method, flags.method.config(method, flags.method.preset),
                                flags.run.has("noise-threshold"), flags.run.has("time-limit"));
  for (const std::string* path :
       {&flags.output, &flags.statsPath, &flags.variancePath, &flags.rawPath})
    if (!path->empty()) createParentDirectory(*path);
}

// `spp`: the samples per pixel the image holds (a time limit or a noise threshold may stop a
// run before, or past, the scene's spp).
void printSummary(const RenderFlags& flags, const Scene& s, double spp, double seconds,
                  uint64_t rays, const std::string& extra) {
  if (flags.quiet) return;
  std::printf("%s: %dx%d, %.4g spp%s, %.2f s, %.2f Mrays/s\n", flags.output.c_str(),
              s.settings.width, s.settings.height, spp, extra.c_str(), seconds,
              seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0);
}

void warnNonFinite(uint64_t count) {
  if (count > 0)
    std::fprintf(stderr, "penumbra render: warning: %llu NaN or infinite samples were dropped\n",
                 static_cast<unsigned long long>(count));
}

// The output image, with an alpha channel saying where the scene is when it is transparent.
void writeOutput(const RenderFlags& flags, const PreparedScene& prepared, const Image& image) {
  if (!prepared.scene.transparent) {
    writeImage(flags.output, image, flags.exposure);
    return;
  }
  const std::vector<float> alpha = cameraCoverage(prepared);
  writeImage(flags.output, image, flags.exposure, &alpha);
}

// Plain LD to its end through renderImage (methods/render.h): the same image as its method,
// with a shard's pixel mask.
void runLd(const RenderFlags& flags, const PreparedScene& prepared, const RunShape& shape,
           int threads) {
  const Scene& s = prepared.scene;
  RenderOptions options;
  options.sampler = shape.sampler;
  options.seed = shape.seed;
  options.spp = shape.spp;
  options.threads = flags.threads;
  ProgressBar bar("render " + std::to_string(s.settings.width) + "x" +
                  std::to_string(s.settings.height) + " " + std::to_string(shape.spp) + " spp");
  if (!flags.quiet) options.progress = [&bar](double f) { bar.update(f); };
  Shard shard;
  if (!flags.shard.empty()) {
    shard = parseShard(flags.shard);  // checked in run()
    options.pixelMask = shardPixelMask(s.settings.width, s.settings.height, shard);
  }
  const RenderResult result = renderImage(prepared, options);
  bar.finish();

  writeOutput(flags, prepared, result.image);
  if (!flags.variancePath.empty()) writeImage(flags.variancePath, result.varianceOfMean);
  if (!flags.shard.empty()) {
    ShardRecord record;
    record.command = "render";
    record.scene = flags.scene.scenePath;
    record.sceneHash = sceneHash(s);
    record.settings = pixelSettings(s, flags.scene, shape.spp, shape.seed, shape.sampler);
    record.shard = shard;
    record.tiles = shardTiles(s.settings.width, s.settings.height, shard);
    record.width = s.settings.width;
    record.height = s.settings.height;
    record.image = flags.output;
    record.variance = flags.variancePath;
    record.seconds = result.seconds;
    record.rays = result.rays;
    record.nanSamples = result.nonFiniteSamples;
    writeJson(shardRecordPath(flags.output), record.toJson());
  }
  if (!flags.statsPath.empty()) {
    nlohmann::json j =
        commonStats(flags, s, shape, threads, result.seconds, result.rays, result.samples);
    j["nan_samples"] = result.nonFiniteSamples;
    writeJson(flags.statsPath, j);
  }
  printSummary(flags, s, shape.spp, result.seconds, result.rays, "");
  warnNonFinite(result.nonFiniteSamples);
}

// Any method: rounds until it is done (its budget, or a stopping rule), then the final snapshot.
void runProgressive(const RenderFlags& flags, const PreparedScene& prepared, const MethodSpec& spec,
                    int threads) {
  const Scene& s = prepared.scene;
  const RunShape& shape = spec.shape;
  std::unique_ptr<tbb::global_control> limit;
  if (flags.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(flags.threads));
  auto method = makeMethod(prepared, spec);
  ProgressBar bar(flags.method.method + " " + std::to_string(s.settings.width) + "x" +
                  std::to_string(s.settings.height) + " " + std::to_string(shape.spp) + " spp");
  std::vector<nlohmann::json> rounds;
  const double pixels = double(s.settings.width) * s.settings.height;
  while (!method->done()) {
    method->runRound(nullptr);
    if (!flags.statsPath.empty()) rounds.push_back(roundStats(*method->snapshot(false)));
    if (flags.quiet) continue;
    if (shape.timeLimit > 0)
      bar.update(std::min(1.0, method->seconds() / shape.timeLimit));
    else if (const double share = method->budgetShare(); share == share)
      bar.update(share);
  }
  const auto snap = method->snapshot();
  bar.finish();
  returnFreedMemory();  // the reconstruction's planes, kept for a next round that is not coming

  // A method without a reconstruction publishes its raw estimate as the reconstruction.
  writeOutput(flags, prepared, snap->reconstructed);
  if (!flags.rawPath.empty()) writeImage(flags.rawPath, snap->raw, flags.exposure);
  if (!flags.variancePath.empty()) writeImage(flags.variancePath, method->rawVarianceOfMean());
  if (!flags.aovDir.empty()) writeSnapshotMaps(flags.aovDir, *snap);
  if (!flags.statsPath.empty()) {
    nlohmann::json j =
        commonStats(flags, s, shape, threads, snap->seconds, snap->rays, snap->keptSamples);
    j.update(methodRunStats(spec, flags.method.preset, *snap, method->memoryBytes()));
    j["per_round"] = rounds;
    writeJson(flags.statsPath, j);
  }
  char extra[96];
  std::snprintf(extra, sizeof extra, " (%.1f traced), %d rounds",
                double(snap->tracedSamples) / pixels, snap->round);
  printSummary(flags, s, double(snap->keptSamples) / pixels, snap->seconds, snap->rays, extra);
  warnNonFinite(snap->nonFiniteSamples);
}

// --region x,y,w,h: only that window of the full image is rendered, and written, as a w x h
// image (the camera's view is the full image's; every sample lands inside the window).
void applyRegion(const std::string& text, Scene& scene) {
  const auto [x, y, w, h] = parseRegion(text, scene.settings.width, scene.settings.height);
  scene.camera.regionX = x;
  scene.camera.regionY = y;
  scene.camera.fullWidth = scene.settings.width;
  scene.camera.fullHeight = scene.settings.height;
  scene.settings.width = w;
  scene.settings.height = h;
}

// Plain LD, the method renderImage runs to its end: LD without its reconstruction.
bool isPlainLd(const MethodOptions& options) {
  const MethodDescriptor& method = options.descriptor();
  return &method == &ldMethod() &&
         !method.abilities(options.config(method, options.preset)).filters;
}

// --shard K/N: plain LD to an .exr, nothing that needs the whole image.
void checkShard(RenderFlags& flags) {
  try {
    parseShard(flags.shard);
  } catch (const std::invalid_argument& e) {
    throw CommandError(std::string("--shard: ") + e.what());
  }
  if (!isPlainLd(flags.method))
    throw CommandError("--shard: only the plain LD method (--method ld, no --filter) is sharded");
  if (flags.run.has("time-limit") || flags.run.has("noise-threshold") || !flags.aovDir.empty() ||
      !flags.region.empty() || !flags.rawPath.empty())
    throw CommandError(
        "--shard renders whole tiles of the image: not with --time-limit, --noise-threshold, "
        "--aov-dir, --raw-out or --region");
  if (lowercaseExtension(flags.output) != ".exr")
    throw CommandError("--output " + flags.output + ": a shard is written as .exr");
  if (flags.variancePath.empty()) flags.variancePath = siblingPath(flags.output, "_var", ".exr");
}

void run(RenderFlags flags) {
  if (!flags.shard.empty()) checkShard(flags);
  if (flags.scene.transparent && !flags.shard.empty())
    throw CommandError("--transparent: a shard has no alpha channel; render the image whole");
  if (flags.scene.transparent && lowercaseExtension(flags.output) == ".pfm")
    throw CommandError("--output " + flags.output +
                       ": --transparent writes an alpha channel, which PFM cannot hold: use .exr "
                       "or .png");
  prepareOutputs(flags);
  Scene scene = loadSceneWithOptions(flags.scene);
  if (!flags.region.empty()) applyRegion(flags.region, scene);
  auto prepared = prepareScene(std::move(scene));
  const int threads =
      flags.threads > 0 ? flags.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  const MethodSpec spec = flags.method.spec(renderShape(flags, prepared->scene));
  // Plain LD renders through renderImage, unless it needs the method's maps or stopping rules.
  if (isPlainLd(flags.method) && !spec.shape.hasStoppingRule() && flags.aovDir.empty())
    runLd(flags, *prepared, spec.shape, threads);
  else
    runProgressive(flags, *prepared, spec, threads);
}
}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto flags = std::make_shared<RenderFlags>();
  CLI::App* c = app.add_subcommand(
      "render", "Render a scene to an image (EXR/PFM linear, PNG tone-mapped sRGB)");
  addSceneOptions(*c, flags->scene);
  addRunOptions(*c, flags->run, kRenderCommand, RunShape::batch(16),
                {{"spp", "the scene's render.spp"}});
  c->add_option("-o,--output", flags->output,
                "Output image: .exr or .pfm (linear float) or .png (sRGB, 8 bit)")
      ->required();
  c->add_option("--region", flags->region,
                "Render only the window x,y,w,h of the image (pixels, top left first) and write "
                "it as a w x h image");
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--exposure", flags->exposure, "Exposure in stops applied to PNG output")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--stats", flags->statsPath,
                "Write statistics (time, rays, Mrays/s, spp, NaN count; for every method but "
                "plain LD also per-phase times, rounds, kept and traced spp, its parameters, its "
                "own figures and histograms of its error estimate and filter scale) as JSON");
  c->add_option("--variance-out", flags->variancePath,
                "Write the per-pixel variance of the mean (per channel) as an image, e.g. var.exr");
  c->add_option("--raw-out", flags->rawPath,
                "Adaptive methods: also write the raw estimate (before reconstruction, the box "
                "mean) to this image");
  c->add_option("--aov-dir", flags->aovDir,
                "Write the method's debug maps (its error estimate as bias, selected pixels, "
                "sample counts, filter scale and its own) as EXR and false-colour PNG into this "
                "folder");
  c->add_option(
      "--shard", flags->shard,
      "K/N: plain LD only, render shard K (from 0) of N by tile, for a job array; writes "
      "the image, its variance and OUTPUT.shard.json for `penumbra merge` (docs/farm.md)");
  c->add_flag("-q,--quiet", flags->quiet, "No progress bar or summary line");
  addMethodOptions(*c, flags->method);
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
