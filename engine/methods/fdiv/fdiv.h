// The f-divergence baseline (Rigau, Feixas, Sbert 2003; ALGORITHM.md §10.2) on the shared
// allocation framework (allocation.h): a pixel's score is its mean luminance times the
// square root of the divergence of its samples' luminance distribution from uniform, over N
// (eq. 15's 1/N), with the Hellinger, Kullback-Leibler or chi-square divergence [A21].
#pragma once

#include "methods/allocation.h"

#include <memory>

namespace penumbra {

enum class Divergence { Hellinger, KullbackLeibler, ChiSquare };  // [A21]

struct FDivConfig : AllocationConfig {
  Divergence divergence = Divergence::Hellinger;
};

// The parameters of FDivConfig, for the command line, the panel, the stats and compare.
const ParamTable<FDivConfig>& fdivParams();
// The method\'s descriptor (methods/method.h).
const MethodDescriptor& fdivMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeFDivMethod(const PreparedScene& prepared,
                                                  const RunShape& shape, const FDivConfig& config);

namespace adaptive {

// The divergence of p_i = L_i / sum L from uniform q_i = 1/N: Hellinger
// 1/2 sum (sqrt p_i - sqrt(1/N))^2, Kullback-Leibler sum p_i ln(N p_i), chi-square
// N sum p_i^2 - 1. 0 when N < 2 or sum L = 0.
double divergence(const LuminanceSums& s, Divergence kind);
// Rigau's refinement score with eq. 15's 1/N: mean L x sqrt(divergence) / N.
double fDivergenceScore(const LuminanceSums& s, Divergence kind);

}  // namespace adaptive

}  // namespace penumbra
