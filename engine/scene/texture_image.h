// The texels of an image texture, kept at their own bit depth, with a box-filtered mip pyramid.
// 8-bit files stay 8-bit: colour (base colour, emission) as sRGB bytes, decoded at lookup
// through a 256-entry table; data (normal maps, metallic-roughness, coverage) as bytes read as
// v / 255. HDR sources (EXR, Radiance HDR, PFM, 16-bit PNG) stay float. Only the channels a
// texture uses are stored: one (grey or coverage) or three (RGB). Each mip level is the one
// above it averaged over boxes (in linear values, then stored in the level 0 encoding), down
// to 1x1; lookups are bilinear at a level, or trilinear between the two levels around a
// pixel footprint. Copies share the texels, which never change once built.
#pragma once

#include "core/image.h"

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

// How a texture image's texels are stored and turned into linear values at lookup.
enum class TexelEncoding {
  Srgb8,    // 8-bit sRGB-encoded colour, decoded through srgb8ToLinear's table
  Linear8,  // 8-bit data, v / 255
  Float,    // 32-bit float, linear as it is
};

struct TextureImage {
  struct Level {
    int width = 0, height = 0;
    size_t offset = 0;  // index of the level's first value in `bytes` or `floats`
  };
  TexelEncoding encoding = TexelEncoding::Float;
  int channels = 3;           // 1: one value, read as (v, v, v); 3: RGB
  std::vector<Level> levels;  // [0] the image; each next one half the size (rounded down)
  std::shared_ptr<const std::vector<uint8_t>> bytes;  // Srgb8 and Linear8: every level
  std::shared_ptr<const std::vector<float>> floats;   // Float: every level

  int width() const { return levels.empty() ? 0 : levels[0].width; }
  int height() const { return levels.empty() ? 0 : levels[0].height; }
  bool empty() const { return levels.empty(); }
  // Bytes of texels over every level.
  size_t byteSize() const;
};

// How many values an image of width x height with `channels` holds with its mip levels (or
// level 0 alone): a vector of texels reserved to it is not reallocated when the levels are
// added.
size_t textureValueCount(int width, int height, int channels, bool mips = true);

// An 8-bit image (`encoding` Srgb8 or Linear8): `texels` holds width x height pixels of
// `channels` (1 or 3) values each, top row first. With `mips`, the pyramid down to 1x1 is
// built (what a lookup with a footprint needs); without, only level 0 (a cut-out's coverage).
// Throws std::invalid_argument on sizes that do not match.
TextureImage makeTextureImage8(int width, int height, int channels, std::vector<uint8_t> texels,
                               TexelEncoding encoding, bool mips = true);
// A float image of `channels` (1 or 3) linear values per pixel, top row first.
TextureImage makeTextureImageFloat(int width, int height, int channels, std::vector<float> texels,
                                   bool mips = true);
// A linear RGB image as a float texture.
TextureImage makeTextureImage(const Image& image, bool mips = true);
// An image file as a colour texture: 8-bit files (PNG, JPEG, TGA, BMP) stay 8-bit sRGB, grey
// ones with one channel; the others are read by readImage as float RGB. Alpha is dropped.
// Throws ImageIoError as readImage does.
TextureImage readTextureImage(const std::string& path);

// How a lookup reaches the image outside uv [0, 1), per axis: glTF's sampler wrap modes (and
// OpenGL's): the image repeats, its edge texels extend, or it repeats mirrored every other time.
enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
// A sampler: the wrap modes, and whether a magnified lookup (a footprint finer than a texel of
// level 0) reads the nearest texel instead of blending four (glTF's magFilter NEAREST: pixel
// art stays blocky). Minified lookups are trilinear either way.
struct TextureWrapModes {
  TextureWrap u = TextureWrap::Repeat, v = TextureWrap::Repeat;
  bool nearest = false;
  bool repeats() const { return u == TextureWrap::Repeat && v == TextureWrap::Repeat; }
  bool operator==(const TextureWrapModes&) const = default;
};

// The texel (x, y) of `level` in linear values (x and y wrap around).
vec3 textureTexel(const TextureImage& image, int level, int x, int y);
// Bilinear at one level (the nearest texel with wrap.nearest), wrapping as `wrap` says
// (repeating by default); uv (0,0) is the image's bottom-left corner.
vec3 sampleTextureLevel(const TextureImage& image, int level, glm::vec2 uv,
                        TextureWrapModes wrap = {});
// The mip level whose texels match a footprint of one pixel with uv derivatives dx and dy:
// log2 of the footprint's longer side (|duv/dx| or |duv/dy|) in texels of level 0, clamped to
// [0, coarsest]. A zero or non-finite footprint gives 0.
float textureMipLevel(const TextureImage& image, glm::vec2 dx, glm::vec2 dy);
// The image over a pixel's footprint: trilinear between the two levels around
// textureMipLevel (bilinear at level 0 for a zero footprint or one finer than a texel, or the
// nearest texel there with wrap.nearest).
vec3 sampleTexture(const TextureImage& image, glm::vec2 uv, glm::vec2 dx, glm::vec2 dy,
                   TextureWrapModes wrap = {});
// The image from its second level down: half the size, a quarter of the texels. The image
// must have more than one level.
TextureImage withoutFinestLevel(const TextureImage& image);
// Drops the finest level of the largest images, one level at a time (largest first, ties by
// index), until all of them take at most `budgetBytes` or none has a coarser level to fall
// back to. Returns how many levels were dropped. A lookup with a footprint reads the same
// coarser levels as before; only one magnified past the new level 0 sees fewer texels.
int fitTexturesToBudget(std::vector<TextureImage>& images, size_t budgetBytes);
// What a budget did, for a warning: "the image textures take 1342 MB, over the texture budget
// of 384 MB: the largest were halved 5 times (a mip level each), leaving 335 MB (...)".
std::string textureBudgetWarning(size_t beforeBytes, size_t budgetBytes, size_t afterBytes,
                                 int dropped);

// The mean luminance of `factor` times each texel of level 0 (0 for an empty image).
float imageMeanLuminance(const TextureImage& image, vec3 factor);

}  // namespace penumbra
