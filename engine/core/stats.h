// Order statistics of per-pixel values, shared by the maps' colour scales, the report and the
// viewer's frame timing. Non-finite values are left out.
#pragma once

#include <optional>
#include <span>

namespace penumbra {

// The value at rank floor(q n) of the n finite values in ascending order (the value below
// which a fraction q lies); nothing when no value is finite.
std::optional<float> lowerQuantile(std::span<const float> values, double q);
// The value at rank round(q (n - 1)), the nearest-rank q-quantile; nothing when no value is
// finite.
std::optional<float> nearestRankQuantile(std::span<const float> values, float q);

}  // namespace penumbra
