// Numeric constants shared by the engine: one definition each, so that no two files disagree
// on a digit and a unity build sees no duplicates.
#pragma once

namespace penumbra {

inline constexpr double kPiD = 3.14159265358979323846;
inline constexpr float kPi = 3.14159265358979f;
inline constexpr float kTwoPi = 6.28318530717958648f;
inline constexpr float kInvPi = 0.31830988618f;

}  // namespace penumbra
