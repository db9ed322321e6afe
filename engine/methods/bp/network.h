// Per-pixel BP (back-propagation) networks of ALGORITHM.md §4: Ni inputs (4 or 5), Nm
// sigmoid hidden units, 3 sigmoid outputs, fixed thresholds b_h and b_o subtracted from
// every unit, weights initialised uniformly in (-1, 1) from a per-pixel seed, and batch
// ("patch") training: one weight update per epoch from the summed gradient of
// er = 1/2 sum_k sum_o (d_o(k) - y_o(k))^2 (eq. 17), with the learning rate steered by er.
//
// `trainNetworks` trains many pixels at once with SIMD: pixels sit in the lanes of a
// vector register (structure of arrays), one lane group per task. The widest instruction
// set the CPU supports is chosen at run time (AVX-512, AVX2+FMA or SSE). A lane's result
// depends only on its own pixel's data, never on which pixels share its group, so images
// do not depend on thread count; `trainNetworkScalar` is the one-pixel reference.
#pragma once

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

constexpr int kMaxNetInputs = 5;
constexpr int kMaxNetHidden = 16;
constexpr int kNetOutputs = 3;

enum class LearningRateMode {
  BoldDriver,    // §4.5 [A5]: x1.05 when er falls, x0.7 when it rises by > 4%, clamped
  Proportional,  // mu = muMin + (muMax - muMin) * min(1, er / er_first)
};

struct NetworkConfig {
  int inputs = 4;               // 4: (sqrt2 * r, u, v, t); 5: (2dx, 2dy, u, v, t)
  int hidden = 8;               // Nm, 1..kMaxNetHidden
  int epochs = 60;              // Nit per (re)training
  float biasHidden = 0.01f;     // b_h, subtracted, not learned [A4]
  float biasOutput = 0.01f;     // b_o
  float errorThreshold = 0.1f;  // e: training of a pixel stops early once er < e [A6]
  float muStart = 0.05f, muMin = 0.02f, muMax = 0.08f;
  LearningRateMode rate = LearningRateMode::BoldDriver;
  bool meanGradient = false;  // divide the summed gradient by n (off: the paper's sum)
};

// One pixel's network. Only the first `inputs` rows and `hidden` columns are used.
struct PixelNet {
  float w1[kMaxNetInputs][kMaxNetHidden];  // input -> hidden
  float w2[kMaxNetHidden][kNetOutputs];    // hidden -> output
  float mu = 0.05f;      // current learning rate, kept across retrainings (warm start)
  float er = 0.0f;       // er of the current weights over the last training set
  float erPrev = 0.0f;   // er of the previous epoch (bold driver)
  float erFirst = 0.0f;  // er of the first epoch of the last training (proportional rate)
};

// Weights uniform in (-1, 1) from `seed`, mu = config.muStart, errors 0.
void initNetwork(PixelNet& net, const NetworkConfig& config, uint64_t seed);

// sigma(x) = 1 / (1 + e^-x) with x clamped to [-30, 30], the same approximation of e^x
// the SIMD kernels use (relative error below 1e-6).
float sigmoid(float x);

// Forward pass: the three outputs for input vector x[0 .. config.inputs).
glm::vec3 predict(const PixelNet& net, const NetworkConfig& config, const float* x);

// er of `net` on n samples (inputs: n * kMaxNetInputs floats, sample-major; targets: n * 3).
double networkError(const PixelNet& net, const NetworkConfig& config, const float* inputs,
                    const float* targets, int n);
// d er / d w for every weight (same layout as PixelNet::w1 / w2), by back-propagation.
void networkGradient(const PixelNet& net, const NetworkConfig& config, const float* inputs,
                     const float* targets, int n, float gradW1[kMaxNetInputs][kMaxNetHidden],
                     float gradW2[kMaxNetHidden][kNetOutputs]);

// Training data of several pixels: pixel j owns samples [offsets[j], offsets[j+1]) of the
// flat arrays (inputs: kMaxNetInputs floats per sample, unused inputs 0; targets: 3 floats).
struct TrainingBatch {
  std::vector<float> inputs;
  std::vector<float> targets;
  std::vector<uint32_t> offsets{0};
  void clear() {
    inputs.clear();
    targets.clear();
    offsets.assign(1, 0u);
  }
  int pixelCount() const { return int(offsets.size()) - 1; }
};

// Runs config.epochs epochs on each net (warm start from its current weights and mu):
//   per epoch: forward + backward over all samples, er summed (eq. 17); stop if er < e;
//   w += mu * G (eq. 11); update mu from er.
// Afterwards net.er is the er of the final weights. nets[j] trains on batch pixel j;
// pixels with no sample are left unchanged. Runs in parallel (oneTBB) over lane groups;
// group membership is fixed by the batch alone. Returns the floating-point operations
// spent in multiply-adds (2 per multiply-add), for GFLOP/s figures.
// `cancel`, when given and set, stops the training between lane groups (the caller then
// discards the networks' state).
uint64_t trainNetworks(const NetworkConfig& config, std::span<PixelNet* const> nets,
                       const TrainingBatch& batch, const std::atomic<bool>* cancel = nullptr);

// The same training for one pixel without SIMD; the reference for tests.
void trainNetworkScalar(const NetworkConfig& config, PixelNet& net, const float* inputs,
                        const float* targets, int n);

// Name of the instruction set trainNetworks uses on this CPU ("avx512", "avx2", "sse").
const char* networkSimdName();

// Peak single-precision FMA throughput of this machine in GFLOP/s (2 flops per FMA),
// measured with independent FMA chains in the widest vector width, on `threads` threads
// (0 = all cores) for about `seconds`.
double measureFmaPeakGflops(int threads, double seconds);

}  // namespace penumbra
