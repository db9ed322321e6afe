// Sampler tests: elementary-interval stratification of the per-pixel (0,2) points,
// the bijection behind the shuffles, and determinism of the streams.
#include "trace/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

namespace penumbra {
namespace {

// Every elementary interval of volume 1/n (2^a by 2^(m-a) cells) holds exactly one point.
void expectElementaryIntervals(const std::vector<glm::vec2>& points, int m) {
  const int n = 1 << m;
  ASSERT_EQ(int(points.size()), n);
  for (int a = 0; a <= m; ++a) {
    const int cellsX = 1 << a, cellsY = 1 << (m - a);
    std::vector<int> counts(size_t(n), 0);
    for (const glm::vec2& p : points) {
      ASSERT_GE(p.x, 0.0f);
      ASSERT_LT(p.x, 1.0f);
      ASSERT_GE(p.y, 0.0f);
      ASSERT_LT(p.y, 1.0f);
      const int cx = int(p.x * cellsX), cy = int(p.y * cellsY);
      ++counts[size_t(cy * cellsX + cx)];
    }
    for (int c : counts) ASSERT_EQ(c, 1) << "interval shape " << cellsX << "x" << cellsY;
  }
}

struct PixelPoints {
  std::vector<glm::vec2> image, lens, integrator;
  std::vector<float> time;
};

PixelPoints drawPixel(PixelSampler& sampler, int px, int py, uint32_t first, uint32_t count) {
  PixelPoints out;
  for (uint32_t i = first; i < first + count; ++i) {
    sampler.startSample(px, py, i);
    const CameraSample s = sampler.cameraSample();
    out.image.push_back({s.imageX - float(px), s.imageY - float(py)});
    out.lens.push_back({s.lensU, s.lensV});
    out.time.push_back(s.time);
    sampler.next1D();  // a first integrator dimension, then a 2D one
    out.integrator.push_back(sampler.next2D());
  }
  return out;
}

// 2^m points: a (0,m,2)-net in the image, the lens and an integrator pair, and one time per
// stratum of 1/2^m.
void expectEveryDimensionStratified(const PixelPoints& p, int m) {
  expectElementaryIntervals(p.image, m);
  expectElementaryIntervals(p.lens, m);
  expectElementaryIntervals(p.integrator, m);
  std::set<int> strata;
  for (float t : p.time) strata.insert(int(t * float(1 << m)));
  EXPECT_EQ(int(strata.size()), 1 << m) << "time is one point per stratum";
}

TEST(Sampler, ZeroTwoPointsAreStratifiedInEveryElementaryInterval) {
  for (BlockOrder order : {BlockOrder::Nested, BlockOrder::Shuffled}) {
    for (int m : {0, 2, 4, 5, 8}) {
      PixelSampler sampler(SamplerKind::LowDiscrepancy, 1234, 1u << m, order);
      for (auto [px, py] : {std::pair{0, 0}, std::pair{17, 3}, std::pair{255, 255}}) {
        const PixelPoints p = drawPixel(sampler, px, py, 0, 1u << m);
        expectEveryDimensionStratified(p, m);
      }
    }
  }
}

TEST(Sampler, LaterBlocksAreStratifiedToo) {
  PixelSampler sampler(SamplerKind::LowDiscrepancy, 7, 16);
  const PixelPoints second = drawPixel(sampler, 3, 4, 16, 16);
  expectElementaryIntervals(second.image, 4);
  const PixelPoints both = drawPixel(sampler, 3, 4, 0, 32);
  expectElementaryIntervals(both.image, 5);
}

// An adaptive method stops a pixel at any count, an open-ended run uses blocks of 64: the
// first 2^j samples of a block are a (0,j,2)-net in every dimension pair, wherever the block
// starts. (With a plain random shuffle of the block, its first 16 of 64 samples were a random
// subset, and cornell's MSE at 16 spp in open-ended runs was 4.6x the batch run's.)
TEST(Sampler, EveryPowerOfTwoPrefixOfABlockIsStratified) {
  for (uint32_t setSize : {64u, 4096u}) {
    PixelSampler sampler(SamplerKind::LowDiscrepancy, 99, setSize);
    for (auto [px, py] : {std::pair{0, 0}, std::pair{40, 9}}) {
      for (uint32_t first : {0u, setSize}) {
        for (int j : {1, 3, 4, 6}) {
          const PixelPoints p = drawPixel(sampler, px, py, first, 1u << j);
          expectEveryDimensionStratified(p, j);
        }
      }
    }
  }
}

TEST(Sampler, NeighbouringPixelsGetDifferentSampleOrders) {
  // Two pixels' sets, each shuffled by its own key, pair their samples differently.
  PixelSampler sampler(SamplerKind::LowDiscrepancy, 99, 64);
  const PixelPoints a = drawPixel(sampler, 0, 0, 0, 64);
  const PixelPoints b = drawPixel(sampler, 1, 0, 0, 64);
  int sameOrder = 0;
  for (int i = 0; i < 64; ++i)
    sameOrder += int(a.image[size_t(i)].x * 8) == int(b.image[size_t(i)].x * 8) ? 1 : 0;
  EXPECT_LT(sameOrder, 32);
}

// Chi-square per degree of freedom of the pairs (a[i], b[i]) on an 8x8 grid: about 1 (or
// less, both marginals being stratified) when the two dimensions pair at random.
double pairChiSquare(const std::vector<float>& a, const std::vector<float>& b) {
  constexpr int kCells = 8;
  std::vector<double> counts(kCells * kCells, 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    counts[size_t(int(a[i] * kCells) * kCells + int(b[i] * kCells))] += 1;
  const double expected = double(a.size()) / (kCells * kCells);
  double chi = 0;
  for (double c : counts) chi += (c - expected) * (c - expected) / expected;
  return chi / (kCells * kCells - 1);
}

// The dimensions of one pixel pair independently at every sample count, within one large
// block and across many small ones: a correlation there is an error that stops falling
// with more samples (the image converges to a wrong value per seed).
TEST(Sampler, DimensionsOfAPixelPairIndependently) {
  for (auto [setSize, order] :
       {std::pair{4096u, BlockOrder::Nested}, std::pair{64u, BlockOrder::Nested},
        std::pair{4096u, BlockOrder::Shuffled}, std::pair{64u, BlockOrder::Shuffled}}) {
    for (auto [px, py] : {std::pair{0, 0}, std::pair{112, 104}, std::pair{203, 153}}) {
      PixelSampler sampler(SamplerKind::LowDiscrepancy, 5, setSize, order);
      const PixelPoints p = drawPixel(sampler, px, py, 0, 4096);
      std::vector<float> imageX, lensU, lensV, pathX, pathY;
      for (size_t i = 0; i < p.image.size(); ++i) {
        imageX.push_back(p.image[i].x);
        lensU.push_back(p.lens[i].x);
        lensV.push_back(p.lens[i].y);
        pathX.push_back(p.integrator[i].x);
        pathY.push_back(p.integrator[i].y);
      }
      // Before the per-block keys and the full-width permutation these were 3 to 27.
      EXPECT_LT(pairChiSquare(lensU, pathX), 2.0) << "set " << setSize << " pixel " << px;
      EXPECT_LT(pairChiSquare(imageX, p.time), 2.0) << "set " << setSize << " pixel " << px;
      EXPECT_LT(pairChiSquare(lensV, pathY), 2.0) << "set " << setSize << " pixel " << px;
    }
  }
}

TEST(Sampler, PermutationsAreBijections) {
  for (uint32_t n : {1u, 2u, 8u, 64u, 1024u, 65536u}) {
    for (uint32_t key : {0u, 1u, 0xdeadbeefu}) {
      std::set<uint32_t> seen, nested;
      for (uint32_t i = 0; i < n; ++i) {
        seen.insert(permuteIndex(i, n, key));
        nested.insert(nestedPermuteIndex(i, n, key));
      }
      EXPECT_EQ(seen.size(), n);
      EXPECT_LT(*seen.rbegin(), n);
      EXPECT_EQ(nested.size(), n);
      EXPECT_LT(*nested.rbegin(), n);
    }
  }
}

TEST(Sampler, SameSeedSameSamplesDifferentSeedDifferentSamples) {
  for (SamplerKind kind : {SamplerKind::LowDiscrepancy, SamplerKind::Independent}) {
    PixelSampler a(kind, 5, 16), b(kind, 5, 16), c(kind, 6, 16);
    const PixelPoints pa = drawPixel(a, 9, 9, 0, 16), pb = drawPixel(b, 9, 9, 0, 16),
                      pc = drawPixel(c, 9, 9, 0, 16);
    EXPECT_EQ(pa.image, pb.image);
    EXPECT_EQ(pa.integrator, pb.integrator);
    EXPECT_NE(pa.image, pc.image);
    // Drawing another pixel in between does not disturb a pixel's stream.
    drawPixel(a, 1, 2, 0, 5);
    EXPECT_EQ(drawPixel(a, 9, 9, 0, 16).lens, pb.lens);
  }
}

TEST(Sampler, IndependentSamplesAreUniform) {
  // Chi-square over 16 bins of 16384 values: the 0.999 quantile with 15 dof is 37.7.
  PixelSampler sampler(SamplerKind::Independent, 3, 1);
  std::vector<int> bins(16, 0);
  for (uint32_t i = 0; i < 16384; ++i) {
    sampler.startSample(i % 64, i / 64, i);
    ++bins[size_t(sampler.next1D() * 16)];
  }
  double chi2 = 0;
  for (int c : bins) chi2 += (c - 1024.0) * (c - 1024.0) / 1024.0;
  EXPECT_LT(chi2, 37.7);
}

TEST(Sampler, IndependentSamplesOfAPixelAreIndependent) {
  // A pixel's mean of 256 values of one dimension, standardised, has variance 1 over pixels
  // when the samples are independent; 4096 pixels estimate it within +-0.022 (one sigma).
  // Seeding each sample's PCG with the pixel's state and the sample index as its increment gave
  // 0.63-1.08 across the first eight dimensions.
  PixelSampler sampler(SamplerKind::Independent, 1, 256);
  const int n = 256, pixels = 4096;
  for (int dimension = 0; dimension < 8; ++dimension) {
    double variance = 0;
    for (int p = 0; p < pixels; ++p) {
      double sum = 0;
      for (int i = 0; i < n; ++i) {
        sampler.startSample(p % 64, p / 64, uint32_t(i));
        float u = 0;
        for (int d = 0; d <= dimension; ++d) u = sampler.next1D();
        sum += u;
      }
      const double z = (sum / n - 0.5) / std::sqrt(1.0 / 12.0 / n);
      variance += z * z / pixels;
    }
    EXPECT_NEAR(variance, 1.0, 0.1) << "dimension " << dimension;
  }
}

TEST(Sampler, OwenScrambledDimensionsStayStratified) {
  // Owen scrambling permutes the digits nestedly, so every elementary interval still holds one
  // point, in both block orders and past the first block.
  for (BlockOrder order : {BlockOrder::Nested, BlockOrder::Shuffled}) {
    for (int m : {0, 2, 4, 6}) {
      PixelSampler sampler(SamplerKind::LowDiscrepancy, 99, 1u << m, order);
      for (uint32_t first : {0u, 1u << m}) {
        std::vector<glm::vec2> points;
        std::set<int> strata;
        for (uint32_t i = first; i < first + (1u << m); ++i) {
          sampler.startSample(5, 9, i);
          sampler.cameraSample();
          strata.insert(int(sampler.next1D(Scrambling::Owen) * float(1 << m)));
          points.push_back(sampler.next2D(Scrambling::Owen));
        }
        expectElementaryIntervals(points, m);
        EXPECT_EQ(int(strata.size()), 1 << m) << "1D: one point per stratum";
      }
    }
  }
}

TEST(Sampler, OwenScramblingGivesEachSampleItsOwnFineDigits) {
  // The 64 samples of a pixel, and the digits below their 1/64 strata: with a digital shift
  // they are the pixel's scramble in every sample, so a choice made by them (the 10th binary
  // digit here, as an alias table's accept test reads the digits below its column) is the same
  // for all 64; Owen-scrambled, about half the samples take each branch.
  PixelSampler sampler(SamplerKind::LowDiscrepancy, 3, 64);
  for (int pixel = 0; pixel < 8; ++pixel) {
    int shiftedOnes[2] = {0, 0}, owenOnes[2] = {0, 0};
    for (uint32_t i = 0; i < 64; ++i) {
      sampler.startSample(pixel, 2 * pixel, i);
      sampler.cameraSample();
      const glm::vec2 shifted = sampler.next2D(Scrambling::DigitalShift);
      const glm::vec2 owen = sampler.next2D(Scrambling::Owen);
      auto tenthDigit = [](float u) { return int(u * 1024.0f) & 1; };
      shiftedOnes[0] += tenthDigit(shifted.x), shiftedOnes[1] += tenthDigit(shifted.y);
      owenOnes[0] += tenthDigit(owen.x), owenOnes[1] += tenthDigit(owen.y);
    }
    for (int c = 0; c < 2; ++c) {
      EXPECT_TRUE(shiftedOnes[c] == 0 || shiftedOnes[c] == 64) << shiftedOnes[c];
      // Binomial(64, 1/2): 32 +- 4; 16 and 48 are four standard deviations out.
      EXPECT_GT(owenOnes[c], 16) << "pixel " << pixel << ", coordinate " << c;
      EXPECT_LT(owenOnes[c], 48) << "pixel " << pixel << ", coordinate " << c;
    }
  }
}

TEST(Sampler, OwenScrambleIsANestedPermutationOfTheDigits) {
  // Two fractions that agree in their first k digits agree there after scrambling, and the
  // scramble is a bijection on the digits it sees.
  for (uint32_t seed : {1u, 0x9e3779b9u, 0xdeadbeefu}) {
    std::set<uint32_t> images;
    for (uint32_t top = 0; top < 256; ++top) {
      const uint32_t a = top << 24, b = (top << 24) | 0x00abcdefu;
      EXPECT_EQ(owenScramble(a, seed) >> 24, owenScramble(b, seed) >> 24);
      images.insert(owenScramble(a, seed) >> 24);
    }
    EXPECT_EQ(images.size(), 256u) << "a bijection of the first 8 digits";
    for (uint32_t index : {0u, 1u, 5u, 63u, 1000u, 0xfffffu})
      EXPECT_EQ(owenVanDerCorput(index, seed), toUnitFloat(owenScramble(reverseBits(index), seed)));
  }
}

TEST(Sampler, RadicalInversesMatchHandValues) {
  // Base-2 radical inverse of 1, 2, 3 is 1/2, 1/4, 3/4; Sobol's second dimension of the
  // same indices is 1/2, 3/4, 1/4.
  EXPECT_FLOAT_EQ(vanDerCorput(1, 0), 0.5f);
  EXPECT_FLOAT_EQ(vanDerCorput(2, 0), 0.25f);
  EXPECT_FLOAT_EQ(vanDerCorput(3, 0), 0.75f);
  EXPECT_FLOAT_EQ(sobol2(1, 0), 0.5f);
  EXPECT_FLOAT_EQ(sobol2(2, 0), 0.75f);
  EXPECT_FLOAT_EQ(sobol2(3, 0), 0.25f);
}

TEST(Sampler, Sobol2ByBytesIsTheGeneratorMatrixProduct) {
  // The byte tables against the column-by-column product, on every index below 2^16, on
  // single bits and on hashed 32-bit indices, with scrambles.
  for (uint32_t i = 0; i < (1u << 16); ++i)
    ASSERT_EQ(sobol2Bits(i, 0), sobol2BitsByColumns(i, 0)) << i;
  for (int b = 0; b < 32; ++b)
    ASSERT_EQ(sobol2Bits(1u << b, 0x9e3779b9u), sobol2BitsByColumns(1u << b, 0x9e3779b9u)) << b;
  for (uint32_t k = 0; k < 100000; ++k) {
    const uint32_t i = mixBits32(k), scramble = mixBits32(k ^ 0x5bd1e995u);
    ASSERT_EQ(sobol2Bits(i, scramble), sobol2BitsByColumns(i, scramble)) << i;
  }
  // The matrix's first columns, by hand: 1/2, then 1/2 + 1/4, then 1/2 + 1/8.
  EXPECT_EQ(sobol2Bits(1, 0), 0x80000000u);
  EXPECT_EQ(sobol2Bits(2, 0), 0xC0000000u);
  EXPECT_EQ(sobol2Bits(4, 0), 0xA0000000u);
}

// peek2D shows the value a later next2D returns, and peeking (which keeps the peeked value for
// that draw) changes no draw: the same sequence comes out with and without peeks, across
// samples and pixels, and a peek left undrawn does not leak into the next sample.
TEST(Sampler, APeekIsHandedOutOnlyWithItsScrambling) {
  // The integrator peeks at the light point (Owen-scrambled) for a prefetch: next2D hands the
  // peeked value out when asked with the same scrambling, and computes the other one afresh.
  PixelSampler plain(SamplerKind::LowDiscrepancy, 11, 16),
      peeking(SamplerKind::LowDiscrepancy, 11, 16);
  for (uint32_t i = 0; i < 16; ++i) {
    plain.startSample(4, 1, i);
    peeking.startSample(4, 1, i);
    glm::vec2 peeked;
    ASSERT_TRUE(peeking.peek2D(1, peeked, Scrambling::Owen));
    EXPECT_EQ(plain.next1D(Scrambling::Owen), peeking.next1D(Scrambling::Owen));
    const glm::vec2 owen = plain.next2D(Scrambling::Owen);
    EXPECT_EQ(peeking.next2D(Scrambling::Owen), owen);
    EXPECT_EQ(peeked, owen);
    // The same dimension with the other scrambling, from a sampler that peeked with Owen.
    PixelSampler shifted(SamplerKind::LowDiscrepancy, 11, 16);
    shifted.startSample(4, 1, i);
    shifted.next1D();
    glm::vec2 unused;
    peeking.startSample(4, 1, i);
    ASSERT_TRUE(peeking.peek2D(1, unused, Scrambling::Owen));
    peeking.next1D();
    EXPECT_EQ(peeking.next2D(), shifted.next2D());
  }
}

TEST(Sampler, PeekingChangesNoDraw) {
  PixelSampler plain(SamplerKind::LowDiscrepancy, 7, 16),
      peeking(SamplerKind::LowDiscrepancy, 7, 16);
  for (int pixel = 0; pixel < 3; ++pixel)
    for (uint32_t i = 0; i < 16; ++i) {
      plain.startSample(pixel, 2 * pixel, i);
      peeking.startSample(pixel, 2 * pixel, i);
      for (int bounce = 0; bounce < 4; ++bounce) {
        glm::vec2 peeked;
        ASSERT_TRUE(peeking.peek2D(1, peeked));
        if (i % 4 == 3 && bounce == 3) break;  // a peek that is never drawn
        EXPECT_EQ(plain.next1D(), peeking.next1D());
        const glm::vec2 a = plain.next2D(), b = peeking.next2D();
        EXPECT_EQ(a, b);
        EXPECT_EQ(b, peeked);
        EXPECT_EQ(plain.next2D(), peeking.next2D());
      }
      EXPECT_EQ(plain.next2D(), peeking.next2D());
    }
  // A peek, then a new sample of another pixel drawn without peeks: the peeked dimension's
  // draw is the new sample's own.
  glm::vec2 stale;
  peeking.startSample(5, 5, 3);
  ASSERT_TRUE(peeking.peek2D(1, stale));
  plain.startSample(6, 5, 3);
  peeking.startSample(6, 5, 3);
  EXPECT_EQ(plain.next1D(), peeking.next1D());
  EXPECT_EQ(plain.next2D(), peeking.next2D());
  PixelSampler independent(SamplerKind::Independent, 7, 16);
  glm::vec2 unused;
  independent.startSample(0, 0, 0);
  EXPECT_FALSE(independent.peek2D(1, unused));
}

}  // namespace
}  // namespace penumbra
