// `penumbra merge PARTS... -o out.exr`: puts the shards of a render (`reference|render --shard
// K/N`) back together. It checks that the parts belong together (the same scene hash, the same
// settings, the same shard count) and that every shard is there exactly once, then copies each
// shard's tiles into the image and its variance, and writes the reference's JSON record. Every
// pixel of a shard is the unsharded render's, so the merged image is byte for byte the
// unsharded one, whatever the order of the parts. docs/farm.md.
#include "cli/commands.h"
#include "cli/json_file.h"
#include "cli/shard_record.h"
#include "core/image_io.h"
#include "eval/metrics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

namespace penumbra {

namespace {

namespace fs = std::filesystem;

struct MergeFlags {
  std::vector<std::string> parts;
  std::string output, variancePath, statsPath;
  bool quiet = false;
};

// A part as given: its record (STEM.shard.json beside an image, or the record itself).
struct Part {
  std::string recordPath;
  ShardRecord record;
};

Part readPart(const std::string& given) {
  Part part;
  part.recordPath = given.size() > 11 && given.compare(given.size() - 11, 11, ".shard.json") == 0
                        ? given
                        : shardRecordPath(given);
  std::ifstream in(part.recordPath);
  if (!in)
    throw CommandError(part.recordPath + ": cannot open the shard record (of part '" + given +
                       "')");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw CommandError(part.recordPath + ": " + e.what());
  }
  part.record = ShardRecord::fromJson(j, part.recordPath);
  return part;
}

// A file the record names: as written, or beside the record (parts copied off their nodes).
std::string locate(const std::string& named, const std::string& recordPath) {
  if (fs::exists(named)) return named;
  const std::string beside =
      (fs::path(recordPath).parent_path() / fs::path(named).filename()).string();
  if (fs::exists(beside)) return beside;
  throw CommandError(recordPath + ": '" + named + "' not found (nor beside the record)");
}

Image readPartImage(const std::string& named, const Part& part) {
  const std::string path = locate(named, part.recordPath);
  Image image = readImage(path);
  if (image.width != part.record.width || image.height != part.record.height)
    throw CommandError(path + ": " + std::to_string(image.width) + "x" +
                       std::to_string(image.height) + ", its record says " +
                       std::to_string(part.record.width) + "x" +
                       std::to_string(part.record.height));
  return image;
}

void run(MergeFlags flags) {
  prepareLinearOutputs("a merged render", flags.output, flags.variancePath, flags.statsPath);

  std::vector<Part> parts;
  for (const std::string& given : flags.parts) parts.push_back(readPart(given));
  const ShardRecord& first = parts.front().record;
  const int count = first.shard.count;
  std::map<int, const Part*> byIndex;
  for (const Part& part : parts) {
    const ShardRecord& r = part.record;
    const auto differs = [&](const std::string& what) {
      throw CommandError(part.recordPath + ": " + what + " from " + parts.front().recordPath +
                         "'s: the parts are not of one render");
    };
    if (r.sceneHash != first.sceneHash) differs("its scene (the hash of its files) differs");
    if (r.settings != first.settings)
      differs("its settings (size, spp, seed, depth, camera) differ");
    if (r.command != first.command) differs("its command differs");
    if (r.shard.count != count) differs("its shard count differs");
    const auto [at, inserted] = byIndex.emplace(r.shard.index, &part);
    if (!inserted)
      throw CommandError("shard " + std::to_string(r.shard.index) +
                         " is given twice: " + at->second->recordPath + " and " + part.recordPath);
  }
  std::string missing;
  for (int k = 0; k < count; ++k)
    if (!byIndex.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (!missing.empty())
    throw CommandError("missing shard(s) " + missing + " of " + std::to_string(count) + " (from " +
                       std::to_string(parts.size()) + " part(s))");

  Image image(first.width, first.height), variance(first.width, first.height);
  RenderResult total;
  for (const auto& [index, part] : byIndex) {
    copyShardPixels(readPartImage(part->record.image, *part), part->record.shard, image);
    copyShardPixels(readPartImage(part->record.variance, *part), part->record.shard, variance);
    total.seconds += part->record.seconds;
    total.rays += part->record.rays;
    total.nonFiniteSamples += part->record.nanSamples;
  }
  const Convergence converged = convergenceOf(image, variance);
  writeImage(flags.output, image);
  writeImage(flags.variancePath, variance);
  Scene settings;
  settings.settings.width = first.width;
  settings.settings.height = first.height;
  settings.settings.maxDepth = first.settings.at("max_depth").get<int>();
  nlohmann::json j = referenceRecord(first.scene, flags.output, flags.variancePath, settings,
                                     first.settings.at("spp").get<int>(),
                                     first.settings.at("seed").get<uint64_t>(), total, converged);
  j["shards"] = count;  // time_seconds and rays are the parts' sums
  writeJson(flags.statsPath, j);
  if (!flags.quiet)
    std::printf("%s: %d shards merged, %dx%d; variance %s; residual MSE %.3g\n",
                flags.output.c_str(), count, first.width, first.height, flags.variancePath.c_str(),
                converged.residualMse);
}

}  // namespace

void registerMergeCommand(CLI::App& app) {
  auto flags = std::make_shared<MergeFlags>();
  CLI::App* c = app.add_subcommand(
      "merge",
      "Merge the shards of a render (reference|render --shard K/N) into one image, its "
      "variance and a JSON record; byte for byte the unsharded render (docs/farm.md)");
  c->add_option("parts", flags->parts,
                "The shards' images (.exr) or records (.shard.json), in any order")
      ->required();
  c->add_option("-o,--output", flags->output, "Merged image (.exr or .pfm)")->required();
  c->add_option("--variance-out", flags->variancePath,
                "Merged variance of the mean (default: OUTPUT_var.exr)");
  c->add_option("--stats", flags->statsPath, "JSON record (default: OUTPUT with .json)");
  c->add_flag("-q,--quiet", flags->quiet, "No summary line");
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
