// Where the next samples go when a reconstruction estimates each pixel's error
// (RECONSTRUCTION.md §5). A pixel's estimated error falls about as 1/n with its sample count,
// so e_p(n) = c_p / n with c_p = e_p n_p. Minimising sum_p c_p / (n_p + dn_p) over the
// round's budget gives the water-filling allocation n_p + dn_p = lambda sqrt(c_p) (a
// Lagrange multiplier), never taking samples away. A floor keeps every pixel's count at
// least `floorFraction` of the mean count, so every pixel keeps receiving samples and the
// estimate stays consistent; a pixel the noise threshold marks converged gets none.
// It ranks at every spp: there is no uniform pass.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

struct ErrorAllocation {
  float floorFraction = 0.25f;  // every pixel's count >= this x the mean count after the round
};

// Samples per pixel for the next round, summing to `budget` up to rounding (each pixel's
// real share is rounded by a deterministic coin from (seed, round, pixel)). `error`: the
// estimated (relative) error of each pixel now; `count`: its samples. A non-finite error
// counts as the largest finite one. `converged` (empty: none): the pixels that get nothing, one
// value per pixel (RunShape::converged says which, under a noise threshold).
std::vector<uint32_t> allocateByError(std::span<const float> error, std::span<const uint32_t> count,
                                      uint64_t budget, const ErrorAllocation& config, uint64_t seed,
                                      int round, std::span<const uint8_t> converged = {});

// The largest value in each pixel's 3x3 neighbourhood (clipped at the borders), as Cycles
// dilates its error map: a pixel whose own samples missed a rare bright contribution (the
// sliver of an emitter at its edge) looks converged, but its neighbour has seen it, so the
// pixel is not starved; without it the raw estimate fails the per-pixel z-test near lights.
std::vector<float> dilate3x3(std::span<const float> values, int width, int height);

}  // namespace penumbra
