// The BP method's error estimate (ALGORITHM.md §5) and the ranking it drives (§8): each
// trained network's prediction I' at the pixel centre, averaged over K lens/time draws, is
// compared with the pixel's tone-mapped mean I (eq. 13, "bias"); pixels are then ranked
// for the next round's samples.
#pragma once

#include "core/image.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace penumbra {
struct BpPaperConfig;
}

namespace penumbra::bp {

struct BpState;

// eq. 13 with an L1 norm over RGB and the regulariser: sum|I' - I| / (sum I + eps); 0 if
// the pixel mean is exactly black [A13].
float biasOf(vec3 prediction, vec3 mean, float eps);

// The K (u, v, t) points used for I': a 3-D Halton sequence (bases 2, 3, 5) shifted by a
// per-pixel rotation, modulo 1; K = 1 gives one random point.
void predictionPoints(int count, uint64_t pixelKey, float* uvt);

// I', er and the bias of `pixels` from their freshly trained networks.
void estimateErrors(BpState& state, const std::vector<uint32_t>& pixels,
                    const std::atomic<bool>* cancel);

// Pixels in the order they get samples: the difficult ones (bias > Psi and er > e) by
// descending bias; then, with top-up, the other unconverged ones (er > e) by descending
// bias, and last the converged ones (er <= e) by descending er. Ties by pixel index.
// (The paper algorithm's.)
std::vector<uint32_t> rankPixels(const BpState& state, const BpPaperConfig& config);

}  // namespace penumbra::bp
