// Sub-pixel slices, their histograms and the slice statistics of ALGORITHM.md §6-§7.
#include "methods/bp/slices.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra {
namespace {

// Pairs whose eq. 14 distances (or mean differences) differ by less than this are tied:
// the sums behind them are rounded differently depending on summation order, so an exact
// comparison would let the last bit pick the pair.
constexpr double kTieTolerance = 1e-12;
// [A15]: f-divergences closer than this do not tell B from C.
constexpr double kFDivergenceTie = 1e-6;
// Largest float below 1: positions stay inside [0,1) even when 1 - a or (col + a) / S
// rounds up to 1, so a sample never lands in the next slice or pixel.
constexpr float kBelowOne = 1.0f - std::numeric_limits<float>::epsilon() / 2.0f;

// Stratum of an offset along one axis, clamped so that o = 1 (or a rounding error just
// below 0) still names a valid stratum. NaN goes to stratum 0 rather than being UB in
// the float-to-int conversion.
int stratumOf(float offset, int slicesPerSide) {
  const float cell = std::floor(offset * float(slicesPerSide));
  if (!(cell >= 0.0f)) return 0;
  if (cell >= float(slicesPerSide - 1)) return slicesPerSide - 1;
  return int(cell);
}

// (stratum + local) / S rounded to float, nudged back into the stratum where rounding pushed
// it across an edge: a local position just below 1 in stratum 2 of 4 rounds to exactly 3/4,
// and the sample would be counted in the neighbouring slice. A few ulps at most, so the
// loops are bounded (which also keeps an invalid stratum from looping forever).
float offsetInStratum(float local, int stratum, int slicesPerSide) {
  // The last stratum ends at the pixel edge, which stratumOf clamps rather than reports.
  float offset =
      std::min(float((double(stratum) + double(local)) / double(slicesPerSide)), kBelowOne);
  for (int step = 0; step < 8 && stratumOf(offset, slicesPerSide) > stratum; ++step)
    offset = std::nextafter(offset, 0.0f);
  for (int step = 0; step < 8 && stratumOf(offset, slicesPerSide) < stratum; ++step)
    offset = std::nextafter(offset, 1.0f);
  return offset;
}

// N(X) of §6.2: the histogram total, which is what eq. 14 is normalised by.
double histogramTotal(const SliceStats& slice, int levels) {
  double total = 0.0;
  for (int i = 0; i < levels; ++i) total += slice.histogram[i];
  return total;
}

}  // namespace

int sliceOf(float ox, float oy, int slicesPerSide) {
  return stratumOf(ox, slicesPerSide) + slicesPerSide * stratumOf(oy, slicesPerSide);
}

int histogramLevel(float v, int levels) {
  // The product is formed in double, where m * v is exact, so a value like 0.2f lands in
  // the level its decimal spelling suggests instead of depending on float rounding.
  const double scaled = std::floor(double(levels) * double(v));
  if (!(scaled > 0.0)) return 0;  // negative values and NaN [A14]
  if (scaled >= double(levels - 1)) return levels - 1;
  return int(scaled);
}

void SliceStats::add(float v, int levels) {
  ++count;
  sumV += v;
  sumSqrtV += v > 0.0f ? std::sqrt(double(v)) : 0.0;
  uint16_t& bin = histogram[histogramLevel(v, levels)];
  if (bin < std::numeric_limits<uint16_t>::max()) ++bin;  // saturate instead of wrapping to 0
}

double chiSquareDistance(const SliceStats& x, const SliceStats& y, int levels) {
  const double nx = histogramTotal(x, levels), ny = histogramTotal(y, levels);
  if (nx == 0.0 || ny == 0.0) return 0.0;
  double sum = 0.0;
  for (int i = 0; i < levels; ++i) {
    const double hx = x.histogram[i], hy = y.histogram[i];
    if (hx + hy == 0.0) continue;  // empty bins carry no evidence and would divide by 0
    const double d = ny * hx - nx * hy;
    sum += d * d / (nx * ny * (hx + hy));
  }
  return sum / (nx + ny);
}

