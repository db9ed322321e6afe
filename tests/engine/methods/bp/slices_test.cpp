// Tests for engine/bp_slices: slice ids and histogram levels at their edges, eq. 14 and eq. 15
// worked out by hand, the running-sum form of eq. 15 against the explicit one, the choice of
// B and C, the eq. 16 candidate score, and the mirroring of positions between slices.
#include "methods/bp/slices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace penumbra {
namespace {

constexpr int kLevels = 5;  // m of §6.2

SliceStats sliceOfValues(std::initializer_list<float> values) {
  SliceStats slice;
  for (float v : values) slice.add(v, kLevels);
  return slice;
}

// Level = min(m - 1, floor(m v)) with m = 5, negatives counted as 0:
//   0 -> 0;  0.2 -> floor(1.0) = 1 (a value on an edge goes up);  0.1999 -> floor(0.9995) = 0;
//   0.99 -> floor(4.95) = 4;  1.5 -> min(4, 7) = 4;  -0.1 -> 0.
TEST(BpSlices, HistogramLevelEdges) {
  EXPECT_EQ(histogramLevel(0.0f, 5), 0);
  EXPECT_EQ(histogramLevel(0.2f, 5), 1);
  EXPECT_EQ(histogramLevel(0.1999f, 5), 0);
  EXPECT_EQ(histogramLevel(0.99f, 5), 4);
  EXPECT_EQ(histogramLevel(1.5f, 5), 4);
  EXPECT_EQ(histogramLevel(-0.1f, 5), 0);
  // The other interior edges: 0.4 -> 2, 0.6 -> 3, 0.8 -> 4, and just below 0.8 -> 3.
  EXPECT_EQ(histogramLevel(0.4f, 5), 2);
  EXPECT_EQ(histogramLevel(0.6f, 5), 3);
  EXPECT_EQ(histogramLevel(0.8f, 5), 4);
  EXPECT_EQ(histogramLevel(0.7999f, 5), 3);
  EXPECT_EQ(histogramLevel(std::numeric_limits<float>::infinity(), 5), 4);
  EXPECT_EQ(histogramLevel(std::numeric_limits<float>::quiet_NaN(), 5), 0);
}

// S = 2: id = floor(2 ox) + 2 floor(2 oy); S = 3: id = floor(3 ox) + 3 floor(3 oy). Offsets of
// exactly 1 or a rounding error below 0 are clamped into the pixel.
TEST(BpSlices, SliceOfTwoAndThreePerSide) {
  EXPECT_EQ(sliceOf(0.1f, 0.1f, 2), 0);
  EXPECT_EQ(sliceOf(0.6f, 0.1f, 2), 1);
  EXPECT_EQ(sliceOf(0.1f, 0.6f, 2), 2);
  EXPECT_EQ(sliceOf(0.6f, 0.6f, 2), 3);
  EXPECT_EQ(sliceOf(0.5f, 0.5f, 2), 3);          // floor(1) + 2 floor(1)
  EXPECT_EQ(sliceOf(0.49999f, 0.99999f, 2), 2);  // 0 + 2 * 1
  EXPECT_EQ(sliceOf(1.0f, 1.0f, 2), 3);          // clamped, not 2 + 2 * 2 = 6
  EXPECT_EQ(sliceOf(-1e-7f, -1e-7f, 2), 0);      // clamped, not -1 - 2 = -3

  EXPECT_EQ(sliceOf(0.34f, 0.0f, 3), 1);  // floor(1.02) = 1
  EXPECT_EQ(sliceOf(0.0f, 0.34f, 3), 3);  // 0 + 3 * 1
  EXPECT_EQ(sliceOf(0.5f, 0.5f, 3), 4);   // 1 + 3 * 1
  EXPECT_EQ(sliceOf(0.99f, 0.1f, 3), 2);
  EXPECT_EQ(sliceOf(0.1f, 0.99f, 3), 6);
  EXPECT_EQ(sliceOf(0.7f, 0.7f, 3), 8);  // 2 + 3 * 2
  EXPECT_EQ(sliceOf(1.0f, 1.0f, 3), 8);
  EXPECT_EQ(sliceOf(-1e-7f, 1.0f, 3), 6);
}

TEST(BpSlices, AddKeepsSumsAndHistogram) {
  // 0.25 -> level 1, 0.81 -> level 4, -0.5 -> level 0 (and contributes 0 to sum sqrt v).
  const SliceStats s = sliceOfValues({0.25f, 0.81f, -0.5f});
  EXPECT_EQ(s.count, 3u);
  EXPECT_NEAR(s.sumV, 0.25 + 0.81 - 0.5, 1e-7);
  EXPECT_NEAR(s.sumSqrtV, 0.5 + 0.9, 1e-7);
  EXPECT_EQ(s.histogram[0], 1);
  EXPECT_EQ(s.histogram[1], 1);
  EXPECT_EQ(s.histogram[4], 1);
  EXPECT_NEAR(s.meanV(), 0.56 / 3.0, 1e-7);
  EXPECT_EQ(SliceStats{}.meanV(), 0.0);
}

TEST(BpSlices, HistogramBinSaturatesInsteadOfWrapping) {
  SliceStats s;
  for (int i = 0; i < 70000; ++i) s.add(0.1f, kLevels);
  EXPECT_EQ(s.count, 70000u);
  EXPECT_EQ(s.histogram[0], 65535);
}

// X = {0.1, 0.1, 0.3} -> h(X) = (2, 1, 0, 0, 0), N_X = 3
// Y = {0.3, 0.9}      -> h(Y) = (0, 1, 0, 0, 1), N_Y = 2
// Bins with hX + hY > 0, term (N_Y hX - N_X hY)^2 / (N_X N_Y (hX + hY)):
//   bin 0: (2*2 - 3*0)^2 / (6 * 2) = 16 / 12
//   bin 1: (2*1 - 3*1)^2 / (6 * 2) =  1 / 12
//   bin 4: (2*0 - 3*1)^2 / (6 * 1) =  9 / 6  = 18 / 12
// sum = 35 / 12, times 1 / (N_X + N_Y) = 1/5  ->  7 / 12 = 0.58333...
TEST(BpSlices, ChiSquareByHand) {
  const SliceStats x = sliceOfValues({0.1f, 0.1f, 0.3f});
  const SliceStats y = sliceOfValues({0.3f, 0.9f});
  EXPECT_NEAR(chiSquareDistance(x, y, kLevels), 7.0 / 12.0, 1e-15);
}

// Disjoint histograms: each bin gives N_Y hX / N_X (or N_X hY / N_Y), summing to N_Y + N_X,
// so the distance is exactly 1, its maximum. X = {0.1, 0.1}, Y = {0.9}:
//   bin 0: (1*2)^2 / (2*1*2) = 1;  bin 4: (2*1)^2 / (2*1*1) = 2;  (1 + 2) / 3 = 1.
TEST(BpSlices, ChiSquareOfDisjointHistogramsIsOne) {
  EXPECT_NEAR(chiSquareDistance(sliceOfValues({0.1f, 0.1f}), sliceOfValues({0.9f}), kLevels), 1.0,
              1e-15);
}

TEST(BpSlices, ChiSquareOfIdenticalOrProportionalHistogramsIsZero) {
  const SliceStats x = sliceOfValues({0.1f, 0.5f, 0.9f});
  EXPECT_EQ(chiSquareDistance(x, x, kLevels), 0.0);
  // Same shape, twice the samples: N_Y hX - N_X hY = 6 * 1 - 3 * 2 = 0 in every bin.
  const SliceStats y = sliceOfValues({0.15f, 0.55f, 0.95f, 0.05f, 0.45f, 0.85f});
  EXPECT_EQ(chiSquareDistance(x, y, kLevels), 0.0);
}

TEST(BpSlices, ChiSquareIsSymmetricAndZeroForAnEmptySlice) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (int trial = 0; trial < 100; ++trial) {
    SliceStats x, y;
    for (int i = 0; i < 1 + trial % 7; ++i) x.add(value(rng), kLevels);
    for (int i = 0; i < 1 + trial % 5; ++i) y.add(value(rng), kLevels);
    EXPECT_DOUBLE_EQ(chiSquareDistance(x, y, kLevels), chiSquareDistance(y, x, kLevels));
  }
  const SliceStats x = sliceOfValues({0.1f, 0.9f});
  EXPECT_EQ(chiSquareDistance(x, SliceStats{}, kLevels), 0.0);
  EXPECT_EQ(chiSquareDistance(SliceStats{}, x, kLevels), 0.0);
}

