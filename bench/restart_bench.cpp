// What a restart costs before the first full picture, headless, phase by phase: what the
// viewer's worker does after a camera move (ALGORITHM.md §15: open-ended rounds of 1 spp),
// without the window's drawing. For each of the first rounds: the method's creation (the
// first round only), the round (tracing and the method's own work) and its snapshot, split
// into the reconstruction and the rest (the raw image and the maps). The median over the
// repeats, each a fresh method as after a move.
//
// Usage: penumbra_bench_restart [scene] [--size WxH] [--method NAME] [--rounds N]
//        [--repeats R] [--threads T] [--maps] [--profile-snapshots K]
// Without --maps the snapshots carry no debug maps, as in the window while no overlay is shown.
// --profile-snapshots K makes each round's snapshot K more times after the timed one (what
// `perf record` of the run then mostly sees).
// Default: the asset scene's asset.glb (scripts/make_asset_scene.sh) at 1280x720, bp, 3 rounds.
#include "cli/allocation.h"
#include "methods/factory.h"
#include "scene/scene_loader.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace penumbra;

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  configureAllocation();  // as `penumbra` allocates
  std::string scenePath = std::string(PENUMBRA_BENCH_DIR) + "/asset_scene/asset.glb";
  std::string method = "bp";
  int width = 1280, height = 720, rounds = 3, repeats = 3, profileSnapshots = 0;
  bool withMaps = false;
  int threads = int(std::thread::hardware_concurrency());
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "penumbra_bench_restart: %s needs a value\n", flag);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--size")) {
      const char* s = value("--size");
      if (std::sscanf(s, "%dx%d", &width, &height) != 2) width = height = 0;
    } else if (!std::strcmp(argv[i], "--method"))
      method = value("--method");
    else if (!std::strcmp(argv[i], "--rounds"))
      rounds = std::atoi(value("--rounds"));
    else if (!std::strcmp(argv[i], "--repeats"))
      repeats = std::atoi(value("--repeats"));
    else if (!std::strcmp(argv[i], "--maps"))
      withMaps = true;
    else if (!std::strcmp(argv[i], "--profile-snapshots"))
      profileSnapshots = std::atoi(value("--profile-snapshots"));
    else if (!std::strcmp(argv[i], "--threads"))
      threads = std::atoi(value("--threads"));
    else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::printf(
          "usage: penumbra_bench_restart [scene] [--size WxH] [--method NAME] [--rounds N] "
          "[--repeats R] [--threads T] [--maps] [--profile-snapshots K]\n");
      return 0;
    } else if (argv[i][0] == '-') {
      std::fprintf(stderr, "penumbra_bench_restart: unknown flag '%s' (see --help)\n", argv[i]);
      return 2;
    } else
      scenePath = argv[i];
  }
  if (width < 1 || height < 1 || rounds < 1 || repeats < 1 || threads < 1) {
    std::fprintf(stderr,
                 "penumbra_bench_restart: --size, --rounds, --repeats and --threads must be "
                 "positive\n");
    return 2;
  }
  try {
    Scene scene = loadScene(scenePath);
    scene.settings.width = width;
    scene.settings.height = height;
    auto prepared = prepareScene(std::move(scene));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const MethodSpec spec{RunShape::progressive(1), builtinMethods().configFor(method)};

    // Per round: the round, its snapshot, the snapshot's reconstruction; the creation apart.
    std::vector<double> create;
    const size_t n = size_t(rounds);
    std::vector<std::vector<double>> round(n), snap(n), recon(n), spp(n);
    // The round's own phases (the method's PhaseTimes, less its snapshot's reconstruction).
    std::vector<std::vector<PhaseTimes>> phases(n);
    for (int r = 0; r < repeats; ++r) {
      auto start = Clock::now();
      auto m = makeMethod(*prepared, spec);
      m->setMapsWanted(withMaps);
      create.push_back(since(start));
      double reconstructed = 0;
      PhaseTimes last;
      for (int k = 0; k < rounds && !m->done(); ++k) {
        start = Clock::now();
        m->runRound(nullptr);
        round[size_t(k)].push_back(since(start));
        start = Clock::now();
        auto s = m->snapshot();
        snap[size_t(k)].push_back(since(start));
        recon[size_t(k)].push_back(s->times.reconstruct - reconstructed);
        PhaseTimes own = s->times;
        own.trace -= last.trace, own.train -= last.train, own.select -= last.select;
        own.reconstruct -= last.reconstruct + recon[size_t(k)].back();
        phases[size_t(k)].push_back(own);
        // (--profile-snapshots: the same snapshot again, for a profiler; not timed.)
        for (int extra = 0; extra < profileSnapshots; ++extra) s = m->snapshot();
        reconstructed = s->times.reconstruct;
        last = s->times;
        spp[size_t(k)].push_back(double(s->keptSamples) / (double(width) * height));
        if (r == 0)
          std::printf("round %d: traced %.2f spp, %.2f rays a traced sample\n", k + 1,
                      double(s->tracedSamples) / (double(width) * height),
                      double(s->rays) / double(std::max<uint64_t>(1, s->tracedSamples)));
      }
    }
    std::printf("restart of %s at %dx%d, %d threads, %s, median of %d: create %.3f s\n",
                method.c_str(), width, height, threads, withMaps ? "with maps" : "no maps", repeats,
                median(create));
    double total = median(create);
    for (int k = 0; k < rounds && !round[size_t(k)].empty(); ++k) {
      const double rk = median(round[size_t(k)]), sk = median(snap[size_t(k)]),
                   ck = median(recon[size_t(k)]);
      total += rk + sk;
      std::printf(
          "round %d (%.2f spp kept): round %.3f s, snapshot %.3f s (reconstruction %.3f s, "
          "the rest %.3f s); picture at %.3f s\n",
          k + 1, median(spp[size_t(k)]), rk, sk, ck, sk - ck, total);
      // The phases of the repeat whose round took the median time.
      const auto& times = round[size_t(k)];
      const size_t at = size_t(std::find(times.begin(), times.end(), rk) - times.begin());
      const PhaseTimes& p = phases[size_t(k)][at];
      std::printf("  the round: trace %.3f s, train %.3f s, select %.3f s, reconstruct %.3f s\n",
                  p.trace, p.train, p.select, p.reconstruct);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_bench_restart: %s\n", e.what());
    return 1;
  }
  return 0;
}