double fDivergence(std::span<const float> values) {
  const size_t n = values.size();
  if (n <= 1) return 0.0;
  double total = 0.0;
  for (float v : values) total += v;
  if (!(total > 0.0)) return 0.0;
  const double uniform = std::sqrt(1.0 / double(n));
  double squares = 0.0;
  for (float v : values) {
    // Negative values would give sqrt of a negative p; they count as 0, as in SliceStats.
    const double d = std::sqrt(std::max(0.0, double(v) / total)) - uniform;
    squares += d * d;
  }
  const double mean = total / double(n);
  return mean / double(n) * std::sqrt(0.5 * squares);
}

double fDivergence(const SliceStats& slice) {
  if (slice.count <= 1 || !(slice.sumV > 0.0)) return 0.0;
  const double n = slice.count;
  // 1/2 sum (sqrt p_i - sqrt(1/N))^2 expands to 1 - sum sqrt(v_i) / sqrt(N sum v). The
  // subtraction cancels for near-uniform slices and can come out a rounding error below 0.
  const double hellingerSquared = std::max(0.0, 1.0 - slice.sumSqrtV / std::sqrt(n * slice.sumV));
  return slice.meanV() / n * std::sqrt(hellingerSquared);
}

SliceChoice chooseSlices(std::span<const SliceStats> slices, int levels) {
  SliceChoice choice;
  double bestMeanGap = 0.0;
  const int count = int(slices.size());
  // Pairs are visited in increasing (i, j) order, so on a full tie the first one found
  // (the lower ids) is kept.
  for (int i = 0; i < count; ++i) {
    if (slices[i].count < 1) continue;
    for (int j = i + 1; j < count; ++j) {
      if (slices[j].count < 1) continue;
      const double contrast = chiSquareDistance(slices[i], slices[j], levels);
      const double meanGap = std::abs(slices[i].meanV() - slices[j].meanV());
      bool better = choice.b < 0 || contrast > choice.contrast + kTieTolerance;
      if (!better && std::abs(contrast - choice.contrast) <= kTieTolerance)
        better = meanGap > bestMeanGap + kTieTolerance;
      if (!better) continue;
      choice.b = i;
      choice.c = j;
      choice.contrast = contrast;
      bestMeanGap = meanGap;
    }
  }
  if (choice.b < 0) return SliceChoice{};

  const double fi = fDivergence(slices[choice.b]), fj = fDivergence(slices[choice.c]);
  if (fj < fi) std::swap(choice.b, choice.c);
  // Written as "differ by more than" so that a NaN divergence also means no warping.
  choice.warp = std::abs(fi - fj) > kFDivergenceTie && slices[choice.b].count >= 2 &&
                slices[choice.c].count >= 2;
  return choice;
}

double candidateScore(std::span<const float> sliceValues, float vCand, float eps) {
  if (sliceValues.empty()) return 0.0;
  double sum = 0.0;
  for (float v : sliceValues) sum += std::abs(double(v) - vCand) / (double(v) + eps);
  return sum / double(sliceValues.size());
}

glm::vec2 mirrorIntoSlice(glm::vec2 local, int from, int to, int slicesPerSide) {
  // Within one slice there is no line to mirror across; the position stays where it is.
  if (from == to) return local;
  const bool sameRow = from / slicesPerSide == to / slicesPerSide;
  const bool sameColumn = from % slicesPerSide == to % slicesPerSide;
  // Slices side by side mirror across the vertical line between them, stacked slices
  // across the horizontal one; any other pair is a point reflection through the centre
  // between the two slices, which flips both coordinates.
  glm::vec2 out = local;
  if (!sameColumn) out.x = std::min(1.0f - local.x, kBelowOne);
  if (!sameRow) out.y = std::min(1.0f - local.y, kBelowOne);
  return out;
}

glm::vec2 sliceToPixel(glm::vec2 local, int slice, int slicesPerSide) {
  const int col = slice % slicesPerSide, row = slice / slicesPerSide;
  return {offsetInStratum(local.x, col, slicesPerSide),
          offsetInStratum(local.y, row, slicesPerSide)};
}

}  // namespace penumbra
