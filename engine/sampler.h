// Per-pixel samplers. Every sample is drawn one at a time from (pixel, sample index),
// so any sampler (including the adaptive ones) can ask for exactly the points it wants.
//
// - LowDiscrepancy: per pixel, a scrambled (0,2)-sequence for the image offset, another
//   for the lens, a scrambled van der Corput sequence for time, and one independently
//   scrambled (0,2) set per integrator dimension pair (ALGORITHM.md §10.1, after
//   pbrt-v2's LDPixelSample). The sample order is shuffled per dimension within blocks
//   of `setSize` (a power of two), so each dimension stays stratified while dimensions
//   decorrelate; the block structure keeps the sequence extensible past setSize.
// - Independent: uniform random numbers from a per-(pixel, sample) PCG32 stream.
#pragma once

#include "engine/camera.h"
#include "engine/rng.h"

#include <glm/vec2.hpp>

#include <cstdint>

namespace penumbra {

enum class SamplerKind { LowDiscrepancy, Independent };

// Scrambled radical inverses (pbrt-v2 montecarlo.h, VanDerCorput and Sobol2).
float vanDerCorput(uint32_t index, uint32_t scramble);
float sobol2(uint32_t index, uint32_t scramble);

// Bijection of [0, n) for n a power of two, chosen by `key` (Kensler's hashed permutation,
// restricted to powers of two).
uint32_t permuteIndex(uint32_t index, uint32_t n, uint32_t key);

uint32_t roundUpPowerOfTwo(uint32_t v);

// Sample stream of one pixel sample: first the 5D camera point, then the integrator's
// own dimensions in order via next1D / next2D.
class PixelSampler {
 public:
  PixelSampler(SamplerKind kind, uint64_t seed, uint32_t setSize)
      : kind_(kind), seed_(seed), setSize_(roundUpPowerOfTwo(setSize < 1 ? 1 : setSize)) {}

  // Starts sample `sampleIndex` of pixel (px, py); resets the dimension counter.
  void startSample(int px, int py, uint32_t sampleIndex);
  // The 5D point of the current sample (dimensions 0-4).
  CameraSample cameraSample();
  float next1D();
  glm::vec2 next2D();

  SamplerKind kind() const { return kind_; }
  uint32_t setSize() const { return setSize_; }

 private:
  uint32_t dimensionKey(uint32_t dimension) const;
  uint32_t shuffledIndex(uint32_t dimension) const;

  SamplerKind kind_;
  uint64_t seed_;
  uint32_t setSize_;
  uint64_t pixelKey_ = 0;
  uint32_t sampleIndex_ = 0;
  uint32_t dimension_ = 0;
  int px_ = 0, py_ = 0;
  Pcg32 rng_;
};

}  // namespace penumbra
