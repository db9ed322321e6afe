// Training of the BP method's per-pixel networks (ALGORITHM.md §4): the networks of the
// given pixels are retrained together, one SIMD lane per pixel (network.h), on their stored
// samples: inputs from each sample's position, lens and time, targets its tone-mapped
// radiance (or the pixel's mean, the paper's literal reading).
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

namespace penumbra::bp {

struct BpState;

// Network input vector of a sample at centred offsets (dx, dy) with lens (u, v), time t.
void networkInputs(int inputs, float dx, float dy, float u, float v, float t, float* x);

// Retrains the networks of `pixels`. Returns false when cancelled (the state is then
// unusable).
bool trainNetworksOf(BpState& state, const std::vector<uint32_t>& pixels,
                     const std::atomic<bool>* cancel);

}  // namespace penumbra::bp
