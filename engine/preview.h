// A first picture within milliseconds of a camera move: one path per block of
// block x block pixels, traced at the block's centre and drawn as a flat block. The viewer
// runs it as round 0 before the real method (chainMethods), so a restart shows something
// at once even when the method's first round (the BP coarse pass) takes a second.
#pragma once

#include "engine/integrator.h"
#include "engine/progressive.h"

#include <functional>
#include <memory>

namespace penumbra {

std::unique_ptr<ProgressiveMethod> makePreviewMethod(const PreparedScene& prepared, uint64_t seed,
                                                     int block);

// Runs `first` until it is done, then the method that `next` builds (on the worker thread,
// when first is done). Snapshots, inspection and done() come from whichever runs now.
std::unique_ptr<ProgressiveMethod> chainMethods(
    std::unique_ptr<ProgressiveMethod> first,
    std::function<std::unique_ptr<ProgressiveMethod>()> next);

}  // namespace penumbra
