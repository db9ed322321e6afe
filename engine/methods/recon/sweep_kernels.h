// The row kernels of the filter bank's sweep (methods/recon/sweep.cpp), on plain restrict
// pointers so that they vectorise. Every kernel runs over n pixels p = 0 .. n-1 of a row;
// p + shift is the pixel q of the pair (p, q) in the same plane. Internal to methods/recon.
#pragma once

#include <bit>
#include <cstddef>

namespace penumbra::recon::detail {

// The epsilon of §2's denominator.
inline constexpr float kColourEpsilon = 1e-10f;

// e^x for x <= 0 to about 1e-4 relative (plenty for a weight), without calls or branches so that
// the loops over it vectorise; 0 (or a denormal, which the sweep flushes to 0) below -87, and 0 for
// NaN. e^x = (e^(x/2))^2; with (x/2) log2(e) = n + f, n an integer and |f| <= 1/2, e^(x/2) = 2^n
// e^(f ln 2): the power of two is built in the exponent bits and the second factor is its Taylor
// series to the 4th power (truncation error below 5e-5). The half is clamped at -87, where 2^n is
// still a normal float; its square is then below 1e-75, 0 in float.
inline float expNonPositive(float x) {
  const float half = 0.5f * x;
  const float clamped = half > -87.0f ? half : -87.0f;
  const float t = clamped * 1.44269504f;
  // For t <= 0, truncating t - 1/2 rounds it up: n = ceil(t - 1/2), f = t - n in (-1/2, 1/2].
  const int n = int(t - 0.5f);
  const float r = (t - float(n)) * 0.693147181f;
  float p = 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  const float root = p * std::bit_cast<float>((n + 127) << 23);
  return root * root;
}

// The kernels take their planes as restrict parameters (GCC honours restrict reliably only
// there) and avoid selects whose arms compute: either keeps a loop from vectorising.

// Per-pixel colour distances above this are clamped to it, so that the patch's sums of them
// stay finite (any d^2 above about 90 gives a weight of e^-87 anyway).
inline constexpr float kMaxDistance = 1e30f;

// §2's per-channel distance of the pair (p, q):
//   d^2_c = [(u_c(p) - u_c(q))^2 - alpha (V_c(p) + min(V_c(p), V_c(q)))]
//           / [eps + k^2 (V_c(p) + V_c(q))]
// the numerator's second term being the expected noise in the squared difference. For two
// guides of the same variance (the halves), sharing the noise terms.
#define PENUMBRA_RECON_CHANNEL(v, a, b)                           \
  {                                                               \
    const float vp = v[x], vq = v[x + shift];                     \
    const float noise = alpha * (vp + (vp < vq ? vp : vq));       \
    const float scale = 1.0f / (kColourEpsilon + k2 * (vp + vq)); \
    const float diffA = a[x] - a[x + shift];                      \
    sumA += (diffA * diffA - noise) * scale;                      \
    if constexpr (Two) {                                          \
      const float diffB = b[x] - b[x + shift];                    \
      sumB += (diffB * diffB - noise) * scale;                    \
    }                                                             \
  }

// d0 (and d1 when Two) = the distance summed over the channels with guide a (b), times
// pairs = 1 where both pixels are valid, else 0.
template <bool Two>
void colourDistanceRow(int n, ptrdiff_t shift, float k2, float alpha, const float* __restrict v0,
                       const float* __restrict v1, const float* __restrict v2,
                       const float* __restrict a0, const float* __restrict a1,
                       const float* __restrict a2, const float* __restrict b0,
                       const float* __restrict b1, const float* __restrict b2,
                       const float* __restrict valid, float* __restrict d0, float* __restrict d1,
                       float* __restrict pairs) {
  for (int x = 0; x < n; ++x) {
    float sumA = 0.0f, sumB = 0.0f;
    PENUMBRA_RECON_CHANNEL(v0, a0, b0)
    PENUMBRA_RECON_CHANNEL(v1, a1, b1)
    PENUMBRA_RECON_CHANNEL(v2, a2, b2)
    const float both = valid[x] * valid[x + shift];
    d0[x] = both * (sumA < kMaxDistance ? sumA : kMaxDistance);
    if constexpr (Two) d1[x] = both * (sumB < kMaxDistance ? sumB : kMaxDistance);
    pairs[x] = both;
  }
}
#undef PENUMBRA_RECON_CHANNEL

// box[x] = sum of source[x - radius .. x + radius]; source has radius readable (zero) values
// before its first and after its last pixel.
inline void boxRow(int n, int radius, const float* __restrict source, float* __restrict box) {
  for (int x = 0; x < n; ++x) box[x] = source[x - radius];
  for (int t = 1 - radius; t <= radius; ++t) {
    const float* __restrict shifted = source + t;
    for (int x = 0; x < n; ++x) box[x] += shifted[x];
  }
}

inline void addRow(int n, const float* __restrict source, float* __restrict sum) {
  for (int x = 0; x < n; ++x) sum[x] += source[x];
}

// §3 for one feature: phi = max(phi, Phi_j) with
//   Phi_j = (|f(p) - f(q)|^2 - (Var(p) + min(Var(p), Var(q)))) * inverseScale(p).
template <int Components>
void featureRow(int n, ptrdiff_t shift, const float* __restrict f0, const float* __restrict f1,
                const float* __restrict f2, const float* __restrict var,
                const float* __restrict inv, float* __restrict phi) {
  for (int x = 0; x < n; ++x) {
    const float diff0 = f0[x] - f0[x + shift];
    float squared = diff0 * diff0;
    if constexpr (Components == 3) {
      const float diff1 = f1[x] - f1[x + shift], diff2 = f2[x] - f2[x + shift];
      squared += diff1 * diff1 + diff2 * diff2;
    }
    const float vp = var[x], vq = var[x + shift];
    const float distance = (squared - (vp + (vp < vq ? vp : vq))) * inv[x];
    phi[x] = distance > phi[x] ? distance : phi[x];
  }
}

// w = exp(-max(0, d^2, max_j Phi_j)), which is min(w_c, w_f), with d^2 the colour distance
// averaged over the channels and the patch's pairs that exist; 0 where the centre pair
// (p, q) is not valid (otherwise it is one of the patch's pairs, so pairs >= 1). The patch's
// sums are those of Side rows of the row-boxed distances h0, h1 and pairs hp, `stride` apart.
template <bool Two, int Side>
void weightRow(int n, ptrdiff_t shift, const float* __restrict valid, const float* __restrict h0,
               const float* __restrict h1, const float* __restrict hp, size_t stride,
               const float* __restrict phi, float* __restrict w0, float* __restrict w1) {
  for (int x = 0; x < n; ++x) {
    float box0 = h0[x], box1 = 0.0f, boxPairs = hp[x];
    if constexpr (Two) box1 = h1[x];
    for (int t = 1; t < Side; ++t) {
      box0 += h0[x + t * stride];
      if constexpr (Two) box1 += h1[x + t * stride];
      boxPairs += hp[x + t * stride];
    }
    const float pairs = boxPairs > 1.0f ? boxPairs : 1.0f;
    const float toMean = 1.0f / (3.0f * pairs);
    const float f = phi[x] > 0.0f ? phi[x] : 0.0f;
    // 1 or 0, and the exponential is finite: a product rather than a select keeps the loop
    // vectorisable.
    const float centre = valid[x] * valid[x + shift];
    const float c0 = box0 * toMean;
    w0[x] = centre * expNonPositive(-(c0 > f ? c0 : f));
    if constexpr (Two) {
      const float c1 = box1 * toMean;
      w1[x] = centre * expNonPositive(-(c1 > f ? c1 : f));
    }
  }
}

// Adds one offset's weights (times `factor`) into a ring's sums for each stream: sum w,
// sum w y_c, sum w^2 sigma^2_c, with y and sigma^2 read at q.
template <bool Two>
void accumulateRow(int n, float factor, const float* __restrict wA, const float* __restrict wB,
                   const float* __restrict yA0, const float* __restrict yA1,
                   const float* __restrict yA2, const float* __restrict yB0,
                   const float* __restrict yB1, const float* __restrict yB2,
                   const float* __restrict v0, const float* __restrict v1,
                   const float* __restrict v2, float* __restrict sA0, float* __restrict sA1,
                   float* __restrict sA2, float* __restrict sA3, float* __restrict sA4,
                   float* __restrict sA5, float* __restrict sA6, float* __restrict sB0,
                   float* __restrict sB1, float* __restrict sB2, float* __restrict sB3,
                   float* __restrict sB4, float* __restrict sB5, float* __restrict sB6) {
  for (int x = 0; x < n; ++x) {
    const float a = wA[x] * factor, a2 = a * a;
    sA0[x] += a;
    sA1[x] += a * yA0[x];
    sA2[x] += a * yA1[x];
    sA3[x] += a * yA2[x];
    sA4[x] += a2 * v0[x];
    sA5[x] += a2 * v1[x];
    sA6[x] += a2 * v2[x];
    if constexpr (Two) {
      const float b = wB[x] * factor, b2 = b * b;
      sB0[x] += b;
      sB1[x] += b * yB0[x];
      sB2[x] += b * yB1[x];
      sB3[x] += b * yB2[x];
      sB4[x] += b2 * v0[x];
      sB5[x] += b2 * v1[x];
      sB6[x] += b2 * v2[x];
    }
  }
}

}  // namespace penumbra::recon::detail
