// BP's consistent algorithm (consistent.cpp says what it does); makeBpMethod (method.h)
// builds it when BpConfig::algorithm is Consistent.
#pragma once

#include "methods/bp/config.h"
#include "methods/progressive.h"
#include "methods/run_shape.h"
#include "trace/integrator.h"

#include <memory>

namespace penumbra::bp {

std::unique_ptr<ProgressiveMethod> makeConsistentMethod(const PreparedScene& prepared,
                                                        const RunShape& shape,
                                                        const BpConfig& config);

}  // namespace penumbra::bp
