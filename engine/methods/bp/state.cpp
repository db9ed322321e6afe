#include "methods/bp/state.h"

namespace penumbra::bp {

BpState::BpState(const PreparedScene& scene, const RunShape& runShape,
                 const BpCommonConfig& bpConfig, int coarse, int histogramLevels,
                 bool perPixelSamples)
    : prepared(scene),
      shape(runShape),
      config(bpConfig),
      width(scene.scene.settings.width),
      height(scene.scene.settings.height),
      pixelCount(size_t(width) * height),
      slicesPerPixel(bpConfig.slicesPerSide * bpConfig.slicesPerSide),
      coarseSpp(coarse),
      schedule(runShape, pixelCount, coarse, bpConfig.maxRounds) {
  store.slicesPerPixel = slicesPerPixel;
  store.histogramLevels = histogramLevels;
  store.reservoirLimit = size_t(config.reservoir);
  store.seed = shape.seed;
  if (perPixelSamples) {
    store.resize(pixelCount);
    nets.resize(pixelCount);
  }
  selected.assign(pixelCount, 0);
}

size_t BpState::memoryBytes() const {
  return store.memoryBytes() + nets.capacity() * sizeof(PixelNet) +
         selected.capacity() * sizeof(uint8_t) + lastOrder.capacity() * sizeof(uint32_t) +
         inspectedCandidates.capacity() * sizeof(InspectedCandidate);
}

void BpState::reportCounts(Snapshot& snap, double seconds) const {
  snap.tracedSamples = traced;
  snap.rays = counters.rays;
  snap.nonFiniteSamples = counters.nonFinite;
  snap.rejectedSamples = counters.rejected;
  snap.times = times;
  snap.seconds = seconds;
  snap.addStat("coarse_spp", double(coarseSpp));
  snap.addStat("training_gflops",
               trainingSeconds > 0 ? double(trainingFlops) / trainingSeconds * 1e-9 : 0.0);
  snap.addStat("training_kernel_seconds", trainingSeconds);
  snap.addStat("training_simd", std::string(networkSimdName()));
}

}  // namespace penumbra::bp
