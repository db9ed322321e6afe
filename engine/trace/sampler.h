// Per-pixel samplers. Every sample is drawn one at a time from (pixel, sample index),
// so any sampler (including the adaptive ones) can ask for exactly the points it wants.
//
// - LowDiscrepancy: per pixel, a scrambled (0,2)-sequence for the image offset, another
//   for the lens, a scrambled van der Corput sequence for time, and one independently
//   scrambled (0,2) set per integrator dimension pair (ALGORITHM.md §10.1, after
//   pbrt-v2's LDPixelSample). The sample order is permuted per dimension within blocks
//   of `setSize` (a power of two; BlockOrder says how), so each dimension stays stratified
//   while dimensions decorrelate; the block structure keeps the sequence extensible past
//   setSize. Each block has its own permutations: with one for all blocks, the dimensions of
//   a pixel would pair the same way in every block, and the estimate would stop converging.
// - Independent: uniform random numbers from a per-(pixel, sample) PCG32 stream.
#pragma once

#include "core/rng.h"
#include "scene/camera.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>

namespace penumbra {

enum class SamplerKind { LowDiscrepancy, Independent };

// How the low-discrepancy sampler orders a block's samples, per dimension:
// - Nested (nestedPermuteIndex): every power-of-two prefix of a block is stratified, so a
//   pixel stopped at any count (an adaptive method, an open-ended run, a noise threshold)
//   keeps its samples stratified; the price is a weak coupling of the dimensions' fine digits;
// - Shuffled (permuteIndex): a full-avalanche bijection, the best pairing of the dimensions
//   when every block is drawn whole (a batch render at a power-of-two spp); a prefix of a
//   block is a random subset of it.
enum class BlockOrder { Nested, Shuffled };

// Scrambled radical inverses (pbrt-v2 montecarlo.h, VanDerCorput and Sobol2).
inline uint32_t reverseBits(uint32_t v) {
  v = __builtin_bswap32(v);
  v = ((v & 0x0f0f0f0f) << 4) | ((v & 0xf0f0f0f0) >> 4);
  v = ((v & 0x33333333) << 2) | ((v & 0xcccccccc) >> 2);
  return ((v & 0x55555555) << 1) | ((v & 0xaaaaaaaa) >> 1);
}

inline float vanDerCorput(uint32_t index, uint32_t scramble) {
  return toUnitFloat(reverseBits(index) ^ scramble);
}

// The generator matrix of Sobol's second dimension applied to index, xored with scramble: the
// fraction's bits, most significant first. Column c of the matrix is v_c, with v_0 = 2^31 and
// v_c = v_(c-1) xor v_(c-1) >> 1; the product is a xor of the columns of the index's set bits.
inline uint32_t sobol2BitsByColumns(uint32_t index, uint32_t scramble) {
  for (uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1)
    scramble ^= (0u - (index & 1u)) & v;
  return scramble;
}

// The same product a byte of the index at a time: entry [k][b] is the xor of the columns of
// byte k's set bits when that byte is b. Four loads from a 4 KiB table replace a loop of one
// step per bit whose steps depend on each other (an LD sampler computes one per dimension).
struct Sobol2Table {
  uint32_t columns[4][256];
};
inline constexpr Sobol2Table kSobol2Table = [] {
  Sobol2Table t{};
  uint32_t v = 1u << 31;
  for (int k = 0; k < 4; ++k) {
    uint32_t byteColumns[8];
    for (int bit = 0; bit < 8; ++bit, v ^= v >> 1) byteColumns[bit] = v;
    for (uint32_t b = 0; b < 256; ++b) {
      uint32_t x = 0;
      for (int bit = 0; bit < 8; ++bit)
        if (b >> bit & 1u) x ^= byteColumns[bit];
      t.columns[k][b] = x;
    }
  }
  return t;
}();

inline uint32_t sobol2Bits(uint32_t index, uint32_t scramble) {
  const auto& c = kSobol2Table.columns;
  return scramble ^ c[0][index & 255u] ^ c[1][index >> 8 & 255u] ^ c[2][index >> 16 & 255u] ^
         c[3][index >> 24];
}

inline float sobol2(uint32_t index, uint32_t scramble) {
  return toUnitFloat(sobol2Bits(index, scramble));
}

// The hash of Laine and Karras 2011 with Vegdahl's constants: every step (xor with an even
// multiple, an added seed, an odd multiple) flips each bit by the bits below it only.
inline uint32_t laineKarrasHash(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Owen's nested uniform scrambling of a base-2 fraction whose bits come most significant
// first: each digit is flipped by a hash of the digits above it (Burley 2020, "Practical
// Hash-based Owen Scrambling"). Unlike a digital shift (xor with one scramble), which gives
// every point of a set the same digits below the set's resolution, it makes those digits
// random per point while keeping the set's stratification.
inline uint32_t owenScramble(uint32_t bits, uint32_t seed) {
  return reverseBits(laineKarrasHash(reverseBits(bits), seed));
}

// The Owen-scrambled van der Corput point of an index: owenScramble(reverseBits(index), seed),
// whose two reversals of the index cancel.
inline float owenVanDerCorput(uint32_t index, uint32_t seed) {
  return toUnitFloat(reverseBits(laineKarrasHash(index, seed)));
}

// The keys of permuteIndex's three rounds, from its key.
struct PermuteKeys {
  uint32_t round[3];
};
inline PermuteKeys permuteKeys(uint32_t key) {
  PermuteKeys k;
  for (int r = 0; r < 3; ++r, key = mixBits32(key + 0x9e3779b9u)) k.round[r] = key;
  return k;
}

// Bijection of [0, n) for n a power of two, chosen by `key`. Every step is invertible modulo
// n = 2^b: xor with the key, multiply by an odd number, and xorshifts down by about b/2 and b/3
// bits, so that every output bit depends on every input bit; three rounds with fresh keys.
// (Shifts fixed at a few bits, as a 32-bit hash would use, leave the low output bits a
// function of the low input bits once n is large, which correlates the dimensions of a pixel.)
inline uint32_t permuteIndex(uint32_t i, uint32_t n, const PermuteKeys& keys) {
  if (n <= 1) return 0;
  const uint32_t mask = n - 1;
  const int bits = __builtin_ctz(n);
  const int half = (bits + 1) / 2, third = bits / 3 > 0 ? bits / 3 : 1;
  for (uint32_t key : keys.round) {
    i = ((i ^ key) * ((key >> 8) | 1u)) & mask;
    i ^= i >> half;
    i = (i * 0x2c1b3c6du) & mask;
    i ^= i >> third;
  }
  return i;
}

inline uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t key) {
  return permuteIndex(i, n, permuteKeys(key));
}

// nestedPermuteIndex (below) of the index whose reversed bits are given, for n >= 1: a sampler
// reverses a sample's place in its block once for all of its dimensions.
inline uint32_t nestedPermuteReversedIndex(uint32_t reversedIndex, uint32_t n, uint32_t key) {
  return reverseBits(laineKarrasHash(reversedIndex, key)) & (n - 1);  // owenScramble, masked
}

// A nested random permutation of [0, n) for n a power of two, chosen by `key`: bit b of the
// index is flipped by a hash of the bits above it (Owen's nested scrambling applied to the
// index, the shuffle of Burley 2020, "Practical Hash-based Owen Scrambling"). It maps every
// aligned run of 2^j indices onto an aligned run of 2^j, so the first 2^j samples of a block
// are a (0,j,2)-net like the block's whole set: a pixel that stops at any count keeps its
// samples stratified. The hash works on the reversed bits, where each step (xor with an even
// multiple, an added key, an odd multiple) flips a bit by the bits below it only (Laine and
// Karras 2011, with Vegdahl's constants).
inline uint32_t nestedPermuteIndex(uint32_t i, uint32_t n, uint32_t key) {
  return n <= 1 ? 0 : nestedPermuteReversedIndex(reverseBits(i), n, key);
}

uint32_t roundUpPowerOfTwo(uint32_t v);

// How the low-discrepancy sampler scrambles an integrator dimension's values:
// - DigitalShift: each coordinate's bits xored with one per-(pixel, dimension) scramble. Below
//   the resolution of the pixel's sample count every sample then has the same digits, which is
//   harmless where the value is warped smoothly (a BSDF direction, roulette).
// - Owen: nested uniform scrambling (owenScramble), whose digits below that resolution are
//   random per sample. For a value whose fine digits become a discrete choice: light sampling
//   picks an emitter from a CDF over many and an environment texel through alias tables, whose
//   accept test reads the digits below the column; with a digital shift all of a pixel's samples
//   took the same branch of it, and LD's error at 64 spp on an environment-lit asset was 3.5 times
//   what Owen scrambling gives (docs/BENCHMARKS.md).
enum class Scrambling { DigitalShift, Owen };

// Sample stream of one pixel sample: first the 5D camera point, then the integrator's
// own dimensions in order via next1D / next2D.
class PixelSampler {
 public:
  PixelSampler(SamplerKind kind, uint64_t seed, uint32_t setSize,
               BlockOrder order = BlockOrder::Nested)
      : kind_(kind),
        order_(order),
        seed_(seed),
        setSize_(roundUpPowerOfTwo(setSize < 1 ? 1 : setSize)) {}

