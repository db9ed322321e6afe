// `penumbra render`: renders a scene to an image file, with optional statistics.
#include "cli/commands.h"
#include "cli/json_file.h"
#include "cli/method_options.h"
#include "cli/progress.h"
#include "cli/scene_options.h"
#include "cli/shard_record.h"
#include "core/image_io.h"
#include "methods/factory.h"
#include "methods/render.h"
#include "present/snapshot_io.h"
#include "trace/integrator.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include <tbb/global_control.h>

namespace penumbra {

namespace {
struct RenderFlags {
  SceneOptions scene;
  MethodOptions method;
  std::string output, statsPath, variancePath, rawPath, aovDir, region;
  uint64_t seed = 0;
  int threads = 0;
  float exposure = 0;
  std::string samplerName = "ld";
  bool quiet = false;
  double timeLimit = 0;
  float noiseThreshold = 0;
  std::string shard;  // "K/N": plain LD, only shard K's tiles (docs/farm.md)
  SamplerKind sampler() const {
    return samplerName == "independent" ? SamplerKind::Independent : SamplerKind::LowDiscrepancy;
  }
};

// The statistics every method reports.
nlohmann::json commonStats(const RenderFlags& flags, const Scene& scene, int threads,
                           double seconds, uint64_t rays, uint64_t samples) {
  nlohmann::json j;
  j["scene"] = flags.scene.scenePath;
  j["method"] = toString(flags.method.method);
  j["width"] = scene.settings.width;
  j["height"] = scene.settings.height;
  j["spp"] = scene.settings.spp;
  j["seed"] = flags.seed;
  j["threads"] = threads;
  j["max_depth"] = scene.settings.maxDepth;
  j["sampler"] = flags.samplerName;
  j["time_seconds"] = seconds;
  j["rays"] = rays;
  j["mrays_per_second"] = seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0;
  j["samples"] = samples;
  return j;
}

void writeStats(const std::string& path, const RenderFlags& flags, const Scene& scene,
                const RenderResult& r, int threads) {
  nlohmann::json j = commonStats(flags, scene, threads, r.seconds, r.rays, r.samples);
  j["nan_samples"] = r.nonFiniteSamples;
  writeJson(path, j);
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

void prepareOutputs(const RenderFlags& flags) {
  // Fail on a bad output name before spending minutes rendering.
  checkImageExtension("--output", flags.output);
  if (!flags.variancePath.empty()) checkImageExtension("--variance-out", flags.variancePath);
  if (!flags.rawPath.empty()) checkImageExtension("--raw-out", flags.rawPath);
  const MethodSpec spec = flags.method.spec(RunShape::batch(16));
  // Every method but bp's paper and tuned presets keeps each pixel's variance of the mean.
  const bool hasFilm =
      !spec.get<BpConfig>() || spec.get<BpConfig>()->algorithm == BpAlgorithm::Consistent;
  const bool filters = spec.kind() != MethodKind::Ld || spec.get<LdConfig>()->filter;
  if (!filters && !flags.rawPath.empty())
    throw CommandError("--raw-out needs a method that filters (an adaptive --method, or --filter)");
  if (!hasFilm && !flags.variancePath.empty())
    throw CommandError(
        "--variance-out needs a method that keeps each pixel's variance: bp's paper and tuned "
        "presets do not (every other method does)");
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

void runLd(const RenderFlags& flags, const PreparedScene& prepared, int threads) {
  const Scene& s = prepared.scene;
  RenderOptions options;
  options.sampler = flags.sampler();
  options.seed = flags.seed;
  options.spp = s.settings.spp;
  options.threads = flags.threads;
  ProgressBar bar("render " + std::to_string(s.settings.width) + "x" +
                  std::to_string(s.settings.height) + " " + std::to_string(s.settings.spp) +
                  " spp");
  if (!flags.quiet) options.progress = [&bar](double f) { bar.update(f); };
  Shard shard;
  if (!flags.shard.empty()) {
    shard = parseShard(flags.shard);  // checked in run()
    options.pixelMask = shardPixelMask(s.settings.width, s.settings.height, shard);
  }
  const RenderResult result = renderImage(prepared, options);
  bar.finish();

  writeImage(flags.output, result.image, flags.exposure);
  if (!flags.variancePath.empty()) writeImage(flags.variancePath, result.varianceOfMean);
  if (!flags.shard.empty()) {
    ShardRecord record;
    record.command = "render";
    record.scene = flags.scene.scenePath;
    record.sceneHash = sceneHash(s);
    record.settings = pixelSettings(s, flags.scene, s.settings.spp, flags.seed, flags.sampler());
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
  if (!flags.statsPath.empty()) writeStats(flags.statsPath, flags, s, result, threads);
  printSummary(flags, s, s.settings.spp, result.seconds, result.rays, "");
  warnNonFinite(result.nonFiniteSamples);
}

void writeProgressiveStats(const std::string& path, const RenderFlags& flags, const Scene& scene,
                           const MethodSpec& spec, const Snapshot& snap,
                           const std::vector<nlohmann::json>& rounds, size_t memoryBytes,
                           int threads) {
  const double pixels = double(snap.width) * snap.height;
  nlohmann::json j = commonStats(flags, scene, threads, snap.seconds, snap.rays, snap.keptSamples);
  j["method"] = toString(spec.kind());
  j["description"] = describe(spec.kind());
  j["kept_spp"] = double(snap.keptSamples) / pixels;
  j["traced_spp"] = double(snap.tracedSamples) / pixels;
  j["rounds"] = snap.round;
  j["nan_samples"] = snap.nonFiniteSamples;
  j["rejected_samples"] = snap.rejectedSamples;
  j["phases"] = {{"trace", snap.times.trace},
                 {"train", snap.times.train},
                 {"select", snap.times.select},
                 {"reconstruct", snap.times.reconstruct}};
  j["adaptive_overhead"] =
      snap.times.total() > 0
          ? (snap.times.train + snap.times.select + snap.times.reconstruct) / snap.times.total()
          : 0.0;
  j["memory_bytes_per_pixel"] = double(memoryBytes) / pixels;
  // Every parameter of the method's table, under its name.
  nlohmann::json config = nlohmann::json::object();
  for (const MethodParam& p : methodParams(spec.kind())) {
    const std::string key = p.jsonKey();
    switch (p.kind) {
      case ParamKind::Int:
        config[key] = int(p.get(spec.config));
        break;
      case ParamKind::Float:  // as the flag would be written: 0.05, not 0.0500000007
        config[key] = std::strtod(formatParam(p, spec.config).c_str(), nullptr);
        break;
      case ParamKind::Flag:
        config[key] = p.get(spec.config) != 0;
        break;
      case ParamKind::Choice:
        config[key] = formatParam(p, spec.config);
        break;
      case ParamKind::FloatList: {
        std::vector<double> values;
        for (float v : p.getList(spec.config))
          values.push_back(std::strtod(formatBound(v).c_str(), nullptr));
        config[key] = values;
        break;
      }
    }
  }
  j["config"] = config;
  if (const BpConfig* bp = spec.get<BpConfig>()) {
    j["preset"] = toString(flags.method.preset);
    j["coarse_spp"] = bp->effectiveCoarseSpp(spec.shape);
    j["training_gflops"] = snap.trainingKernelSeconds > 0
                               ? double(snap.trainingFlops) / snap.trainingKernelSeconds * 1e-9
                               : 0.0;
    j["training_simd"] = networkSimdName();
    // ALGORITHM.md §5 and §9.5: the spread of bias decides how selective sampling and
    // filtering are, so both histograms are part of every run's record.
    const SnapshotMap* bias = snap.map(MapId::ErrorEstimate);
    j["bias_histogram"] = {
        {"bin_width", 0.05},
        {"counts", histogram(bias ? bias->values : std::vector<float>{}, 20, 1.0f)}};
    std::vector<uint64_t> alphaCounts(bp->filter.alphas.size(), 0);
    if (const SnapshotMap* alpha = snap.map(MapId::FilterScale))
      for (float a : alpha->values)
        if (a >= 0 && size_t(a) < alphaCounts.size()) ++alphaCounts[size_t(a)];
    j["alpha_histogram"] = {{"alphas", bp->filter.alphas}, {"counts", alphaCounts}};
  } else if (const SnapshotMap* scale = snap.map(MapId::FilterScale)) {
    const std::vector<std::string>& labels = scale->legend.categories;
    std::vector<uint64_t> counts(labels.size(), 0);
    for (float a : scale->values)
      if (a >= 0 && size_t(a) < counts.size()) ++counts[size_t(a)];
    j["filter_scale_histogram"] = {{"scales", labels}, {"counts", counts}};
  }
  j["per_round"] = rounds;
  writeJson(path, j);
}

// Every method but plain LD: rounds until the budget is spent, then the final snapshot.
void runProgressive(const RenderFlags& flags, const PreparedScene& prepared, int threads) {
  const Scene& s = prepared.scene;
  RunShape shape = RunShape::batch(s.settings.spp, flags.seed);
  if (flags.timeLimit > 0 || flags.noiseThreshold > 0) {
    // Open-ended rounds of 1 spp until a rule stops them; an explicit --spp caps them.
    shape = RunShape::progressive(1, flags.seed, flags.scene.spp.value_or(0));
    shape.timeLimit = flags.timeLimit;
    shape.noiseThreshold = flags.noiseThreshold;
  }
  shape.sampler = flags.sampler();
  const MethodSpec spec = flags.method.spec(shape);
  std::unique_ptr<tbb::global_control> limit;
  if (flags.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(flags.threads));
  auto method = makeMethod(prepared, spec);
  int maxRounds = 8;  // for the progress bar: the method's adaptive rounds
  for (const MethodParam& p : methodParams(spec.kind()))
    if (p.name == "rounds") maxRounds = int(p.get(spec.config));
  ProgressBar bar(std::string(toString(flags.method.method)) + " " +
                  std::to_string(s.settings.width) + "x" + std::to_string(s.settings.height) + " " +
                  std::to_string(s.settings.spp) + " spp");
  std::vector<nlohmann::json> rounds;
  const double pixels = double(s.settings.width) * s.settings.height;
  const bool wantRounds = !flags.statsPath.empty();
  if (shape.noiseThreshold > 0 && shape.timeLimit <= 0 && spec.get<BpConfig>() &&
      spec.get<BpConfig>()->algorithm != BpAlgorithm::Consistent)
    throw CommandError(
        "--noise-threshold: bp's paper and tuned presets have no error estimate to stop on (their "
        "bias is not one); use the consistent preset, or give --time-limit or --spp instead");
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  while (!method->done() && !method->stoppedByRule(shape, seconds())) {
    method->runRound(nullptr);
    if (wantRounds) {
      const auto snap = method->snapshot(false);
      const SnapshotMap* selected = snap->map(MapId::Selected);
      nlohmann::json round = {
          {"round", snap->round},
          {"kept_spp", double(snap->keptSamples) / pixels},
          {"traced_spp", double(snap->tracedSamples) / pixels},
          {"pixels_sampled",
           selected ? std::count(selected->values.begin(), selected->values.end(), 1.0f) : 0},
          {"seconds", snap->seconds}};
      const SnapshotMap* bias = snap->map(MapId::ErrorEstimate);
      const SnapshotMap* er = snap->map(MapId::NetworkError);
      const BpConfig* bp = spec.get<BpConfig>();
      if (bp && bias && er) {
        size_t difficult = 0;
        for (size_t p = 0; p < bias->values.size(); ++p)
          difficult += bias->values[p] > bp->psi && er->values[p] > bp->network.errorThreshold;
        round["difficult_pixels"] = difficult;
      }
      rounds.push_back(round);
    }
    if (!flags.quiet) {
      if (shape.timeLimit > 0)
        bar.update(std::min(1.0, seconds() / shape.timeLimit));
      else if (!shape.openEnded)
        bar.update(std::min(1.0, double(method->roundsDone()) / (maxRounds + 1)));
    }
  }
  const auto snap = method->snapshot();
  bar.finish();

  // A method without a reconstruction publishes its raw estimate as the reconstruction.
  writeImage(flags.output, snap->reconstructed, flags.exposure);
  if (!flags.rawPath.empty()) writeImage(flags.rawPath, snap->raw, flags.exposure);
  if (!flags.variancePath.empty()) writeImage(flags.variancePath, method->rawVarianceOfMean());
  if (!flags.aovDir.empty()) writeSnapshotMaps(flags.aovDir, *snap);
  if (!flags.statsPath.empty())
    writeProgressiveStats(flags.statsPath, flags, s, spec, *snap, rounds, method->memoryBytes(),
                          threads);
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

// --shard K/N: plain LD to an .exr, nothing that needs the whole image.
void checkShard(RenderFlags& flags) {
  try {
    parseShard(flags.shard);
  } catch (const std::invalid_argument& e) {
    throw CommandError(std::string("--shard: ") + e.what());
  }
  const MethodSpec spec = flags.method.spec(RunShape::batch(1));
  if (spec.kind() != MethodKind::Ld || spec.get<LdConfig>()->filter)
    throw CommandError("--shard: only the plain LD method (--method ld, no --filter) is sharded");
  if (flags.timeLimit > 0 || flags.noiseThreshold > 0 || !flags.aovDir.empty() ||
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
  prepareOutputs(flags);
  Scene scene = loadSceneWithOptions(flags.scene);
  if (!flags.region.empty()) applyRegion(flags.region, scene);
  auto prepared = prepareScene(std::move(scene));
  const int threads =
      flags.threads > 0 ? flags.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  const MethodSpec spec = flags.method.spec(RunShape::batch(prepared->scene.settings.spp));
  const bool plainLd = spec.kind() == MethodKind::Ld && !spec.get<LdConfig>()->filter;
  // Plain LD renders through renderImage (the same image as its method), unless it needs the
  // method's maps or stopping rules.
  if (plainLd && flags.timeLimit <= 0 && flags.noiseThreshold <= 0 && flags.aovDir.empty())
    runLd(flags, *prepared, threads);
  else
    runProgressive(flags, *prepared, threads);
}
}  // namespace

std::string& commandLine() {
  static std::string line;
  return line;
}

void registerRenderCommand(CLI::App& app) {
  auto flags = std::make_shared<RenderFlags>();
  CLI::App* c = app.add_subcommand(
      "render", "Render a scene to an image (EXR/PFM linear, PNG tone-mapped sRGB)");
  addSceneOptions(*c, flags->scene);
  c->add_option("-o,--output", flags->output,
                "Output image: .exr or .pfm (linear float) or .png (sRGB, 8 bit)")
      ->required();
  c->add_option("--region", flags->region,
                "Render only the window x,y,w,h of the image (pixels, top left first) and write "
                "it as a w x h image");
  c->add_option("--seed", flags->seed,
                "Random seed; the image is the same for a seed whatever the thread count");
  c->add_option("--time-limit", flags->timeLimit,
                "Stop after the round in which this many seconds have passed (open-ended rounds; "
                "--spp, when given, still caps them). Such a run need not be deterministic")
      ->check(CLI::Range(0.0, 1e9));
  c->add_option(
       "--noise-threshold", flags->noiseThreshold,
       "Stop once the image's mean estimated relMSE (of the filtered image, for a method "
       "that filters) is below this; pixels below it get no more samples (every method but "
       "bp's paper and tuned presets)")
      ->check(CLI::Range(0.0, 1e9));
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--exposure", flags->exposure, "Exposure in stops applied to PNG output")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--sampler", flags->samplerName,
                "Sample generator: ld (scrambled (0,2)-sequence, default) or independent")
      ->check(CLI::IsMember({"ld", "independent"}));
  c->add_option("--stats", flags->statsPath,
                "Write statistics (time, rays, Mrays/s, spp, NaN count; with --method bp also "
                "per-phase times, rounds, kept and traced spp, bias and alpha histograms) as JSON");
  c->add_option("--variance-out", flags->variancePath,
                "Write the per-pixel variance of the mean (per channel) as an image, e.g. var.exr");
  c->add_option("--raw-out", flags->rawPath,
                "Adaptive methods: also write the raw estimate (before reconstruction, the box "
                "mean) to this image");
  c->add_option("--aov-dir", flags->aovDir,
                "Adaptive methods: write the debug maps (the method's error estimate as bias; "
                "BP also er, I', slices B and C; selected pixels, sample counts, filter scale) "
                "as EXR and false-colour PNG into this folder");
  c->add_option(
      "--shard", flags->shard,
      "K/N: plain LD only, render shard K (from 0) of N by tile, for a job array; writes "
      "the image, its variance and OUTPUT.shard.json for `penumbra merge` (docs/farm.md)");
  c->add_flag("-q,--quiet", flags->quiet, "No progress bar or summary line");
  addMethodOptions(*c, flags->method);
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
