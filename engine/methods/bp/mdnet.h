// Multidimensional network reconstruction (issue 26): a pixel's estimate from a small network
// fitted to the samples of its neighbourhood over the sample's dimensions, then averaged over
// the pixel's footprint and those dimensions.
//
// Near an edge of a soft shadow, of a moving or of a defocused object, the radiance is a smooth
// step along one linear combination of the sample's dimensions: a penumbra is a step in the
// image position and the light sample's position together (Mehta et al. 2012), motion blur in
// x - v t (Egan et al. 2009), defocus in x and the lens position (Soler et al. 2009). One
// sigmoid unit of a one-hidden-layer network is such a step. Fitted on the samples of the
// pixel's (2r+1)^2 neighbourhood, with their offsets from the pixel's centre and their other
// dimensions as inputs, the network learns the step along the right shear; its mean over the
// pixel's own footprint (offsets in [-0.5, 0.5]^2) and over the other dimensions is then an
// estimate of the pixel that borrows its neighbours' samples without the blur of an image-space
// filter (which cannot tell a penumbra from texture or noise).
//
// The network: `inputs` inputs, `hidden` sigmoid units with learned biases, three linear
// outputs (RGB, each standardised by the training targets' mean and spread), trained by
// full-batch Adam on the mean squared error. A network warm-starts from its last weights.
// Everything here is scalar and per pixel: the reference for the batched kernels to come.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::mdnet {

constexpr int kMaxInputs = 7;  // dx, dy, lens u, v, time, light chart s, t
constexpr int kMaxHidden = 16;
constexpr int kOutputs = 3;

struct Config {
  int inputs = 4;
  int hidden = 8;
  int epochs = 300;  // per (re)training
  float learningRate = 0.05f;
};

// One pixel's network and its optimiser's state. Only the first `inputs` rows and `hidden`
// columns are used.
struct Net {
  float w1[kMaxInputs][kMaxHidden];  // input -> hidden
  float b1[kMaxHidden];
  float w2[kMaxHidden][kOutputs];  // hidden -> output
  float b2[kOutputs];
  glm::vec3 targetMean{0.0f}, targetScale{1.0f};  // outputs are standardised targets
  // Adam's first and second moments, in the order of the weights above, and its step count.
  std::vector<float> m, v;
  int step = 0;
};

// Weights from `seed` (w1 ~ N(0, 1), b1 ~ N(0, 0.5), w2 ~ N(0, 0.3), b2 = 0), moments zero.
void init(Net& net, const Config& config, uint64_t seed);

// Trains on n samples: inputs n x config.inputs floats (sample-major), targets n RGB values.
// The targets' mean and spread are taken from these samples first. Returns the final mean
// squared error over the standardised targets (per channel, averaged).
float fit(Net& net, const Config& config, std::span<const float> inputs,
          std::span<const glm::vec3> targets);

// The network's output for one input vector (config.inputs floats), in the targets' units.
glm::vec3 predict(const Net& net, const Config& config, const float* x);

// The mean of the output over `points` (count x config.inputs floats).
glm::vec3 average(const Net& net, const Config& config, std::span<const float> points);

// Training data of several pixels: pixel j owns samples [offsets[j], offsets[j + 1]) of the
// flat arrays (inputs: config.inputs floats per sample; targets: one RGB value).
struct Batch {
  std::vector<float> inputs;
  std::vector<glm::vec3> targets;
  std::vector<uint32_t> offsets{0};
  int pixelCount() const { return int(offsets.size()) - 1; }
};

// fit() for many pixels at once: nets[j] on batch pixel j, in lane groups of the widest
// vector the CPU has (AVX-512: 16 pixels, AVX2 + FMA: 8, else SSE: 4), in parallel over groups. A
// pixel's result depends only on its own data, never on its group or the thread count; it differs
// from fit()'s by rounding (a polynomial e^x, fused multiply-adds). Returns each pixel's final mean
// squared error over its standardised targets.
// `lanes` forces a width (4: SSE; 8: AVX2, 16: AVX-512, where the CPU has them), for tests; 0
// picks the widest.
std::vector<float> fitBatch(const Config& config, std::span<Net* const> nets, const Batch& batch,
                            int lanes = 0);
// The vector width fitBatch uses on this CPU, in pixels.
int batchLanes();

namespace detail {
// One lane group's data for the kernel (mdnet_kernel.inc), every array [item][lane]; the
// parameters in the order w1 (input-major), b1, w2 (hidden-major), b2.
struct Group {
  int inputs = 0, hidden = 0, samples = 0, epochs = 0;
  float learningRate = 0;
  const float* x = nullptr;          // samples x inputs x lanes
  const float* y = nullptr;          // samples x 3 x lanes, standardised
  const float* valid = nullptr;      // samples x lanes: 1 where the lane has that sample
  const float* gradScale = nullptr;  // lanes: 2 / (3 n), 0 for an empty lane
  float* params = nullptr;           // parameters x lanes
  float* m = nullptr;                // Adam's moments, parameters x lanes
  float* v = nullptr;
  int* step = nullptr;       // lanes: Adam's step counts
  float* loss = nullptr;     // lanes: the last epoch's summed squared error
  float* scratch = nullptr;  // parameters x lanes: the gradient
};
void trainGroupSse(const Group& group);     // 4 lanes
void trainGroupAvx2(const Group& group);    // 8 lanes
void trainGroupAvx512(const Group& group);  // 16 lanes
}  // namespace detail

// `count` points of a fixed low-discrepancy set (Halton, bases 2, 3, 5, ...) in the box
// [lo[d], hi[d]] of each of `dimensions` dimensions, point-major: the nodes over which a
// network is averaged (a pixel's footprint and the other dimensions' ranges).
std::vector<float> haltonPoints(int dimensions, int count, std::span<const float> lo,
                                std::span<const float> hi);

}  // namespace penumbra::mdnet