// Values {0.2, 0.6}: N = 2, sum = 0.8, p = (0.25, 0.75), mean = 0.4.
//   1/2 sum (sqrt p_i - sqrt(1/2))^2 = 1 - (sqrt 0.25 + sqrt 0.75) / sqrt 2
//                                    = 1 - (0.5 + 0.8660254) / 1.4142136 = 1 - 0.9659258
//                                    = 1 - cos 15 deg = 0.0340742
//   fdiver = (1/2) * 0.4 * sqrt(0.0340742) = 0.2 * 0.1845919 = 0.0369184
TEST(BpSlices, FDivergenceByHand) {
  const double expected = 0.2 * std::sqrt(1.0 - std::cos(15.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(expected, 0.0369184, 1e-7);
  const std::vector<float> values{0.2f, 0.6f};
  EXPECT_NEAR(fDivergence(values), expected, 1e-8);
  EXPECT_NEAR(fDivergence(sliceOfValues({0.2f, 0.6f})), expected, 1e-8);
}

// A uniform slice is at Hellinger distance 0 from the uniform distribution: p = (1/2, 1/2).
// The sums form computes 1 - sqrt(0.5) * 2 / sqrt(2 * 1), which may round to +-1e-16 (then
// clamped at 0), so it is only near 0: mean/N * sqrt(2e-16) < 1e-8.
TEST(BpSlices, FDivergenceOfUniformValuesIsZero) {
  const std::vector<float> values{0.5f, 0.5f};
  EXPECT_EQ(fDivergence(values), 0.0);
  EXPECT_NEAR(fDivergence(sliceOfValues({0.5f, 0.5f})), 0.0, 1e-8);
}

TEST(BpSlices, FDivergenceDegenerateCasesAreZero) {
  const std::vector<float> one{0.7f}, zeros{0.0f, 0.0f, 0.0f}, none;
  EXPECT_EQ(fDivergence(one), 0.0);
  EXPECT_EQ(fDivergence(zeros), 0.0);
  EXPECT_EQ(fDivergence(none), 0.0);
  EXPECT_EQ(fDivergence(sliceOfValues({0.7f})), 0.0);
  EXPECT_EQ(fDivergence(sliceOfValues({0.0f, 0.0f})), 0.0);
  EXPECT_EQ(fDivergence(SliceStats{}), 0.0);
}

// 1/2 sum (sqrt p_i - sqrt(1/N))^2 = 1/2 (sum p_i - 2 sum sqrt p_i / sqrt N + 1)
//                                  = 1 - sum sqrt v_i / sqrt(N sum v), so both forms agree.
TEST(BpSlices, FDivergenceFromSumsMatchesValues) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (int trial = 0; trial < 1000; ++trial) {
    std::vector<float> values(size_t(2 + trial % 40));
    SliceStats slice;
    for (float& v : values) {
      v = value(rng);
      slice.add(v, kLevels);
    }
    const double explicitForm = fDivergence(values);
    ASSERT_GT(explicitForm, 0.0);
    EXPECT_NEAR(fDivergence(slice), explicitForm, 1e-9 * explicitForm) << "trial " << trial;
  }
}

// Four slices of one pixel, m = 5:
//   0: {0.02, 0.10, 0.18, 0.10} -> h = (4,0,0,0,0), uneven values
//   1: {0.1, 0.1, 0.9, 0.9}     -> h = (2,0,0,0,2)
//   2: {0.1, 0.9, 0.1, 0.9}     -> h = (2,0,0,0,2)
//   3: {0.9, 0.9, 0.9, 0.9}     -> h = (0,0,0,0,4), uniform
// Eq. 14: (0,3) are disjoint -> 1. (1,2) identical -> 0. Each of (0,1), (0,2), (1,3), (2,3):
//   (4*4 - 4*2)^2 / (16 * 6) + (4*0 - 4*2)^2 / (16 * 2) = 2/3 + 2 = 8/3, / 8 = 1/3.
// So the pair is (0, 3) with contrast 1. Eq. 15: slice 3 is uniform -> 0; slice 0 has
// p = (0.05, 0.25, 0.45, 0.25), sum sqrt p = 1.8944, H^2 = 1 - 1.8944 / 2 = 0.0528,
// fdiver = 0.1 / 4 * sqrt(0.0528) = 0.00574. So B = 3 (less complex), C = 0, and warping.
TEST(BpSlices, ChooseSlicesPicksStrongestContrastAndOrdersByFDivergence) {
  const std::vector<SliceStats> slices{
      sliceOfValues({0.02f, 0.10f, 0.18f, 0.10f}), sliceOfValues({0.1f, 0.1f, 0.9f, 0.9f}),
      sliceOfValues({0.1f, 0.9f, 0.1f, 0.9f}), sliceOfValues({0.9f, 0.9f, 0.9f, 0.9f})};
  EXPECT_NEAR(chiSquareDistance(slices[0], slices[1], kLevels), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(fDivergence(slices[0]), 0.00574, 1e-5);
  const SliceChoice choice = chooseSlices(slices, kLevels);
  EXPECT_EQ(choice.b, 3);
  EXPECT_EQ(choice.c, 0);
  EXPECT_NEAR(choice.contrast, 1.0, 1e-15);
  EXPECT_TRUE(choice.warp);
}

// Slices 1 and 2 both have disjoint histograms from slice 0 (contrast 1, a tie), so the larger
// |mean difference| decides: |0.1 - 0.9| = 0.8 beats |0.15 - 0.9| = 0.75, although slice 0
// has the lower id. Both slices of the pair are constant (eq. 15 = 0 for both): no warping, and
// B is the lower id.
TEST(BpSlices, ChooseSlicesBreaksContrastTiesByMeanDifference) {
  const std::vector<SliceStats> slices{sliceOfValues({0.15f, 0.15f}), sliceOfValues({0.1f, 0.1f}),
                                       sliceOfValues({0.9f, 0.9f})};
  const SliceChoice choice = chooseSlices(slices, kLevels);
  EXPECT_EQ(choice.b, 1);
  EXPECT_EQ(choice.c, 2);
  EXPECT_NEAR(choice.contrast, 1.0, 1e-15);
  EXPECT_FALSE(choice.warp);
}

// Pairs (0,1), (0,3), (1,2), (2,3) all have contrast 1 and mean difference 0.8: the lowest
// ids, (0, 1), win.
TEST(BpSlices, ChooseSlicesBreaksFullTiesByLowerIds) {
  const std::vector<SliceStats> slices{sliceOfValues({0.1f, 0.1f}), sliceOfValues({0.9f, 0.9f}),
                                       sliceOfValues({0.1f, 0.1f}), sliceOfValues({0.9f, 0.9f})};
  const SliceChoice choice = chooseSlices(slices, kLevels);
  EXPECT_EQ(choice.b, 0);
  EXPECT_EQ(choice.c, 1);
  EXPECT_FALSE(choice.warp);  // both f-divergences are 0
}

// Slice 0 has one sample (eq. 15 = 0), slice 1 three uneven ones (eq. 15 > 0): B and C are
// still reported, but with fewer than 2 samples in B there is no warping [A15].
TEST(BpSlices, ChooseSlicesDoesNotWarpWithTooFewSamples) {
  const std::vector<SliceStats> slices{sliceOfValues({0.1f}), sliceOfValues({0.9f, 0.5f, 0.9f}),
                                       SliceStats{}, SliceStats{}};
  const SliceChoice choice = chooseSlices(slices, kLevels);
  EXPECT_EQ(choice.b, 0);
  EXPECT_EQ(choice.c, 1);
  EXPECT_GT(choice.contrast, 0.0);
  EXPECT_FALSE(choice.warp);
}

TEST(BpSlices, ChooseSlicesNeedsTwoNonEmptySlices) {
  const std::vector<SliceStats> one{sliceOfValues({0.1f, 0.9f}), SliceStats{}, SliceStats{},
                                    SliceStats{}};
  SliceChoice choice = chooseSlices(one, kLevels);
  EXPECT_EQ(choice.b, -1);
  EXPECT_EQ(choice.c, -1);
  EXPECT_EQ(choice.contrast, 0.0);
  EXPECT_FALSE(choice.warp);
  choice = chooseSlices(std::vector<SliceStats>(4), kLevels);
  EXPECT_EQ(choice.b, -1);
  EXPECT_EQ(choice.c, -1);
}

// Slice {0.2, 0.5}, candidate 0.3, eps = 0.02:
//   (|0.2 - 0.3| / 0.22 + |0.5 - 0.3| / 0.52) / 2 = (5/11 + 5/13) / 2 = 60/143 = 0.4195804
TEST(BpSlices, CandidateScoreByHand) {
  const std::vector<float> slice{0.2f, 0.5f};
  EXPECT_NEAR(candidateScore(slice, 0.3f), 60.0 / 143.0, 1e-6);
  // With eps = 0.5: (0.1 / 0.7 + 0.2 / 1.0) / 2 = (1/7 + 1/5) / 2 = 12/70 = 0.1714286
  EXPECT_NEAR(candidateScore(slice, 0.3f, 0.5f), 12.0 / 70.0, 1e-6);
  EXPECT_EQ(candidateScore({}, 0.3f), 0.0);
  const std::vector<float> same{0.4f, 0.4f};
  EXPECT_EQ(candidateScore(same, 0.4f), 0.0);
}

// Eq. 16 keeps the candidate with the smallest score: the one closest to the slice's values.
TEST(BpSlices, CandidateClosestToSliceValuesHasMinimumScore) {
  const std::vector<float> slice{0.40f, 0.42f, 0.38f, 0.40f};
  const std::vector<float> candidates{0.10f, 0.95f, 0.39f, 0.70f};
  int best = -1;
  double bestScore = std::numeric_limits<double>::infinity();
  for (int i = 0; i < int(candidates.size()); ++i) {
    const double score = candidateScore(slice, candidates[size_t(i)]);
    if (score < bestScore) {
      bestScore = score;
      best = i;
    }
  }
  EXPECT_EQ(best, 2);
  // A firefly far above the slice scores worst of all.
  EXPECT_GT(candidateScore(slice, 0.95f), candidateScore(slice, 0.10f));
}

// S = 2: slice 0 = (col 0, row 0), 1 = (1, 0), 2 = (0, 1), 3 = (1, 1). Local (0.25, 0.75):
//   0 -> 1 horizontal neighbours: (1 - a, b) = (0.75, 0.75)
//   0 -> 2 vertical neighbours:   (a, 1 - b) = (0.25, 0.25)
//   0 -> 3 and 1 -> 2 diagonal:   (1 - a, 1 - b) = (0.75, 0.25)
TEST(BpSlices, MirrorIntoNeighbourSlices) {
  const glm::vec2 p(0.25f, 0.75f);
  EXPECT_EQ(mirrorIntoSlice(p, 0, 1, 2), glm::vec2(0.75f, 0.75f));
  EXPECT_EQ(mirrorIntoSlice(p, 1, 0, 2), glm::vec2(0.75f, 0.75f));
  EXPECT_EQ(mirrorIntoSlice(p, 0, 2, 2), glm::vec2(0.25f, 0.25f));
  EXPECT_EQ(mirrorIntoSlice(p, 3, 1, 2), glm::vec2(0.25f, 0.25f));
  EXPECT_EQ(mirrorIntoSlice(p, 0, 3, 2), glm::vec2(0.75f, 0.25f));
  EXPECT_EQ(mirrorIntoSlice(p, 1, 2, 2), glm::vec2(0.75f, 0.25f));
  // In pixel coordinates the 0 -> 1 mirror is the reflection across the shared edge x = 1/2:
  // a/2 = 0.125 -> (1 + 0.75)/2 = 0.875 = 1 - 0.125.
  EXPECT_EQ(sliceToPixel(p, 0, 2), glm::vec2(0.125f, 0.375f));
  EXPECT_EQ(sliceToPixel(mirrorIntoSlice(p, 0, 1, 2), 1, 2), glm::vec2(0.875f, 0.375f));
}

// S = 3, slices 0 (col 0, row 0) and 2 (col 2, row 0) are not adjacent: same row -> (1 - a, b);
// 0 and 6 (col 0, row 2): same column -> (a, 1 - b); 1 (col 1, row 0) and 6: neither ->
// (1 - a, 1 - b). Each is the reflection of the pixel position through the centre between
// the two slices, e.g. 1 -> 6: the centres (1/2, 1/6) and (1/6, 5/6) have midpoint (1/3, 1/2),
// and ((1 + a)/3, b/3) reflected through it is ((1 - a)/3, 1 - b/3) = slice 6 at (1 - a, 1 - b).
TEST(BpSlices, MirrorBetweenNonAdjacentSlices) {
  const glm::vec2 p(0.25f, 0.75f);
  EXPECT_EQ(mirrorIntoSlice(p, 0, 2, 3), glm::vec2(0.75f, 0.75f));
  EXPECT_EQ(mirrorIntoSlice(p, 0, 6, 3), glm::vec2(0.25f, 0.25f));
  EXPECT_EQ(mirrorIntoSlice(p, 1, 6, 3), glm::vec2(0.75f, 0.25f));
  EXPECT_EQ(mirrorIntoSlice(p, 0, 8, 3), glm::vec2(0.75f, 0.25f));

  // The geometric statement for every pair with S = 3: the mirrored pixel position is the
  // original reflected through the midpoint of the slice centres, along the axes that differ.
  const int s = 3;
  for (int from = 0; from < s * s; ++from) {
    for (int to = 0; to < s * s; ++to) {
      if (from == to) continue;
      const glm::vec2 original = sliceToPixel(p, from, s);
      const glm::vec2 mirrored = sliceToPixel(mirrorIntoSlice(p, from, to, s), to, s);
      const glm::vec2 centreFrom = sliceToPixel(glm::vec2(0.5f), from, s);
      const glm::vec2 centreTo = sliceToPixel(glm::vec2(0.5f), to, s);
      const glm::vec2 reflected = centreFrom + centreTo - original;
      const float wantX = from % s != to % s ? reflected.x : original.x;
      const float wantY = from / s != to / s ? reflected.y : original.y;
      EXPECT_NEAR(mirrored.x, wantX, 1e-6f) << from << "->" << to;
      EXPECT_NEAR(mirrored.y, wantY, 1e-6f) << from << "->" << to;
    }
  }
}

// Mirroring there and back is the identity: exactly for dyadic positions, to float rounding
// (1 - (1 - a) is not always a in float) for others.
TEST(BpSlices, MirrorTwiceReturnsOriginal) {
  const glm::vec2 dyadic(0.375f, 0.8125f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int s = 2; s <= kMaxSlicesPerSide; ++s) {
    for (int from = 0; from < s * s; ++from) {
      for (int to = 0; to < s * s; ++to) {
        EXPECT_EQ(mirrorIntoSlice(mirrorIntoSlice(dyadic, from, to, s), to, from, s), dyadic);
        const glm::vec2 p(unit(rng), unit(rng));
        const glm::vec2 back = mirrorIntoSlice(mirrorIntoSlice(p, from, to, s), to, from, s);
        EXPECT_NEAR(back.x, p.x, 1e-6f);
        EXPECT_NEAR(back.y, p.y, 1e-6f);
      }
    }
  }
}

// A local 0 mirrors to 1 - 0 = 1, which would name the next slice; it stays just below 1.
TEST(BpSlices, MirroredPositionStaysInsideTheSlice) {
  const glm::vec2 m = mirrorIntoSlice(glm::vec2(0.0f, 0.0f), 0, 3, 2);
  EXPECT_LT(m.x, 1.0f);
  EXPECT_LT(m.y, 1.0f);
  EXPECT_GT(m.x, 0.9999f);
  EXPECT_EQ(sliceOf(sliceToPixel(m, 3, 2).x, sliceToPixel(m, 3, 2).y, 2), 3);
}

// ((col + a)/S, (row + b)/S): S = 2, slice 3 at (0.5, 0.5) -> (0.75, 0.75); S = 3, slice 5
// (col 2, row 1) at (0.5, 0.25) -> (2.5/3, 1.25/3). And sliceOf finds the slice again.
TEST(BpSlices, SliceToPixelAndBack) {
  EXPECT_EQ(sliceToPixel(glm::vec2(0.5f), 3, 2), glm::vec2(0.75f, 0.75f));
  const glm::vec2 q = sliceToPixel(glm::vec2(0.5f, 0.25f), 5, 3);
  EXPECT_NEAR(q.x, 2.5f / 3.0f, 1e-7f);
  EXPECT_NEAR(q.y, 1.25f / 3.0f, 1e-7f);

  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int s = 1; s <= kMaxSlicesPerSide; ++s) {
    for (int slice = 0; slice < s * s; ++slice) {
      for (glm::vec2 local : {glm::vec2(0.0f), glm::vec2(std::nextafter(1.0f, 0.0f)),
                              glm::vec2(unit(rng), unit(rng))}) {
        const glm::vec2 o = sliceToPixel(local, slice, s);
        EXPECT_GE(o.x, 0.0f);
        EXPECT_LT(o.x, 1.0f);
        EXPECT_LT(o.y, 1.0f);
        EXPECT_EQ(sliceOf(o.x, o.y, s), slice) << "S " << s << " local " << local.x;
      }
    }
  }
}

}  // namespace
}  // namespace penumbra
