// The fuzzy-uncertainty baseline: our re-implementation of Xu et al. 2008 (ALGORITHM.md
// §10.3, [A22]) on the shared allocation framework (allocation.h). A pixel's score is the
// De Luca-Termini entropy of its min-max normalised sample luminances (a reservoir of them),
// times their contrast, times mean / sqrt(N).
#pragma once

#include "methods/allocation.h"

#include <memory>
#include <span>

namespace penumbra {

struct FuzzyConfig : AllocationConfig {
  int reservoir = 1024;  // luminances kept per pixel for the fuzzy entropy
};

// The parameters of FuzzyConfig, for the command line, the panel, the stats and compare.
const ParamTable<FuzzyConfig>& fuzzyParams();
// The method\'s descriptor (methods/method.h).
const MethodDescriptor& fuzzyMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeFuzzyMethod(const PreparedScene& prepared,
                                                   const RunShape& shape,
                                                   const FuzzyConfig& config);

namespace adaptive {

// The stand-in fuzzy uncertainty of §10.3 on a pixel's luminances: De Luca-Termini
// entropy of the min-max normalised values, times the contrast (max-min)/(max+min+eps),
// times mean / sqrt(N). `values` may be a subsample of the pixel's n samples (their
// exact min, max and mean are passed separately); 0 when the range < 1e-4 x mean.
double fuzzyScore(std::span<const float> values, double minimum, double maximum, double mean,
                  uint32_t n);

}  // namespace adaptive

}  // namespace penumbra
