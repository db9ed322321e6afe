#include "engine/sampler.h"

namespace penumbra {

namespace {
// Dimension slots of the camera point; integrator dimensions start after them.
constexpr uint32_t kImageDim = 0, kLensDim = 1, kTimeDim = 2, kFirstIntegratorDim = 3;
}  // namespace

float vanDerCorput(uint32_t index, uint32_t scramble) {
  index = (index << 16) | (index >> 16);
  index = ((index & 0x00ff00ff) << 8) | ((index & 0xff00ff00) >> 8);
  index = ((index & 0x0f0f0f0f) << 4) | ((index & 0xf0f0f0f0) >> 4);
  index = ((index & 0x33333333) << 2) | ((index & 0xcccccccc) >> 2);
  index = ((index & 0x55555555) << 1) | ((index & 0xaaaaaaaa) >> 1);
  return toUnitFloat(index ^ scramble);
}

float sobol2(uint32_t index, uint32_t scramble) {
  for (uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1) scramble ^= v;
  return toUnitFloat(scramble);
}

uint32_t roundUpPowerOfTwo(uint32_t v) {
  uint32_t p = 1;
  while (p < v && p < (1u << 31)) p <<= 1;
  return p;
}

uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t key) {
  // Kensler 2013, "Correlated Multi-Jittered Sampling": an invertible hash on the bits
  // of i masked to log2(n) bits. Every step is a bijection modulo n = 2^k.
  const uint32_t w = n - 1;
  if (w == 0) return 0;
  i ^= key;
  i *= 0xe170893d;
  i ^= key >> 16;
  i ^= (i & w) >> 4;
  i ^= key >> 8;
  i *= 0x0929eb3f;
  i ^= key >> 23;
  i ^= (i & w) >> 1;
  i *= 1 | key >> 27;
  i *= 0x6935fa69;
  i ^= (i & w) >> 11;
  i *= 0x74dcb303;
  i ^= (i & w) >> 2;
  i *= 0x9e501cc3;
  i ^= (i & w) >> 2;
  i *= 0xc860a3df;
  i &= w;
  i ^= i >> 5;
  return i & w;
}

void PixelSampler::startSample(int px, int py, uint32_t sampleIndex) {
  px_ = px;
  py_ = py;
  sampleIndex_ = sampleIndex;
  dimension_ = kFirstIntegratorDim;
  pixelKey_ = hashValues(seed_, (uint64_t(uint32_t(py)) << 32) | uint32_t(px));
  if (kind_ == SamplerKind::Independent) rng_.seedWith(pixelKey_, sampleIndex);
}

uint32_t PixelSampler::dimensionKey(uint32_t dimension) const {
  return uint32_t(hashValues(pixelKey_, dimension));
}

uint32_t PixelSampler::shuffledIndex(uint32_t dimension) const {
  const uint32_t block = sampleIndex_ & ~(setSize_ - 1);
  const uint32_t key = uint32_t(hashValues(pixelKey_, dimension, 0x5eed));
  return block | permuteIndex(sampleIndex_ & (setSize_ - 1), setSize_, key);
}

CameraSample PixelSampler::cameraSample() {
  CameraSample s;
  if (kind_ == SamplerKind::Independent) {
    s.imageX = px_ + rng_.nextFloat();
    s.imageY = py_ + rng_.nextFloat();
    s.lensU = rng_.nextFloat();
    s.lensV = rng_.nextFloat();
    s.time = rng_.nextFloat();
    return s;
  }
  // Each aligned block of setSize samples is a (0,m,2)-net in the image offsets (and in
  // the lens), whatever the shuffled order inside the block.
  const uint32_t imageIndex = shuffledIndex(kImageDim);
  const uint32_t imageKey = dimensionKey(kImageDim);
  s.imageX = px_ + vanDerCorput(imageIndex, imageKey);
  s.imageY = py_ + sobol2(imageIndex, uint32_t(mixBits(imageKey)));
  const uint32_t lensIndex = shuffledIndex(kLensDim);
  const uint32_t lensKey = dimensionKey(kLensDim);
  s.lensU = vanDerCorput(lensIndex, lensKey);
  s.lensV = sobol2(lensIndex, uint32_t(mixBits(lensKey)));
  s.time = vanDerCorput(shuffledIndex(kTimeDim), dimensionKey(kTimeDim));
  return s;
}

float PixelSampler::next1D() {
  if (kind_ == SamplerKind::Independent) return rng_.nextFloat();
  const uint32_t d = dimension_++;
  return vanDerCorput(shuffledIndex(d), dimensionKey(d));
}

glm::vec2 PixelSampler::next2D() {
  if (kind_ == SamplerKind::Independent) {
    const float a = rng_.nextFloat();
    return {a, rng_.nextFloat()};
  }
  const uint32_t d = dimension_++;
  const uint32_t index = shuffledIndex(d), key = dimensionKey(d);
  return {vanDerCorput(index, key), sobol2(index, uint32_t(mixBits(key)))};
}

}  // namespace penumbra
