#include "methods/bp/network.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <thread>

#include "core/rng.h"

namespace penumbra {

// The per-ISA kernels (network_kernel.inc compiled three times).
#define PENUMBRA_BP_DECLARE_ISA(NS)                                                            \
  namespace NS {                                                                               \
  int laneCount();                                                                             \
  int fmaPeakChains();                                                                         \
  uint64_t trainGroup(const NetworkConfig& config, PixelNet* const* nets, const float* inputs, \
                      const float* targets, const uint32_t* offsets, const uint32_t* pixels,   \
                      int lanes, void* scratch);                                               \
  float fmaPeak(long long iterations, float multiplier, float addend);                         \
  }
PENUMBRA_BP_DECLARE_ISA(bpnet_sse)
PENUMBRA_BP_DECLARE_ISA(bpnet_avx2)
PENUMBRA_BP_DECLARE_ISA(bpnet_avx512)
#undef PENUMBRA_BP_DECLARE_ISA

namespace {

namespace scalar_math {
#include "methods/bp/network_kernel.inc"
}  // namespace scalar_math

struct IsaKernels {
  const char* name;
  int lanes;
  int fmaPeakChains;
  uint64_t (*trainGroup)(const NetworkConfig&, PixelNet* const*, const float*, const float*,
                         const uint32_t*, const uint32_t*, int, void*);
  float (*fmaPeak)(long long, float, float);
};

// Widest supported instruction set. PENUMBRA_NET_SIMD=sse|avx2 forces a narrower one (for
// tests and benchmarks of the other kernels); it can never select one the CPU lacks.
const IsaKernels& isaKernels() {
  static const IsaKernels kernels = [] {
    const IsaKernels sse{"sse", bpnet_sse::laneCount(), bpnet_sse::fmaPeakChains(),
                         bpnet_sse::trainGroup, bpnet_sse::fmaPeak};
    const IsaKernels avx2{"avx2", bpnet_avx2::laneCount(), bpnet_avx2::fmaPeakChains(),
                          bpnet_avx2::trainGroup, bpnet_avx2::fmaPeak};
    const IsaKernels avx512{"avx512", bpnet_avx512::laneCount(), bpnet_avx512::fmaPeakChains(),
                            bpnet_avx512::trainGroup, bpnet_avx512::fmaPeak};
    __builtin_cpu_init();
    const bool hasAvx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    const bool hasAvx512 = hasAvx2 && __builtin_cpu_supports("avx512f") &&
                           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
    const char* forced = std::getenv("PENUMBRA_NET_SIMD");
    const std::string_view want = forced ? forced : "";
    if (want == "sse") return sse;
    if (hasAvx512 && want != "avx2") return avx512;
    if (hasAvx2) return avx2;
    return sse;
  }();
  return kernels;
}

// Sizes outside the arrays of PixelNet would index out of bounds; clamp them once here.
NetworkConfig checkedConfig(const NetworkConfig& config) {
  NetworkConfig c = config;
  c.inputs = std::clamp(c.inputs, 1, kMaxNetInputs);
  c.hidden = std::clamp(c.hidden, 1, kMaxNetHidden);
  c.epochs = std::max(c.epochs, 0);
  return c;
}

float scalarSigmoid(float x) {
  scalar_math::sigmoidDenominators<float, uint32_t, 1>(&x, 1);
  return 1.0f / x;
}

// Forward pass in the same operation order as the SIMD kernel (bias first, then the inputs).
void forwardPass(const PixelNet& net, const NetworkConfig& c, const float* x,
                 float ho[kMaxNetHidden], float yo[kNetOutputs]) {
  for (int h = 0; h < c.hidden; ++h) {
    float a = -c.biasHidden;
    for (int i = 0; i < c.inputs; ++i) a = net.w1[i][h] * x[i] + a;
    ho[h] = scalarSigmoid(a);
  }
  for (int o = 0; o < kNetOutputs; ++o) {
    float a = -c.biasOutput;
    for (int h = 0; h < c.hidden; ++h) a = net.w2[h][o] * ho[h] + a;
    yo[o] = scalarSigmoid(a);
  }
}

// One batch epoch: returns er (eq. 17) and fills g1 / g2 with G = -d er / d w (only the used
// entries; the rest is zeroed).
float scalarEpoch(const PixelNet& net, const NetworkConfig& c, const float* inputs,
                  const float* targets, int n, float g1[kMaxNetInputs][kMaxNetHidden],
                  float g2[kMaxNetHidden][kNetOutputs]) {
  std::memset(g1, 0, sizeof(float) * kMaxNetInputs * kMaxNetHidden);
  std::memset(g2, 0, sizeof(float) * kMaxNetHidden * kNetOutputs);
  float errSum = 0.0f;
  for (int k = 0; k < n; ++k) {
    const float* x = inputs + size_t(k) * kMaxNetInputs;
    const float* t = targets + size_t(k) * kNetOutputs;
    float ho[kMaxNetHidden], yo[kNetOutputs], delta[kNetOutputs];
    forwardPass(net, c, x, ho, yo);
    for (int o = 0; o < kNetOutputs; ++o) {
      const float r = t[o] - yo[o];
      errSum = r * r + errSum;
      delta[o] = r * (yo[o] - yo[o] * yo[o]);
    }
    for (int h = 0; h < c.hidden; ++h) {
      float back = net.w2[h][0] * delta[0];
      for (int o = 0; o < kNetOutputs; ++o) {
        g2[h][o] = delta[o] * ho[h] + g2[h][o];
        if (o > 0) back = net.w2[h][o] * delta[o] + back;
      }
      const float deltaHidden = (ho[h] - ho[h] * ho[h]) * back;
      for (int i = 0; i < c.inputs; ++i) g1[i][h] = deltaHidden * x[i] + g1[i][h];
    }
  }
  return 0.5f * errSum;
}

float scalarError(const PixelNet& net, const NetworkConfig& c, const float* inputs,
                  const float* targets, int n) {
  float errSum = 0.0f;
  for (int k = 0; k < n; ++k) {
    float ho[kMaxNetHidden], yo[kNetOutputs];
    forwardPass(net, c, inputs + size_t(k) * kMaxNetInputs, ho, yo);
    for (int o = 0; o < kNetOutputs; ++o) {
      const float r = targets[size_t(k) * kNetOutputs + o] - yo[o];
      errSum = r * r + errSum;
    }
  }
  return 0.5f * errSum;
}

void prefetchBytes(const void* begin, size_t bytes) {
  const char* p = static_cast<const char*>(begin);
  for (size_t offset = 0; offset < bytes; offset += 64) __builtin_prefetch(p + offset);
}

// Pulls a group's networks and samples towards the cache while the previous group trains
// (tens of microseconds), so the next gather does not wait on main memory.
void prefetchGroup(std::span<PixelNet* const> nets, const TrainingBatch& batch,
                   const uint32_t* pixels, int count) {
  for (int l = 0; l < count; ++l) {
    const uint32_t p = pixels[l], first = batch.offsets[p], n = batch.offsets[p + 1] - first;
    prefetchBytes(nets[p], sizeof(PixelNet));
    prefetchBytes(batch.inputs.data() + size_t(first) * kMaxNetInputs,
                  size_t(n) * kMaxNetInputs * sizeof(float));
    prefetchBytes(batch.targets.data() + size_t(first) * kNetOutputs,
                  size_t(n) * kNetOutputs * sizeof(float));
  }
}

// Memory for one lane group's samples, in the vector alignment of the widest kernel.
struct alignas(64) ScratchBlock {
  float v[16];
};

}  // namespace

void initNetwork(PixelNet& net, const NetworkConfig& config, uint64_t seed) {
  const NetworkConfig c = checkedConfig(config);
  std::memset(net.w1, 0, sizeof(net.w1));
  std::memset(net.w2, 0, sizeof(net.w2));
  Pcg32 rng(mixBits(seed), 0x6270'6e65'74ULL);
  // Odd multiples of 2^-24 in (-1, 1): symmetric, and neither end can be drawn.
  auto draw = [&rng] {
    const int32_t v = int32_t(rng.nextUint() >> 8);
    return float(2 * v + 1 - (1 << 24)) * 0x1p-24f;
  };
  for (int i = 0; i < c.inputs; ++i)
    for (int h = 0; h < c.hidden; ++h) net.w1[i][h] = draw();
  for (int h = 0; h < c.hidden; ++h)
    for (int o = 0; o < kNetOutputs; ++o) net.w2[h][o] = draw();
  net.mu = c.muStart;
  net.er = net.erPrev = net.erFirst = 0.0f;
}

float sigmoid(float x) { return scalarSigmoid(x); }

glm::vec3 predict(const PixelNet& net, const NetworkConfig& config, const float* x) {
  const NetworkConfig c = checkedConfig(config);
  float ho[kMaxNetHidden], yo[kNetOutputs];
  forwardPass(net, c, x, ho, yo);
  return {yo[0], yo[1], yo[2]};
}

double networkError(const PixelNet& net, const NetworkConfig& config, const float* inputs,
                    const float* targets, int n) {
  const NetworkConfig c = checkedConfig(config);
  // Double sums so that finite differences of er are not swamped by summation rounding.
  double errSum = 0.0;
  for (int k = 0; k < n; ++k) {
    float ho[kMaxNetHidden], yo[kNetOutputs];
    forwardPass(net, c, inputs + size_t(k) * kMaxNetInputs, ho, yo);
    for (int o = 0; o < kNetOutputs; ++o) {
      const double r = double(targets[size_t(k) * kNetOutputs + o]) - double(yo[o]);
      errSum += r * r;
    }
  }
  return 0.5 * errSum;
}

void networkGradient(const PixelNet& net, const NetworkConfig& config, const float* inputs,
                     const float* targets, int n, float gradW1[kMaxNetInputs][kMaxNetHidden],
                     float gradW2[kMaxNetHidden][kNetOutputs]) {
  const NetworkConfig c = checkedConfig(config);
  scalarEpoch(net, c, inputs, targets, n, gradW1, gradW2);
  for (int i = 0; i < kMaxNetInputs; ++i)
    for (int h = 0; h < kMaxNetHidden; ++h) gradW1[i][h] = -gradW1[i][h];
  for (int h = 0; h < kMaxNetHidden; ++h)
    for (int o = 0; o < kNetOutputs; ++o) gradW2[h][o] = -gradW2[h][o];
}

void trainNetworkScalar(const NetworkConfig& config, PixelNet& net, const float* inputs,
                        const float* targets, int n) {
  if (n <= 0) return;
  const NetworkConfig c = checkedConfig(config);
  const float gradScale = c.meanGradient ? 1.0f / float(n) : 1.0f;
  float g1[kMaxNetInputs][kMaxNetHidden], g2[kMaxNetHidden][kNetOutputs];
  for (int epoch = 0; epoch < c.epochs; ++epoch) {
    const float er = scalarEpoch(net, c, inputs, targets, n, g1, g2);
    if (epoch == 0) net.erFirst = er;
    const float previous = net.erPrev;
    net.erPrev = er;
    if (er < c.errorThreshold) {
      net.er = er;  // the weights did not change since this er was measured
      return;
    }
    const float step = net.mu * gradScale;
    for (int h = 0; h < c.hidden; ++h) {
      for (int i = 0; i < c.inputs; ++i) net.w1[i][h] = step * g1[i][h] + net.w1[i][h];
      for (int o = 0; o < kNetOutputs; ++o) net.w2[h][o] = step * g2[h][o] + net.w2[h][o];
    }
    if (c.rate == LearningRateMode::BoldDriver) {
      // The previous training's er belongs to other samples, so the first epoch of every
      // training has nothing to compare with.
      if (epoch == 0) continue;
      if (er < previous) {
        net.mu = std::min(net.mu * 1.05f, c.muMax);
      } else if (er > 1.04f * previous) {
        net.mu = std::max(net.mu * 0.7f, c.muMin);
      }
    } else {
      const float ratio = std::min(1.0f, er / std::max(net.erFirst, 1e-30f));
      net.mu = (c.muMax - c.muMin) * ratio + c.muMin;
    }
  }
  net.er = scalarError(net, c, inputs, targets, n);
}

uint64_t trainNetworks(const NetworkConfig& config, std::span<PixelNet* const> nets,
                       const TrainingBatch& batch, const std::atomic<bool>* cancel) {
  const NetworkConfig c = checkedConfig(config);
  const IsaKernels& isa = isaKernels();
  const int pixelCount = std::min(int(nets.size()), batch.pixelCount());
  auto samplesOf = [&](uint32_t p) { return batch.offsets[p + 1] - batch.offsets[p]; };

  // Sorting by sample count keeps the padding of each group small; the index breaks ties so
  // that the grouping is a function of the batch alone.
  std::vector<uint32_t> order;
  order.reserve(size_t(pixelCount));
  for (int p = 0; p < pixelCount; ++p)
    if (nets[size_t(p)] && samplesOf(uint32_t(p)) > 0) order.push_back(uint32_t(p));
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const uint32_t na = samplesOf(a), nb = samplesOf(b);
    return na != nb ? na < nb : a < b;
  });
  if (order.empty()) return 0;

  const int lanes = isa.lanes;
  const int groupCount = (int(order.size()) + lanes - 1) / lanes;
  const size_t floatsPerSample = size_t(c.inputs + 4) * size_t(lanes);
  std::atomic<uint64_t> flops{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, groupCount), [&](const tbb::blocked_range<int>& r) {
    // Groups are sorted by size, so the last one of the range needs the most room.
    const size_t lastPixel = std::min(order.size(), size_t(r.end()) * size_t(lanes)) - 1;
    const size_t floats = size_t(samplesOf(order[lastPixel])) * floatsPerSample;
    std::vector<ScratchBlock> scratch((floats + 15) / 16);
    uint64_t localFlops = 0;
    auto groupCount = [&](size_t first) {
      return int(std::min(order.size() - first, size_t(lanes)));
    };
    for (int group = r.begin(); group < r.end(); ++group) {
      if (cancel && cancel->load(std::memory_order_relaxed)) break;
      const size_t first = size_t(group) * size_t(lanes);
      const int count = groupCount(first);
      if (group + 1 < r.end())
        prefetchGroup(nets, batch, order.data() + first + lanes, groupCount(first + lanes));
      localFlops +=
          isa.trainGroup(c, nets.data(), batch.inputs.data(), batch.targets.data(),
                         batch.offsets.data(), order.data() + first, count, scratch.data());
    }
    flops.fetch_add(localFlops, std::memory_order_relaxed);
  });
  return flops.load();
}

