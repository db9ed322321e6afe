// What the BP method keeps per pixel (ALGORITHM.md §3, §7.4, §15): running sums of the
// kept samples, per-slice statistics and sums, and a reservoir of at most `reservoir`
// samples for training and eq. 16, so that memory stays bounded in open-ended runs. The
// pixel's raw estimate (the plain mean, or the mean of its slices' means) comes from here.
#pragma once

#include "core/image.h"
#include "core/tone_map.h"
#include "methods/bp/slices.h"
#include "trace/sampler.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::bp {

struct StoredSample {
  float dx, dy;  // centred offsets in [-0.5, 0.5)
  float u, v, t;
  vec3 radiance;  // linear
  float value;    // Y(T(L)), once the tone map is known
  uint8_t slice;
};

struct PixelState {
  uint32_t kept = 0;     // samples in the estimate
  uint32_t traced = 0;   // camera samples traced (kept, candidates, rejected, non-finite)
  uint32_t drawn = 0;    // sample indices used from the pixel's sampler stream
  glm::dvec3 sumL{0.0};  // linear radiance
  glm::dvec3 sumT{0.0};  // tone-mapped radiance, for eq. 12
  float bias = 0.0f;
  float er = 0.0f;
  vec3 prediction{0.0f};
  int8_t sliceB = -1, sliceC = -1;
  bool warped = false;
  uint8_t alpha = 0;
  uint32_t addedLastRound = 0;
  float contrast = 0.0f;

  vec3 meanMapped() const { return kept ? vec3(sumT / double(kept)) : vec3(0.0f); }
};

// The stored form of a traced camera sample of pixel (px, py).
StoredSample makeStoredSample(const CameraSample& cs, int px, int py, vec3 radiance,
                              const ToneMap& tone, int slicesPerSide);

struct PixelStore {
  int slicesPerPixel = 1;
  int histogramLevels = 5;
  size_t reservoirLimit = 64;
  uint64_t seed = 0;  // of the reservoirs' replacement choices

  std::vector<PixelState> pixels;
  std::vector<std::vector<StoredSample>> reservoirs;
  std::vector<SliceStats> slices;     // pixel-major, S^2 per pixel
  std::vector<glm::dvec3> sliceSumL;  // linear radiance per slice

  void resize(size_t pixelCount);
  std::span<const SliceStats> slicesOf(size_t p) const {
    return {&slices[p * slicesPerPixel], size_t(slicesPerPixel)};
  }
  // Adds a kept sample to the pixel's sums, slice statistics and reservoir. For one pixel,
  // called by one thread at a time.
  void keep(size_t p, const StoredSample& s, const ToneMap& tone);
  // The raw estimate: the mean of the slice means (stratified) or the plain mean.
  vec3 estimate(size_t p, bool stratified) const;
  Image estimateImage(int width, int height, bool stratified) const;
  size_t memoryBytes() const;
};

}  // namespace penumbra::bp
