// `penumbra render`: renders a scene to an image file, with optional statistics.
#include "engine/image_io.h"
#include "engine/integrator.h"
#include "engine/render.h"
#include "viewer/commands.h"
#include "viewer/progress.h"
#include "viewer/scene_options.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

namespace penumbra {

namespace {
struct RenderFlags {
  SceneOptions scene;
  std::string output, statsPath, variancePath;
  uint64_t seed = 0;
  int threads = 0;
  float exposure = 0;
  std::string samplerName = "ld";
  bool quiet = false;
  SamplerKind sampler() const {
    return samplerName == "independent" ? SamplerKind::Independent : SamplerKind::LowDiscrepancy;
  }
};

void writeStats(const std::string& path, const RenderFlags& flags, const Scene& scene,
                const RenderResult& r, int threads) {
  nlohmann::json j;
  j["scene"] = flags.scene.scenePath;
  j["width"] = scene.settings.width;
  j["height"] = scene.settings.height;
  j["spp"] = scene.settings.spp;
  j["seed"] = flags.seed;
  j["threads"] = threads;
  j["max_depth"] = scene.settings.maxDepth;
  j["sampler"] = flags.samplerName;
  j["time_seconds"] = r.seconds;
  j["rays"] = r.rays;
  j["mrays_per_second"] = r.seconds > 0 ? double(r.rays) / r.seconds * 1e-6 : 0.0;
  j["samples"] = r.samples;
  j["nan_samples"] = r.nonFiniteSamples;
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) throw ImageIoError(path + ": cannot write");
  });
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

void run(const RenderFlags& flags) {
  // Fail on a bad output name before spending minutes rendering.
  checkImageExtension("--output", flags.output);
  if (!flags.variancePath.empty()) checkImageExtension("--variance-out", flags.variancePath);
  for (const std::string* path : {&flags.output, &flags.statsPath, &flags.variancePath})
    if (!path->empty()) createParentDirectory(*path);
  Scene scene = loadSceneWithOptions(flags.scene);
  auto prepared = prepareScene(std::move(scene));
  const Scene& s = prepared->scene;
  RenderOptions options;
  options.sampler = flags.sampler();
  options.seed = flags.seed;
  options.spp = s.settings.spp;
  options.threads = flags.threads;
  const int threads =
      flags.threads > 0 ? flags.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  ProgressBar bar("render " + std::to_string(s.settings.width) + "x" +
                  std::to_string(s.settings.height) + " " + std::to_string(s.settings.spp) +
                  " spp");
  if (!flags.quiet) options.progress = [&bar](double f) { bar.update(f); };
  const RenderResult result = renderImage(*prepared, options);
  bar.finish();

  writeImage(flags.output, result.image, flags.exposure);
  if (!flags.variancePath.empty()) writeImage(flags.variancePath, result.varianceOfMean);
  if (!flags.statsPath.empty()) writeStats(flags.statsPath, flags, s, result, threads);
  if (!flags.quiet) {
    std::printf("%s: %dx%d, %d spp, %.2f s, %.2f Mrays/s\n", flags.output.c_str(), s.settings.width,
                s.settings.height, s.settings.spp, result.seconds,
                result.seconds > 0 ? double(result.rays) / result.seconds * 1e-6 : 0.0);
  }
  if (result.nonFiniteSamples > 0)
    std::fprintf(stderr, "penumbra render: warning: %llu NaN or infinite samples were dropped\n",
                 static_cast<unsigned long long>(result.nonFiniteSamples));
}
}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto flags = std::make_shared<RenderFlags>();
  CLI::App* c = app.add_subcommand(
      "render", "Render a scene to an image (EXR/PFM linear, PNG tone-mapped sRGB)");
  addSceneOptions(*c, flags->scene);
  c->add_option("-o,--output", flags->output,
                "Output image: .exr or .pfm (linear float) or .png (sRGB, 8 bit)")
      ->required();
  c->add_option("--seed", flags->seed,
                "Random seed; the image is the same for a seed whatever the thread count");
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--exposure", flags->exposure, "Exposure in stops applied to PNG output")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--sampler", flags->samplerName,
                "Sample generator: ld (scrambled (0,2)-sequence, default) or independent")
      ->check(CLI::IsMember({"ld", "independent"}));
  c->add_option("--stats", flags->statsPath,
                "Write statistics (time, rays, Mrays/s, spp, NaN count) as JSON");
  c->add_option("--variance-out", flags->variancePath,
                "Write the per-pixel variance of the mean (per channel) as an image, e.g. var.exr");
  c->add_flag("-q,--quiet", flags->quiet, "No progress bar or summary line");
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