  // Starts sample `sampleIndex` of pixel (px, py); resets the dimension counter. `stream`
  // picks one of the pixel's independent sequences (0: the pixel's own, which every method
  // uses; others, e.g. one per sub-pixel slice, are scrambled and shuffled apart from it).
  void startSample(int px, int py, uint32_t sampleIndex, uint32_t stream = 0);
  // The 5D point of the current sample (dimensions 0-4). A pinhole camera needs no lens
  // sample and a scene without motion no time: those are left at 0.5, not computed.
  CameraSample cameraSample(bool needLens = true, bool needTime = true);
  float next1D(Scrambling scrambling = Scrambling::DigitalShift);
  glm::vec2 next2D(Scrambling scrambling = Scrambling::DigitalShift);
  // Leaves `count` dimensions unused, so the next ones keep their index in every path
  // (LD dimensions must line up across the samples of a pixel to stay stratified).
  void skip(uint32_t count) { dimension_ += count; }
  // The value next2D would return `ahead` dimensions from now, without drawing it; false for
  // the independent sampler, whose values exist only once drawn. Lets a caller prefetch what
  // a later draw will read.
  bool peek2D(uint32_t ahead, glm::vec2& value, Scrambling scrambling = Scrambling::DigitalShift);

  SamplerKind kind() const { return kind_; }
  uint32_t setSize() const { return setSize_; }

