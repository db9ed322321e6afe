// Texture evaluation: constant, image, checker and stripes in uv. Image textures are looked up
// over a footprint (texture_image.h: trilinear between mip levels) when the caller knows one:
// the uv derivatives across one pixel, from the camera's ray differentials
// (cameraRayDifferentials) at a path's first hit; other lookups use level 0. Checker and
// stripes are point-sampled.
#pragma once

#include "scene/scene.h"

#include <glm/vec2.hpp>

#include <cstddef>

namespace penumbra {

// The change of uv across one pixel of the image, in x and in y: zero, the finest level.
struct UvFootprint {
  glm::vec2 dx = glm::vec2(0.0f), dy = glm::vec2(0.0f);
};

vec3 evalTexture(const Scene& scene, const Texture& texture, glm::vec2 uv,
                 const UvFootprint& footprint = {});
// An image at uv, bilinear at level 0, wrapping as `wrap` says (repeating by default); uv (0,0)
// is its bottom-left corner.
vec3 sampleImageBilinear(const TextureImage& image, glm::vec2 uv, TextureWrapModes wrap = {});
// The uv an image texture is read at, for a surface's uv: its uv transform applied.
glm::vec2 textureUv(const Texture& texture, glm::vec2 uv);
// The mean luminance of a texture over its uv square (the mean of two colours for checker and
// stripes), its factor applied.
float textureMeanLuminance(const Scene& scene, const Texture& texture);
// Bytes of texels of every image of the scene, mip levels included.
size_t textureBytes(const Scene& scene);

// Where a hit's differential rays meet its tangent plane (through `point`, normal `normal`),
// as offsets from the point: pbrt's dp/dx and dp/dy. False when either ray runs parallel to
// the plane or misses it behind its origin.
bool differentialOffsets(const RayDifferentials& rays, vec3 point, vec3 normal, vec3& dpdx,
                         vec3& dpdy);
// The uv footprint of dp/dx and dp/dy on a surface with tangents dp/du and dp/dv, by least
// squares (the offsets need not lie in the tangents' plane); zero where the tangents are
// degenerate.
UvFootprint uvFootprint(vec3 dpdx, vec3 dpdy, vec3 dpdu, vec3 dpdv);

}  // namespace penumbra
