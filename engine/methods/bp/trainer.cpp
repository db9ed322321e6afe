// Training of the BP method's per-pixel networks.
#include "methods/bp/trainer.h"

#include "methods/bp/state.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace penumbra::bp {

void networkInputs(int inputs, float dx, float dy, float u, float v, float t, float* x) {
  if (inputs == 5) {
    x[0] = 2.0f * dx;
    x[1] = 2.0f * dy;
    x[2] = u;
    x[3] = v;
    x[4] = t;
    return;
  }
  x[0] = std::sqrt(2.0f) * std::sqrt(dx * dx + dy * dy);
  x[1] = u;
  x[2] = v;
  x[3] = t;
  x[4] = 0.0f;
}

bool trainNetworksOf(BpState& state, const std::vector<uint32_t>& pixels,
                     const std::atomic<bool>* cancel) {
  const BpCommonConfig& config = state.config;
  const int ni = config.network.inputs;
  TrainingBatch batch;
  batch.offsets.resize(pixels.size() + 1);
  batch.offsets[0] = 0;
  for (size_t i = 0; i < pixels.size(); ++i)
    batch.offsets[i + 1] = batch.offsets[i] + uint32_t(state.store.reservoirs[pixels[i]].size());
  batch.inputs.assign(size_t(batch.offsets.back()) * kMaxNetInputs, 0.0f);
  batch.targets.assign(size_t(batch.offsets.back()) * kNetOutputs, 0.0f);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixels.size(), method::kPixelGrain),
      [&](const tbb::blocked_range<size_t>& range) {
        if (state.cancelled(cancel)) return;
        for (size_t i = range.begin(); i < range.end(); ++i) {
          const uint32_t p = pixels[i];
          const vec3 mean = state.pixel(p).meanMapped();
          size_t k = batch.offsets[i];
          for (const StoredSample& s : state.store.reservoirs[p]) {
            networkInputs(ni, s.dx, s.dy, s.u, s.v, s.t, &batch.inputs[k * kMaxNetInputs]);
            const vec3 target =
                config.targets == TargetMode::PerSample ? state.tone.apply(s.radiance) : mean;
            batch.targets[k * 3 + 0] = target.x;
            batch.targets[k * 3 + 1] = target.y;
            batch.targets[k * 3 + 2] = target.z;
            ++k;
          }
        }
      });
  std::vector<PixelNet*> nets(pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) nets[i] = &state.nets[pixels[i]];
  if (cancel && cancel->load()) return false;
  const auto kernelStart = Clock::now();
  state.trainingFlops += trainNetworks(config.network, nets, batch, cancel);
  if (cancel && cancel->load()) return false;
  state.trainingSeconds += secondsSince(kernelStart);
  return true;
}

}  // namespace penumbra::bp
