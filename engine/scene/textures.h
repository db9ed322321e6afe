// Texture evaluation: constant, image (bilinear, repeating), checker and stripes in uv.
#pragma once

#include "scene/scene.h"

namespace penumbra {

vec3 evalTexture(const Scene& scene, const Texture& texture, vec2 uv);

}  // namespace penumbra
