// A first picture within milliseconds of a camera move: one path per block of
// block x block pixels, traced at the block's centre and drawn as a flat block. The viewer
// draws it on its own thread the moment the camera moves, so a restart shows the new view
// at once, whatever the render threads are busy with (a BP coarse pass takes a second at
// 512x512, and in the window they run at a lower priority than the UI).
#pragma once

#include "core/image.h"
#include "trace/integrator.h"

#include <cstdint>

namespace penumbra {

// The preview image at the scene's resolution, traced on the calling thread only. A path
// that fails numerically leaves its block black.
Image renderPreview(const PreparedScene& prepared, uint64_t seed, int block);

}  // namespace penumbra
