// The BP method's error estimate and the pixel ranking.
#include "methods/bp/error_estimate.h"

#include "core/rng.h"
#include "methods/bp/paper.h"
#include "methods/bp/state.h"
#include "methods/bp/trainer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace penumbra::bp {

namespace {

// Keeps the prediction draws' random stream apart from the method's others.
constexpr uint64_t kPredictionSalt = 0x70726564696374ULL;

float halton(uint32_t index, uint32_t base) {
  float f = 1.0f, r = 0.0f;
  while (index > 0) {
    f /= float(base);
    r += f * float(index % base);
    index /= base;
  }
  return r;
}

}  // namespace

float biasOf(vec3 prediction, vec3 mean, float eps) {
  const float total = mean.x + mean.y + mean.z;
  if (total == 0.0f) return 0.0f;
  const vec3 d = glm::abs(prediction - mean);
  return (d.x + d.y + d.z) / (total + eps);
}

void predictionPoints(int count, uint64_t pixelKey, float* uvt) {
  Pcg32 rng(pixelKey, 0x9e3779b9u);
  const float shift[3] = {rng.nextFloat(), rng.nextFloat(), rng.nextFloat()};
  static constexpr uint32_t kBases[3] = {2, 3, 5};
  for (int j = 0; j < count; ++j)
    for (int d = 0; d < 3; ++d) {
      // Halton index j + 1 skips the all-zero first point before the rotation.
      float value = (count == 1 ? 0.0f : halton(uint32_t(j + 1), kBases[d])) + shift[d];
      if (value >= 1.0f) value -= 1.0f;
      uvt[3 * j + d] = std::min(value, 0x1.fffffep-1f);
    }
}

void estimateErrors(BpState& state, const std::vector<uint32_t>& pixels,
                    const std::atomic<bool>* cancel) {
  const BpCommonConfig& config = state.config;
  const int ni = config.network.inputs;
  const int K = config.predictionDraws;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixels.size(), method::kPixelGrain),
      [&](const tbb::blocked_range<size_t>& range) {
        if (state.cancelled(cancel)) return;
        std::vector<float> uvt(size_t(K) * 3);
        float x[kMaxNetInputs];
        for (size_t i = range.begin(); i < range.end(); ++i) {
          const uint32_t p = pixels[i];
          PixelState& pixel = state.pixel(p);
          // K = 1 is the paper's single random draw, new every round.
          const uint64_t key = hashValues(
              state.shape.seed, p, K == 1 ? kPredictionSalt + state.rounds : kPredictionSalt);
          predictionPoints(K, key, uvt.data());
          vec3 sum(0.0f);
          for (int j = 0; j < K; ++j) {
            const float u = state.prepared.usesLens ? uvt[3 * j] : 0.5f;
            const float v = state.prepared.usesLens ? uvt[3 * j + 1] : 0.5f;
            const float t = state.prepared.usesTime ? uvt[3 * j + 2] : 0.5f;
            networkInputs(ni, 0.0f, 0.0f, u, v, t, x);
            sum += predict(state.nets[p], config.network, x);
          }
          pixel.prediction = sum / float(K);
          pixel.er = state.nets[p].er;
          pixel.bias = biasOf(pixel.prediction, pixel.meanMapped(), config.biasEpsilon);
        }
      });
}

// Converged pixels are not ranked by bias: their training stopped as soon as er fell below
// e, so their I' can still be far from the mean (a dark, constant background keeps a bias
// above 1) and bias no longer measures their error, while er (the energy the network
// cannot explain) still does. [A6]
std::vector<uint32_t> rankPixels(const BpState& state, const BpPaperConfig& config) {
  std::vector<uint32_t> hard, open, converged;
  for (uint32_t p = 0; p < state.pixelCount; ++p) {
    const PixelState& s = state.pixel(p);
    if (s.er <= config.network.errorThreshold)
      converged.push_back(p);
    else
      (s.bias > config.psi ? hard : open).push_back(p);
  }
  auto byBias = [&](uint32_t a, uint32_t b) {
    if (state.pixel(a).bias != state.pixel(b).bias)
      return state.pixel(a).bias > state.pixel(b).bias;
    return a < b;
  };
  auto byError = [&](uint32_t a, uint32_t b) {
    if (state.pixel(a).er != state.pixel(b).er) return state.pixel(a).er > state.pixel(b).er;
    return a < b;
  };
  std::sort(hard.begin(), hard.end(), byBias);
  if (config.topUp) {
    std::sort(open.begin(), open.end(), byBias);
    std::sort(converged.begin(), converged.end(), byError);
    hard.insert(hard.end(), open.begin(), open.end());
    hard.insert(hard.end(), converged.begin(), converged.end());
  }
  return hard;
}

}  // namespace penumbra::bp
