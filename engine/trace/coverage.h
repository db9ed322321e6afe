// Where the scene covers the image: the alpha channel of a render whose environment is hidden
// from the camera (Scene::transparent). A pixel's alpha is the share of a fixed, stratified set
// of camera rays through it (positions, lens points and times on a 4 x 4 grid) that hit
// geometry, so it does not depend on the seed, the method or the thread count.
#pragma once

#include "trace/integrator.h"

#include <vector>

namespace penumbra {

// One value in [0, 1] per pixel, top row first. `raysPerSide` x `raysPerSide` rays per pixel.
std::vector<float> cameraCoverage(const PreparedScene& prepared, int raysPerSide = 4);

}  // namespace penumbra
