#include "scene/textures.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace penumbra {

vec3 sampleImageBilinear(const TextureImage& image, glm::vec2 uv, TextureWrapModes wrap) {
  return sampleTextureLevel(image, 0, uv, wrap);
}

glm::vec2 textureUv(const Texture& texture, glm::vec2 uv) {
  return texture.uvTransformed ? texture.uvLinear * uv + texture.uvOffset : uv;
}

vec3 evalTexture(const Scene& scene, const Texture& texture, glm::vec2 uv,
                 const UvFootprint& footprint) {
  switch (texture.kind) {
    case Texture::Kind::Constant:
      return texture.color0;
    case Texture::Kind::Image: {
      const TextureImage& image = scene.images[size_t(texture.imageIndex)];
      // The footprint's derivatives go through the uv map's linear part.
      const vec3 value =
          texture.factor *
          (texture.uvTransformed
               ? sampleTexture(image, textureUv(texture, uv), texture.uvLinear * footprint.dx,
                               texture.uvLinear * footprint.dy, texture.wrap)
               : sampleTexture(image, uv, footprint.dx, footprint.dy, texture.wrap));
      return texture.hasOffset ? texture.offset + value : value;
    }
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

float textureMeanLuminance(const Scene& scene, const Texture& texture) {
  if (texture.kind != Texture::Kind::Image)
    return luminance(0.5f * (texture.color0 + texture.color1));
  return imageMeanLuminance(scene.images[size_t(texture.imageIndex)], texture.factor);
}

size_t textureBytes(const Scene& scene) {
  size_t bytes = 0;
  for (const TextureImage& image : scene.images) bytes += image.byteSize();
  return bytes;
}

// ---- footprints (pbrt-v4's ray differentials) -------------------------------------------------

bool differentialOffsets(const RayDifferentials& rays, vec3 point, vec3 normal, vec3& dpdx,
                         vec3& dpdy) {
  // Each offset ray meets the plane dot(normal, p - point) = 0 at t = dot(normal, point - o) /
  // dot(normal, d).
  const auto meet = [&](vec3 origin, vec3 direction, vec3& offset) {
    const float t = glm::dot(normal, point - origin) / glm::dot(normal, direction);
    if (!(t >= 0.0f) || !std::isfinite(t)) return false;
    offset = origin + t * direction - point;
    return true;
  };
  return meet(rays.xOrigin, rays.xDirection, dpdx) && meet(rays.yOrigin, rays.yDirection, dpdy);
}

UvFootprint uvFootprint(vec3 dpdx, vec3 dpdy, vec3 dpdu, vec3 dpdv) {
  // Least squares: the normal equations of [dpdu dpdv] (du, dv) = dp, whose matrix is the
  // tangents' Gram matrix.
  const float a00 = glm::dot(dpdu, dpdu), a01 = glm::dot(dpdu, dpdv), a11 = glm::dot(dpdv, dpdv);
  const float det = a00 * a11 - a01 * a01;
  // Parallel or zero tangents (sin^2 of their angle tiny), or no uv at all: no footprint.
  if (!(det > 1e-8f * a00 * a11) || !std::isfinite(det)) return {};
  const auto solve = [&](vec3 dp) {
    const float bu = glm::dot(dpdu, dp), bv = glm::dot(dpdv, dp);
    const glm::vec2 duv((a11 * bu - a01 * bv) / det, (a00 * bv - a01 * bu) / det);
    return std::isfinite(duv.x) && std::isfinite(duv.y) ? duv : glm::vec2(0.0f);
  };
  return {solve(dpdx), solve(dpdy)};
}

}  // namespace penumbra
