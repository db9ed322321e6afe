// The plain low-discrepancy renderer as a progressive method, for the viewer and as the
// baseline the adaptive methods are compared with.
#pragma once

#include "methods/progressive.h"
#include "trace/integrator.h"
#include "trace/sampler.h"

#include <memory>

namespace penumbra {

// The plain low-discrepancy renderer as a progressive method: the coarse pass, then
// rounds adding samples to every pixel. Its final image equals renderImage's for the same
// seed and spp (box filter, per-pixel mean in sample order).
struct LdConfig {
  uint64_t seed = 0;
  int spp = 16;
  bool openEnded = false;
  int roundSpp = 1;  // samples per pixel per round after the first
  int maxSpp = 0;
  SamplerKind sampler = SamplerKind::LowDiscrepancy;
};
std::unique_ptr<ProgressiveMethod> makeLdMethod(const PreparedScene& prepared,
                                                const LdConfig& config);

}  // namespace penumbra
