// The BP method's sampling of one round (ALGORITHM.md §6-§7): how many samples each ranked
// pixel gets, the order in which its slices receive them (with the less complex slice B's
// sample warped into the more complex C), and the candidates among which each kept sample
// is chosen: traced and scored by eq. 16, or scored by the network's prediction and then
// traced and tested for outliers.
#pragma once

#include "methods/bp/slices.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {
struct BpPaperConfig;
}

namespace penumbra::bp {

struct BpState;

// Kept samples each pixel gets this round: S^2 per selected pixel, pixels in `order`
// (highest priority first), several passes when the budget exceeds one pass, the last
// pixel getting the remainder. Sums exactly to min(budget, ...) = budget when order is
// non-empty.
std::vector<uint32_t> allocateSlots(std::span<const uint32_t> order, size_t pixelCount,
                                    uint64_t budget, int slotsPerPixel);

// Adds `slotCount` samples to pixel p in the slices `choice` names; returns the budget they
// used (kept samples plus slots lost to non-finite values; outlier rejections use none).
// Non-finite samples are counted in `nonFinite`. For one pixel, called by one thread.
uint64_t samplePixel(BpState& state, const BpPaperConfig& config, uint32_t p, uint32_t slotCount,
                     const SliceChoice& choice, PixelSampler& sampler, PathCounters& counters,
                     uint64_t& nonFinite);

}  // namespace penumbra::bp
