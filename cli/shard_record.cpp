#include "cli/shard_record.h"

#include "cli/commands.h"
#include "core/image_io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace penumbra {

namespace {
constexpr const char* kKind = "penumbra-shard";
constexpr int kVersion = 1;

void fnv(uint64_t& h, const void* data, size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
}
}  // namespace

std::string sceneHash(const Scene& scene) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (const std::string& file : scene.sourceFiles) {
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const uint64_t size = bytes.size();
    fnv(h, &size, sizeof size);  // so that moving bytes between files changes the hash
    fnv(h, bytes.data(), bytes.size());
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

nlohmann::json pixelSettings(const Scene& scene, const SceneOptions& options, int spp,
                             uint64_t seed, SamplerKind sampler) {
  const Camera& c = scene.camera;
  nlohmann::json j;
  j["width"] = scene.settings.width;
  j["height"] = scene.settings.height;
  j["spp"] = spp;
  j["seed"] = seed;
  j["max_depth"] = scene.settings.maxDepth;
  j["sampler"] = sampler == SamplerKind::Independent ? "independent" : "ld";
  j["camera"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
                 {"look_at", {c.lookAt.x, c.lookAt.y, c.lookAt.z}},
                 {"up", {c.up.x, c.up.y, c.up.z}},
                 {"fov", c.vfovDegrees},
                 {"orthographic_height", c.orthographicHeight},
                 {"lens_radius", c.lensRadius},
                 {"focus_distance", c.focusDistance},
                 {"shutter", {c.shutterOpen, c.shutterClose}}};
  const Environment& e = scene.environment;
  j["environment"] = {{"file", e.builtin ? "(built-in)" : e.file},
                      {"strength", e.strength},
                      {"rotation", e.rotationDegrees},
                      {"transparent", scene.transparent}};
  j["gltf_camera"] = options.camera;
  j["frame_time"] = options.frameTime ? nlohmann::json(*options.frameTime) : nlohmann::json();
  j["shutter_seconds"] =
      options.shutterSeconds ? nlohmann::json(*options.shutterSeconds) : nlohmann::json();
  j["texture_budget_mb"] =
      options.textureBudgetMb ? nlohmann::json(*options.textureBudgetMb) : nlohmann::json();
  return j;
}

std::string siblingPath(const std::string& path, const std::string& suffix,
                        const std::string& extension) {
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + suffix + extension)).string();
}

nlohmann::json referenceRecord(const std::string& scenePath, const std::string& image,
                               const std::string& variance, const Scene& s, int spp, uint64_t seed,
                               const RenderResult& r, const Convergence& converged) {
  nlohmann::json j;
  j["scene"] = scenePath;
  j["image"] = image;
  j["variance"] = variance;
  j["width"] = s.settings.width;
  j["height"] = s.settings.height;
  j["spp"] = spp;
  j["seed"] = seed;
  j["max_depth"] = s.settings.maxDepth;
  j["time_seconds"] = r.seconds;
  j["rays"] = r.rays;
  j["nan_samples"] = r.nonFiniteSamples;
  j["mean_relative_standard_error"] = converged.meanRelativeError;
  j["residual_mse"] = converged.residualMse;
  return j;
}

void prepareLinearOutputs(const std::string& what, const std::string& output,
                          std::string& variancePath, std::string& statsPath) {
  try {
    checkWritableImagePath(output);
  } catch (const ImageIoError& e) {
    throw CommandError(std::string("--output ") + e.what());
  }
  if (lowercaseExtension(output) == ".png")
    throw CommandError("--output " + output + ": " + what + " must be linear: use .exr or .pfm");
  if (variancePath.empty()) variancePath = siblingPath(output, "_var", ".exr");
  if (statsPath.empty()) statsPath = siblingPath(output, "", ".json");
  for (const std::string& path : {output, variancePath, statsPath}) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (ec) throw CommandError(path + ": cannot create directory: " + ec.message());
  }
}

std::string shardRecordPath(const std::string& imagePath) {
  const std::filesystem::path p(imagePath);
  return (p.parent_path() / (p.stem().string() + ".shard.json")).string();
}

nlohmann::json ShardRecord::toJson() const {
  nlohmann::json j;
  j["kind"] = kKind;
  j["version"] = kVersion;
  j["command"] = command;
  j["scene"] = scene;
  j["scene_hash"] = sceneHash;
  j["settings"] = settings;
  j["shard"] = shard.index;
  j["shards"] = shard.count;
  j["tile_size"] = kShardTile;
  j["tiles"] = tiles;
  j["width"] = width;
  j["height"] = height;
  j["image"] = image;
  j["variance"] = variance;
  j["time_seconds"] = seconds;
  j["rays"] = rays;
  j["nan_samples"] = nanSamples;
  return j;
}

ShardRecord ShardRecord::fromJson(const nlohmann::json& j, const std::string& path) {
  const auto fail = [&](const std::string& field, const std::string& why) {
    throw CommandError(path + ": " + field + ": " + why);
  };
  if (!j.is_object() || j.value("kind", "") != kKind)
    throw CommandError(path + ": not a shard record (no \"kind\": \"" + kKind + "\")");
  if (j.value("version", 0) != kVersion) fail("version", "expected " + std::to_string(kVersion));
  ShardRecord r;
  try {
    r.command = j.at("command").get<std::string>();
    r.scene = j.at("scene").get<std::string>();
    r.sceneHash = j.at("scene_hash").get<std::string>();
    r.settings = j.at("settings");
    r.shard.index = j.at("shard").get<int>();
    r.shard.count = j.at("shards").get<int>();
    r.tiles = j.at("tiles").get<std::vector<int>>();
    r.width = j.at("width").get<int>();
    r.height = j.at("height").get<int>();
    r.image = j.at("image").get<std::string>();
    r.variance = j.at("variance").get<std::string>();
    r.seconds = j.at("time_seconds").get<double>();
    r.rays = j.at("rays").get<uint64_t>();
    r.nanSamples = j.at("nan_samples").get<uint64_t>();
  } catch (const nlohmann::json::exception& e) {
    throw CommandError(path + ": " + e.what());
  }
  if (j.value("tile_size", 0) != kShardTile)
    fail("tile_size", "expected " + std::to_string(kShardTile));
  if (!(r.shard.count >= 1 && r.shard.index >= 0 && r.shard.index < r.shard.count))
    fail("shard", std::to_string(r.shard.index) + " of " + std::to_string(r.shard.count) +
                      " is not a shard");
  if (!(r.width >= 1 && r.height >= 1 && r.width <= 16384 && r.height <= 16384))
    fail("width", "not an image size");
  if (r.tiles != shardTiles(r.width, r.height, r.shard))
    fail("tiles", "not the tiles of shard " + std::to_string(r.shard.index) + " of " +
                      std::to_string(r.shard.count));
  return r;
}

}  // namespace penumbra