const char* networkSimdName() { return isaKernels().name; }

double measureFmaPeakGflops(int threads, double seconds) {
  const IsaKernels& isa = isaKernels();
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  seconds = std::max(seconds, 1e-3);
  // One call: chains x lanes x kChunk FMAs, well under a millisecond on current CPUs.
  constexpr long long kChunk = 1 << 14;
  const double flopsPerChunk = 2.0 * isa.fmaPeakChains * isa.lanes * double(kChunk);
  using Clock = std::chrono::steady_clock;

  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::vector<double> rates(size_t(threads), 0.0);
  std::vector<float> sinks(size_t(threads), 0.0f);
  auto worker = [&](int t) {
    ready.fetch_add(1);
    while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
    // Warm-up first: wide vector units may need time to reach their steady clock.
    const auto warmEnd = Clock::now() + std::chrono::duration<double>(0.1 * seconds);
    float sink = 0.0f;
    while (Clock::now() < warmEnd) sink += isa.fmaPeak(kChunk, 0.999f, 1e-3f);
    const auto start = Clock::now();
    const auto end = start + std::chrono::duration<double>(0.9 * seconds);
    long long chunks = 0;
    do {
      sink += isa.fmaPeak(kChunk, 0.999f, 1e-3f * float(chunks & 7));
      ++chunks;
    } while (Clock::now() < end);
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    rates[size_t(t)] = double(chunks) * flopsPerChunk / elapsed;
    sinks[size_t(t)] = sink;  // observable, so the work cannot be dropped
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker, t);
  while (ready.load() < threads) std::this_thread::yield();
  go.store(true, std::memory_order_release);
  for (std::thread& th : pool) th.join();
  double total = 0.0;
  float sinkSum = 0.0f;
  for (int t = 0; t < threads; ++t) {
    total += rates[size_t(t)];
    sinkSum += sinks[size_t(t)];
  }
  // The chains stay finite; testing their sum makes the results used, so the FMA loops
  // cannot be discarded even under whole-program optimisation.
  if (!(sinkSum == sinkSum)) return 0.0;
  return total * 1e-9;
}

}  // namespace penumbra
