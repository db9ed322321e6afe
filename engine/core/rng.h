// Counter-based random numbers: hashes of (seed, pixel, sample, dimension) so that every
// pixel has its own stream and an image does not depend on thread count or tile order.
#pragma once

#include <cstdint>

namespace penumbra {

// A 64-bit finaliser (splitmix64 constants) used to derive independent seeds.
inline uint64_t mixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ULL;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dULL;
  v ^= v >> 33;
  return v;
}

// A 32-bit integer hash (xorshift-multiply rounds) for deriving 32-bit keys
// (the sampler's shuffles).
inline uint32_t mixBits32(uint32_t v) {
  v ^= v >> 16;
  v *= 0x7feb352du;
  v ^= v >> 15;
  v *= 0x846ca68bu;
  v ^= v >> 16;
  return v;
}

inline uint64_t hashValues(uint64_t a, uint64_t b) {
  return mixBits(a * 0x9e3779b97f4a7c15ULL ^ mixBits(b));
}
inline uint64_t hashValues(uint64_t a, uint64_t b, uint64_t c) {
  return hashValues(hashValues(a, b), c);
}

// 32-bit integer to float in [0,1): top 24 bits, so 1 is never reached.
inline float toUnitFloat(uint32_t v) { return float(v >> 8) * 0x1p-24f; }

// PCG32 (O'Neill): a small, fast, statistically good generator for per-pixel streams.
class Pcg32 {
 public:
  Pcg32() = default;
  Pcg32(uint64_t seed, uint64_t stream) { seedWith(seed, stream); }
  void seedWith(uint64_t seed, uint64_t stream) {
    state_ = 0;
    inc_ = (stream << 1u) | 1u;
    nextUint();
    state_ += seed;
    nextUint();
  }
  uint32_t nextUint() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  float nextFloat() { return toUnitFloat(nextUint()); }

 private:
  uint64_t state_ = 0x853c49e6748fea9bULL;
  uint64_t inc_ = 0xda3e39cb94b95bdbULL;
};

}  // namespace penumbra
