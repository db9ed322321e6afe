// Speed of the film's reconstruction (methods/film_reconstruction.h, the default bp's and
// filtered LD's), on a synthetic film: a procedural image with colour, albedo, normal and depth
// edges, `--spp` noisy samples per pixel. The sweep's cost does not depend on the values (it
// has no branches on them), so a synthetic film times it as a render's would. Prints the
// median of `--repeats` reconstructions, the bytes the reconstruction adds at its peak (the
// process's peak RSS before and after) and whether any output is not finite. With --coarse,
// the half-resolution reconstruction of a large image's first pictures (reconstructPicture
// of a picture that is not final at --spp samples per pixel: recon::denoiseCoarse from
// kCoarsePixels up, while --spp is at most the default coarse-recon-spp).
//
// Usage: penumbra_bench_recon [--size WxH] [--spp N] [--repeats R] [--threads T] [--coarse]
#include "methods/film.h"
#include "methods/film_reconstruction.h"

#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace penumbra;

namespace {

// VmHWM (peak resident set) of this process, in bytes.
size_t peakRss() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return size_t(std::atoll(line.c_str() + 6)) * 1024;
  return 0;
}

// CPU seconds of this process (all threads): on a shared machine a steadier figure than the
// wall time, which counts the other jobs' turns.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec) +
         double(usage.ru_stime.tv_sec) + 1e-6 * double(usage.ru_stime.tv_usec);
}

void fill(Film& film, int spp, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const int w = film.width(), h = film.height();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool right = x > w / 2 + y / 4, low = y > h / 2;
      const float stripe = (x / 8) % 2 ? 0.7f : 0.3f;
      PathFeatures f;
      f.albedo = low ? vec3(stripe, 0.8f * stripe, 0.5f) : vec3(0.6f, 0.5f, 0.4f);
      f.normal = right ? vec3(0.0f, 0.0f, 1.0f) : vec3(0.6f, 0.0f, 0.8f);
      f.depth = 2.0f + float(y) / float(h) + (right ? 1.0f : 0.0f);
      const vec3 light(0.3f + 0.7f * float(x) / float(w), right ? 1.2f : 0.5f, 0.8f);
      for (int s = 0; s < spp; ++s) {
        // A heavy-tailed sample: mostly dim, sometimes bright, as a path tracer's are.
        const float r = u(rng);
        const float gain = r < 0.9f ? 0.6f * r / 0.9f : 4.0f * (r - 0.9f) / 0.1f + 1.0f;
        film.add(size_t(y) * w + x, light * f.albedo * gain, f);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int width = 1280, height = 720, spp = 4, repeats = 5;
  int threads = int(std::thread::hardware_concurrency());
  bool coarse = false;
  for (int i = 1; i < argc; ++i) {
    auto next = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "penumbra_bench_recon: %s needs a value\n", flag);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--size")) {
      if (std::sscanf(next("--size"), "%dx%d", &width, &height) != 2) {
        std::fprintf(stderr, "penumbra_bench_recon: --size takes WxH\n");
        return 2;
      }
    } else if (!std::strcmp(argv[i], "--spp")) {
      spp = std::atoi(next("--spp"));
    } else if (!std::strcmp(argv[i], "--repeats")) {
      repeats = std::atoi(next("--repeats"));
    } else if (!std::strcmp(argv[i], "--threads")) {
      threads = std::atoi(next("--threads"));
    } else if (!std::strcmp(argv[i], "--coarse")) {
      coarse = true;
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::printf(
          "usage: penumbra_bench_recon [--size WxH] [--spp N] [--repeats R] [--threads T] "
          "[--coarse]\n");
      return 0;
    } else {
      std::fprintf(stderr, "penumbra_bench_recon: unknown argument '%s' (see --help)\n", argv[i]);
      return 2;
    }
  }
  if (width < 1 || height < 1 || spp < 1 || repeats < 1 || threads < 1) {
    std::fprintf(stderr, "penumbra_bench_recon: sizes, --spp, --repeats, --threads must be > 0\n");
    return 2;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  Film film(width, height);
  fill(film, spp, 1);
  const recon::DenoiseConfig config;
  const size_t before = peakRss();
  std::vector<double> seconds, cpu;
  size_t nonFinite = 0, identity = 0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = cpuSeconds();
    const recon::DenoiseResult result = coarse
                                            ? reconstructPicture(film, config, double(spp), false)
                                            : reconstructFilm(film, config);
    cpu.push_back(cpuSeconds() - cpuStart);
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (r == 0) {
      for (const vec3& c : result.output.pixels) nonFinite += isFinite(c) ? 0 : 1;
      for (uint8_t s : result.scale) identity += s == 0 ? 1 : 0;
    }
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(cpu.begin(), cpu.end());
  const double pixels = double(width) * height;
  std::printf(
      "reconstruction %dx%d, %d spp, %d threads: median %.3f s (min %.3f, max %.3f) of %d\n", width,
      height, spp, threads, seconds[seconds.size() / 2], seconds.front(), seconds.back(), repeats);
  std::printf("cpu time median %.3f s (wall x threads would be %.3f s)\n", cpu[cpu.size() / 2],
              seconds[seconds.size() / 2] * threads);
  std::printf("film %.0f bytes per pixel; reconstruction peak adds %.0f bytes per pixel\n",
              double(film.memoryBytes()) / pixels, double(peakRss() - before) / pixels);
  std::printf("non-finite outputs %zu; identity chosen at %.1f %% of pixels\n", nonFinite,
              100.0 * double(identity) / pixels);
  return nonFinite ? 1 : 0;
}
