// Speed of the multidimensional networks' training (methods/bp/mdnet.h): the scalar fit and
// the lane-group kernel (fitBatch) on the same pixels, and the kernel's share of the machine's
// FMA peak. Each pixel trains on `--samples` samples of a sheared step over (dx, dy, u, v) for
// `--epochs` epochs, as a 5x5 neighbourhood at 16 spp would; `--inputs` above 4 adds inputs
// the step does not depend on (time, the light's chart: `bp --networks 1` fits 4 to 7).
//
// Usage: penumbra_bench_mdnet [--pixels N] [--samples S] [--epochs E] [--hidden H] [--inputs I]
#include "core/rng.h"
#include "methods/bp/mdnet.h"
#include "methods/bp/network.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

using namespace penumbra;

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

int main(int argc, char** argv) {
  int pixels = 512, samples = 400, epochs = 300, hidden = 8, inputs = 4;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
    if (a == "--pixels")
      pixels = std::max(1, next());
    else if (a == "--samples")
      samples = std::max(1, next());
    else if (a == "--epochs")
      epochs = std::max(1, next());
    else if (a == "--hidden")
      hidden = std::clamp(next(), 1, mdnet::kMaxHidden);
    else if (a == "--inputs")
      inputs = std::clamp(next(), 4, mdnet::kMaxInputs);
    else {
      std::fprintf(stderr,
                   "penumbra_bench_mdnet: unknown flag %s\nusage: %s [--pixels N] [--samples S] "
                   "[--epochs E] [--hidden H] [--inputs I]\n",
                   a.c_str(), argv[0]);
      return 2;
    }
  }
  mdnet::Config config;
  config.inputs = inputs;
  config.hidden = hidden;
  config.epochs = epochs;
  mdnet::Batch batch;
  Pcg32 rng(5, 3);
  for (int j = 0; j < pixels; ++j) {
    const float shear = float(j % 9) * 0.25f - 1.0f;
    for (int k = 0; k < samples; ++k) {
      const float x = 5 * rng.nextFloat() - 2.5f, y = 5 * rng.nextFloat() - 2.5f;
      const float u = rng.nextFloat() - 0.5f, v = rng.nextFloat() - 0.5f;
      batch.inputs.insert(batch.inputs.end(), {x, y, u, v});
      for (int i = 4; i < inputs; ++i) batch.inputs.push_back(rng.nextFloat() - 0.5f);
      batch.targets.push_back(glm::vec3(x + shear * u > 0.3f ? 1.0f : 0.1f));
    }
    batch.offsets.push_back(uint32_t(batch.targets.size()));
  }
  std::vector<mdnet::Net> nets(static_cast<size_t>(pixels));
  std::vector<mdnet::Net*> pointers;
  for (int j = 0; j < pixels; ++j) {
    mdnet::init(nets[size_t(j)], config, uint64_t(j));
    pointers.push_back(&nets[size_t(j)]);
  }
  const int threads = int(std::thread::hardware_concurrency());
  // The scalar fit on a few pixels, one thread.
  const int scalarPixels = std::min(pixels, 16);
  double start = now();
  for (int j = 0; j < scalarPixels; ++j) {
    mdnet::Net net;
    mdnet::init(net, config, uint64_t(j));
    const uint32_t b = batch.offsets[size_t(j)], e = batch.offsets[size_t(j) + 1];
    const size_t n = size_t(inputs);
    mdnet::fit(net, config, std::span<const float>(batch.inputs.data() + n * b, n * (e - b)),
               std::span<const glm::vec3>(batch.targets.data() + b, e - b));
  }
  const double scalarPerFit = (now() - start) / scalarPixels;
  // The kernel on one thread, then on all.
  double batchOneThread;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    start = now();
    mdnet::fitBatch(config, pointers, batch);
    batchOneThread = (now() - start) / pixels;
  }
  for (int j = 0; j < pixels; ++j) mdnet::init(nets[size_t(j)], config, uint64_t(j));
  start = now();
  mdnet::fitBatch(config, pointers, batch);
  const double batchAll = (now() - start) / pixels;
  // Multiply-adds per sample and epoch: forward I x H + H x 3, backward H x 3 twice and I x H.
  const double macs = 2.0 * config.inputs * hidden + 3.0 * hidden * 3;
  const double flops = 2.0 * macs * double(samples) * double(epochs);
  const double peak = measureFmaPeakGflops(1, 0.5);
  std::printf("mdnet: %d pixels x %d samples x %d epochs, %d inputs, %d hidden, %d lanes\n", pixels,
              samples, epochs, config.inputs, hidden, mdnet::batchLanes());
  std::printf("scalar fit          %.2f ms a pixel (one thread)\n", scalarPerFit * 1e3);
  std::printf("lane-group kernel   %.3f ms a pixel (one thread): %.1fx the scalar fit\n",
              batchOneThread * 1e3, scalarPerFit / batchOneThread);
  std::printf("                    %.3f ms a pixel (%d threads)\n", batchAll * 1e3, threads);
  std::printf("kernel GFLOP/s      %.1f on one thread, %.0f%% of its FMA peak (%.1f)\n",
              flops / batchOneThread * 1e-9, 100.0 * flops / batchOneThread * 1e-9 / peak, peak);
  return 0;
}
