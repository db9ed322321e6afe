#include "scene/textures.h"

#include <cmath>

namespace penumbra {

vec3 sampleImageBilinear(const Image& image, vec2 uv) {
  // uv (0,0) is the bottom-left corner of the image; rows are stored top first.
  const float x = (uv.x - std::floor(uv.x)) * image.width - 0.5f;
  const float y = (1.0f - (uv.y - std::floor(uv.y))) * image.height - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  auto texel = [&](int ix, int iy) {
    ix = ((ix % image.width) + image.width) % image.width;
    iy = ((iy % image.height) + image.height) % image.height;
    return image.at(ix, iy);
  };
  const int ix = int(fx), iy = int(fy);
  return (1 - ty) * ((1 - tx) * texel(ix, iy) + tx * texel(ix + 1, iy)) +
         ty * ((1 - tx) * texel(ix, iy + 1) + tx * texel(ix + 1, iy + 1));
}

vec3 evalTexture(const Scene& scene, const Texture& texture, vec2 uv) {
  switch (texture.kind) {
    case Texture::Kind::Constant:
      return texture.color0;
    case Texture::Kind::Image:
      return sampleImageBilinear(scene.images[size_t(texture.imageIndex)], uv);
    case Texture::Kind::Checker: {
      const int cx = int(std::floor(uv.x * texture.scale.x));
      const int cy = int(std::floor(uv.y * texture.scale.y));
      return ((cx + cy) & 1) ? texture.color1 : texture.color0;
    }
    case Texture::Kind::Stripes: {
      // Stripes across u; scale.x stripe pairs per unit u.
      const float f = uv.x * texture.scale.x;
      return (f - std::floor(f)) < 0.5f ? texture.color0 : texture.color1;
    }
  }
  return texture.color0;
}

}  // namespace penumbra
