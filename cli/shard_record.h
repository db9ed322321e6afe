// The record a shard of a render writes beside its image (`reference|render --shard K/N`), and
// what `penumbra merge` checks before it puts the shards back together: the same scene (a hash
// of every file it was read from), the same settings that decide the pixels, the same shard
// count, and each shard once. docs/farm.md.
#pragma once

#include "cli/scene_options.h"
#include "eval/metrics.h"
#include "methods/render.h"
#include "methods/shard.h"
#include "scene/scene.h"
#include "trace/sampler.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace penumbra {

// A hex FNV-1a hash of the contents of every file the scene was read from, in order.
std::string sceneHash(const Scene& scene);

// Everything but the scene's files that decides a plain LD render's pixels: size, spp, seed,
// depth, sampler, the camera after its flags, and the glTF animation flags.
nlohmann::json pixelSettings(const Scene& scene, const SceneOptions& options, int spp,
                             uint64_t seed, SamplerKind sampler);

// PATH's folder / PATH's stem + suffix + extension.
std::string siblingPath(const std::string& path, const std::string& suffix,
                        const std::string& extension);

// Checks a linear image output (`--output` must be writable, not .png: `what` names what is
// written, "a reference"), fills in the defaults OUTPUT_var.exr and OUTPUT.json, and creates the
// three files' folders. Throws CommandError naming the file.
void prepareLinearOutputs(const std::string& what, const std::string& output,
                          std::string& variancePath, std::string& statsPath);

// The JSON record `penumbra reference` writes beside a reference (and `merge` beside the merged
// shards): what was rendered and how converged it is.
nlohmann::json referenceRecord(const std::string& scenePath, const std::string& image,
                               const std::string& variance, const Scene& s, int spp, uint64_t seed,
                               const RenderResult& r, const Convergence& converged);

// The record's path for a shard whose image is `imagePath`: beside it, STEM.shard.json.
std::string shardRecordPath(const std::string& imagePath);

struct ShardRecord {
  std::string command;  // "reference" or "render"
  std::string scene;    // the scene file as given
  std::string sceneHash;
  nlohmann::json settings;
  Shard shard;
  std::vector<int> tiles;
  int width = 0, height = 0;
  std::string image, variance;  // as written (paths relative to the record's folder work too)
  double seconds = 0;
  uint64_t rays = 0, nanSamples = 0;

  nlohmann::json toJson() const;
  // Throws CommandError naming `path` and the field when the record is not one.
  static ShardRecord fromJson(const nlohmann::json& j, const std::string& path);
};

}  // namespace penumbra