 private:
  // Per (pixel, dimension): the shuffle key and the scrambles of the two coordinates.
  struct DimensionKeys {
    uint32_t shuffle, scrambleX, scrambleY;
    PermuteKeys firstBlock;  // permuteKeys(shuffle): the shuffle of the first block's samples
  };
  static constexpr uint32_t kCachedDimensions = 64;
  DimensionKeys keysFor(uint32_t dimension) const;
  const DimensionKeys& keys(uint32_t dimension);
  uint32_t shuffledIndex(const DimensionKeys& keys) const;
  // A 2D dimension's value for this sample.
  glm::vec2 lowDiscrepancy2D(uint32_t dimension, Scrambling scrambling);

  SamplerKind kind_;
  BlockOrder order_;
  uint64_t seed_;
  uint32_t setSize_;
  uint64_t pixelKey_ = 0;
  uint32_t sampleIndex_ = 0;
  // Of the sample index: the hash of its block and its reversed place in the block.
  uint32_t blockKey_ = 0, reversedLocal_ = 0;
  uint32_t dimension_ = 0;
  // The last peeked 2D value and its dimension (kNoPeek: none), which next2D hands out
  // rather than computing it twice; valid for the current sample only.
  static constexpr uint32_t kNoPeek = ~0u;
  uint32_t peekedDimension_ = kNoPeek;
  Scrambling peekedScrambling_ = Scrambling::DigitalShift;
  glm::vec2 peeked_{0.0f};
  int px_ = 0, py_ = 0;
  uint32_t stream_ = 0;
  bool havePixel_ = false;
  // Hashing keys is the costly part of an LD sample; they depend only on the pixel and
  // the dimension, so they are computed once per pixel, on first use.
  std::array<DimensionKeys, kCachedDimensions> cache_{};
  uint32_t cachedCount_ = 0;
  DimensionKeys overflow_{};
  Pcg32 rng_;
};

}  // namespace penumbra
