// Sub-pixel slices of ALGORITHM.md §6-§7: S x S equal image-space strata per pixel, their
// quantised luminance histograms, the chi-square contrast of eq. 14 that picks the pair of
// slices with the strongest contrast, the f-divergence of eq. 15 that tells the less complex
// slice B from the more complex C, the candidate score of eq. 16, and the symmetric
// transfer ("warping") of sample positions from B into C.
//
// All scalar values v are tone-mapped luminances in [0, 1) (§0).
#pragma once

#include <glm/vec2.hpp>

#include <cstdint>
#include <span>

namespace penumbra {

constexpr int kMaxHistogramLevels = 16;
constexpr int kMaxSlicesPerSide = 4;  // S <= 4, so at most 16 slices

// Slice id of local offset (ox, oy) in [0,1)^2: floor(S ox) + S floor(S oy).
int sliceOf(float ox, float oy, int slicesPerSide);

// Histogram level of v with m levels: min(m - 1, floor(m v)), v < 0 counted as 0 [A14].
int histogramLevel(float v, int levels);

// Running statistics of one slice: enough for eq. 14 and eq. 15 without keeping samples.
struct SliceStats {
  uint32_t count = 0;
  double sumV = 0.0;      // sum of v
  double sumSqrtV = 0.0;  // sum of sqrt(v)
  uint16_t histogram[kMaxHistogramLevels] = {};
  void add(float v, int levels);
  double meanV() const { return count ? sumV / count : 0.0; }
};

// Eq. 14, chi-square distance between the histograms of two slices:
//   1/(N_X+N_Y) * sum_{i: hX_i+hY_i>0} (N_Y hX_i - N_X hY_i)^2 / (N_X N_Y (hX_i + hY_i)).
// 0 if either slice is empty.
double chiSquareDistance(const SliceStats& x, const SliceStats& y, int levels);

// Eq. 15 on explicit values: p_i = v_i / sum v, mean = sum v / N,
//   fdiver = (1/N) * mean * sqrt(1/2 * sum_i (sqrt(p_i) - sqrt(1/N))^2); 0 if N <= 1 or sum 0.
double fDivergence(std::span<const float> values);
// The same from running sums, using 1/2 sum(...)^2 = 1 - sum sqrt(v_i) / sqrt(N sum v).
double fDivergence(const SliceStats& slice);

// The slice choice of one pixel for a round (§6.3-§6.4).
struct SliceChoice {
  int b = -1, c = -1;     // -1: no pair (fewer than two non-empty slices)
  double contrast = 0.0;  // eq. 14 of the chosen pair
  bool warp = false;      // move B's new sample into C; false on a tie or < 2 samples [A15]
};
// Picks the pair with the largest eq. 14 distance (ties: larger |mean v difference|, then
// the lower slice ids), then B = the smaller eq. 15 value, C = the larger. No warping when
// the two f-divergences are within 1e-6 or either slice has fewer than 2 samples.
SliceChoice chooseSlices(std::span<const SliceStats> slices, int levels);

// Eq. 16 slice error of a candidate with value vCand against the slice's values:
//   (1/N) sum_i |v_i - vCand| / (v_i + eps); 0 when the slice is empty.
double candidateScore(std::span<const float> sliceValues, float vCand, float eps = 0.02f);

// Local position (a, b) in [0,1)^2 inside slice `from`, mirrored into slice `to` (§7.3):
// same row -> (1-a, b); same column -> (a, 1-b); otherwise (diagonal) -> (1-a, 1-b).
glm::vec2 mirrorIntoSlice(glm::vec2 local, int from, int to, int slicesPerSide);

// Pixel offset in [0,1)^2 of local position (a, b) inside `slice`, and back.
glm::vec2 sliceToPixel(glm::vec2 local, int slice, int slicesPerSide);

}  // namespace penumbra
