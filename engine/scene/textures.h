// Texture evaluation: constant, image (bilinear, repeating), checker and stripes in uv.
#pragma once

#include "scene/scene.h"

namespace penumbra {

vec3 evalTexture(const Scene& scene, const Texture& texture, vec2 uv);
// An image at uv, bilinear and repeating; uv (0,0) is its bottom-left corner.
vec3 sampleImageBilinear(const Image& image, vec2 uv);

}  // namespace penumbra
