// Blender Cycles' adaptive sampling (Dammertz et al. 2010; ALGORITHM.md §10.5) on the
// shared allocation framework (allocation.h): a pixel's error compares the mean of all its
// samples with the mean of the even-indexed half ("half buffer"), normalised by the pixel's
// brightness; unconverged regions are dilated by one pixel.
#pragma once

#include "methods/allocation.h"

#include <memory>

namespace penumbra {

struct CyclesConfig : AllocationConfig {
  bool dilate = true;  // Cycles dilates unconverged pixels by 1 px in x, then y
};

// The parameters of CyclesConfig, for the command line, the panel, the stats and compare.
const ParamTable<CyclesConfig>& cyclesParams();
// The method\'s descriptor (methods/method.h).
const MethodDescriptor& cyclesMethod();

// Throws std::invalid_argument on a bad configuration (factory.h's validate()); the scene must
// outlive the method.
std::unique_ptr<ProgressiveMethod> makeCyclesMethod(const PreparedScene& prepared,
                                                    const RunShape& shape,
                                                    const CyclesConfig& config);

namespace adaptive {

// Cycles' error of a pixel: sum_c |I_c - A_c| / (1e-4 + N(I)), I the mean of all samples,
// A twice the class-A (even index) samples' sum over all samples, N(I) = sqrt(sum I) when
// sum I < 1, else sum I.
double cyclesError(vec3 meanAll, vec3 meanHalf);

}  // namespace adaptive

}  // namespace penumbra
