// `penumbra reference`: a converged low-discrepancy render to compare methods against
// (ALGORITHM.md §11), with its per-pixel variance of the mean and a JSON record of how
// converged it is, so a user can tell whether a reference is good enough for the errors
// they want to measure.
#include "cli/commands.h"
#include "cli/json_file.h"
#include "cli/plan.h"
#include "cli/progress.h"
#include "cli/run_options.h"
#include "cli/scene_options.h"
#include "cli/shard_record.h"
#include "core/image_io.h"
#include "eval/metrics.h"
#include "eval/reference.h"
#include "methods/render.h"
#include "trace/integrator.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>

namespace penumbra {

namespace {

// A reference's own spp and seed (far from the seeds the comparisons use, 1, 2, ...), or the
// flags'; always low discrepancy.
RunShape referenceShape(const RunOptions& options) {
  RunShape shape = RunShape::batch(8192, 999);
  options.apply(shape);
  return shape;
}

struct ReferenceFlags {
  SceneOptions scene;
  RunOptions run;
  std::string output, variancePath, statsPath;
  int threads = 0;
  bool quiet = false;
  std::string shard;  // "K/N": render only shard K's tiles (docs/farm.md)
  std::string plan;   // a folder: write the tasks of a sharded render instead of rendering
  int shards = 0;     // with --plan: how many
};

// --plan DIR --shards N: N tasks, each this command with --shard k/N into DIR/parts, and a
// merge into the output.
void writeReferencePlan(const ReferenceFlags& flags) {
  namespace fs = std::filesystem;
  if (flags.shards < 1) throw CommandError("--plan needs --shards N (N >= 1)");
  if (!flags.shard.empty()) throw CommandError("--plan writes every shard's task: no --shard");
  if (lowercaseExtension(flags.output) != ".exr")
    throw CommandError("--output " + flags.output + ": a merged reference is written as .exr");
  const std::string dir = fs::absolute(flags.plan).lexically_normal().string();
  const std::vector<std::string> kept = argumentsWithout(
      {"-o", "--output", "--plan", "--shards", "--shard", "--variance-out", "--stats"},
      {"-q", "--quiet"}, flags.scene.scenePath);
  std::string common = shellQuote(executablePath());
  for (const std::string& a : kept) common += " " + shellQuote(a);
  std::vector<std::string> tasks;
  std::string merge = shellQuote(executablePath()) + " merge";
  for (int k = 0; k < flags.shards; ++k) {
    const std::string part = dir + "/parts/part_" + std::to_string(k) + ".exr";
    tasks.push_back(common + " --shard " + std::to_string(k) + "/" + std::to_string(flags.shards) +
                    " -o " + shellQuote(part) + " -q");
    merge += " " + shellQuote(part);
  }
  const auto absolute = [](const std::string& path) {
    return shellQuote(fs::absolute(path).lexically_normal().string());
  };
  merge += " -o " + absolute(flags.output) + " --variance-out " + absolute(flags.variancePath) +
           " --stats " + absolute(flags.statsPath);
  writePlan(dir, "reference", tasks, {merge});
  if (!flags.quiet)
    std::printf("%s: %d tasks (tasks.txt), then the merge into %s (finish.txt)\n", dir.c_str(),
                flags.shards, flags.output.c_str());
}

void run(ReferenceFlags flags) {
  if (!flags.plan.empty()) {  // the merge writes the outputs: only their names are needed
    if (flags.variancePath.empty()) flags.variancePath = siblingPath(flags.output, "_var", ".exr");
    if (flags.statsPath.empty()) flags.statsPath = siblingPath(flags.output, "", ".json");
    return writeReferencePlan(flags);
  }
  if (flags.shards > 0) throw CommandError("--shards N goes with --plan DIR (or use --shard K/N)");
  prepareLinearOutputs("a reference", flags.output, flags.variancePath, flags.statsPath);

  const RunShape shape = referenceShape(flags.run);
  if (const std::string problem = shape.validate(); !problem.empty()) throw CommandError(problem);
  Shard shard;
  if (!flags.shard.empty()) {
    try {
      shard = parseShard(flags.shard);
    } catch (const std::invalid_argument& e) {
      throw CommandError(std::string("--shard: ") + e.what());
    }
    if (lowercaseExtension(flags.output) != ".exr")
      throw CommandError("--output " + flags.output + ": a shard is written as .exr");
  }
  Scene scene = loadSceneWithOptions(flags.scene);
  auto prepared = prepareScene(std::move(scene));
  const Scene& s = prepared->scene;
  const int w = s.settings.width, h = s.settings.height;
  ProgressBar bar("reference " + std::to_string(w) + "x" + std::to_string(h) + " " +
                  std::to_string(shape.spp) + " spp" +
                  (flags.shard.empty() ? "" : ", shard " + flags.shard));
  std::function<void(double)> progress;
  if (!flags.quiet) progress = [&bar](double f) { bar.update(f); };
  const Reference ref =
      renderReference(*prepared, shape.spp, shape.seed, flags.threads, progress,
                      flags.shard.empty() ? std::vector<uint8_t>() : shardPixelMask(w, h, shard));
  bar.finish();
  const RenderResult& r = ref.render;
  writeImage(flags.output, r.image);
  writeImage(flags.variancePath, r.varianceOfMean);
  if (!flags.shard.empty()) {
    // A shard's record instead of the reference's: `penumbra merge` makes that one.
    ShardRecord record;
    record.command = "reference";
    record.scene = flags.scene.scenePath;
    record.sceneHash = sceneHash(s);
    record.settings =
        pixelSettings(s, flags.scene, shape.spp, shape.seed, SamplerKind::LowDiscrepancy);
    record.shard = shard;
    record.tiles = shardTiles(w, h, shard);
    record.width = w;
    record.height = h;
    record.image = flags.output;
    record.variance = flags.variancePath;
    record.seconds = r.seconds;
    record.rays = r.rays;
    record.nanSamples = r.nonFiniteSamples;
    const std::string recordPath = shardRecordPath(flags.output);
    writeJson(recordPath, record.toJson());
    if (!flags.quiet)
      std::printf("%s: shard %d of %d (%zu tiles), %.1f s; record %s\n", flags.output.c_str(),
                  shard.index, shard.count, record.tiles.size(), r.seconds, recordPath.c_str());
  } else {
    writeJson(flags.statsPath,
              referenceRecord(flags.scene.scenePath, flags.output, flags.variancePath, s, shape.spp,
                              shape.seed, r, ref.convergence));
    if (!flags.quiet)
      std::printf(
          "%s: %dx%d, %d spp, %.1f s; variance %s; residual MSE %.3g (mean relative "
          "error %.3g)\n",
          flags.output.c_str(), w, h, shape.spp, r.seconds, flags.variancePath.c_str(),
          ref.convergence.residualMse, ref.convergence.meanRelativeError);
  }
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
  addRunOptions(*c, flags->run, kReferenceCommand, referenceShape({}));
  c->add_option("-o,--output", flags->output, "Reference image (.exr or .pfm)")->required();
  c->add_option("--variance-out", flags->variancePath,
                "Per-pixel variance of the mean (default: OUTPUT_var.exr)");
  c->add_option("--stats", flags->statsPath, "JSON record (default: OUTPUT with .json)");
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option(
      "--shard", flags->shard,
      "K/N: render only shard K (from 0) of N, by tile, for a job array; writes the "
      "shard's image, variance and OUTPUT.shard.json for `penumbra merge` (docs/farm.md)");
  c->add_option("--plan", flags->plan,
                "Write the tasks of a sharded reference into this folder instead of rendering: "
                "tasks.txt (one command per shard) and finish.txt (the merge), for a job array "
                "(scripts/farm, docs/farm.md)");
  c->add_option("--shards", flags->shards, "With --plan: the number of shards")
      ->check(CLI::Range(1, 65536));
  c->add_flag("-q,--quiet", flags->quiet, "No progress bar or summary line");
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
