#include "scene/texture_image.h"

#include "core/image_io.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace penumbra {

namespace {

// ---- building the pyramid -------------------------------------------------------------------

// Level sizes from width x height down to 1 x 1 (halved, rounded down), or level 0 alone.
std::vector<TextureImage::Level> levelSizes(int width, int height, int channels, bool mips) {
  std::vector<TextureImage::Level> levels;
  size_t offset = 0;
  for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
    levels.push_back({w, h, offset});
    offset += size_t(w) * size_t(h) * size_t(channels);
    if (!mips || (w == 1 && h == 1)) break;
  }
  return levels;
}

// The source texels a box of the next level covers along one axis, with their weights: texel
// i of `to` covers [i, i + 1) * from / to of `from`, each source texel weighted by its overlap,
// so the level's mean is the mean of the one above for any size (odd ones included).
struct Tap {
  int source;
  float weight;
};
std::vector<std::vector<Tap>> boxTaps(int from, int to) {
  std::vector<std::vector<Tap>> taps(static_cast<size_t>(to));
  const double scale = double(from) / double(to);
  for (int i = 0; i < to; ++i) {
    const double lo = i * scale, hi = (i + 1) * scale;
    for (int k = int(std::floor(lo)); k < std::min(from, int(std::ceil(hi))); ++k) {
      const double overlap = std::min(hi, double(k + 1)) - std::max(lo, double(k));
      if (overlap > 0) taps[size_t(i)].push_back({k, float(overlap / scale)});
    }
  }
  return taps;
}

// The next level (w2 x h2) of a w x h level read through fetch(x, y, channel) as linear values.
template <typename Fetch>
std::vector<float> downsample(int w, int h, int channels, int w2, int h2, Fetch fetch) {
  const auto tapsX = boxTaps(w, w2), tapsY = boxTaps(h, h2);
  std::vector<float> out(size_t(w2) * size_t(h2) * size_t(channels), 0.0f);
  for (int y = 0; y < h2; ++y)
    for (int x = 0; x < w2; ++x)
      for (int c = 0; c < channels; ++c) {
        float sum = 0;
        for (const Tap& ty : tapsY[size_t(y)])
          for (const Tap& tx : tapsX[size_t(x)])
            sum += ty.weight * tx.weight * fetch(tx.source, ty.source, c);
        out[(size_t(y) * size_t(w2) + size_t(x)) * size_t(channels) + size_t(c)] = sum;
      }
  return out;
}

uint8_t encode8(float v, TexelEncoding encoding) {
  if (encoding == TexelEncoding::Srgb8) return linearToSrgb8(v);
  return uint8_t(std::lround(255.0f * std::clamp(v, 0.0f, 1.0f)));
}

// v / 255 for every byte (a table, so that it costs what the sRGB table costs and gives the
// bits of the division).
const std::array<float, 256> kLinear8 = [] {
  std::array<float, 256> table{};
  for (int i = 0; i < 256; ++i) table[size_t(i)] = float(i) / 255.0f;
  return table;
}();

float decode8(uint8_t v, TexelEncoding encoding) {
  return encoding == TexelEncoding::Srgb8 ? srgb8ToLinear(v) : kLinear8[v];
}

// Fills levels 1 and up of `values` (level 0 in place, the vector sized for all of them):
// each level is averaged from the float values of the one above (level 0 decoded as it is
// read), then stored in the image's encoding; only one float level is held at a time.
template <typename Value, typename Decode, typename Encode>
void buildMips(const std::vector<TextureImage::Level>& levels, int channels,
               std::vector<Value>& values, Decode decode, Encode encode) {
  std::vector<float> above;
  for (size_t l = 1; l < levels.size(); ++l) {
    const TextureImage::Level& from = levels[l - 1];
    const TextureImage::Level& to = levels[l];
    const auto index = [&](int x, int y, int c) {
      return (size_t(y) * size_t(from.width) + size_t(x)) * size_t(channels) + size_t(c);
    };
    std::vector<float> level =
        l == 1 ? downsample(from.width, from.height, channels, to.width, to.height,
                            [&](int x, int y, int c) { return decode(values[index(x, y, c)]); })
               : downsample(from.width, from.height, channels, to.width, to.height,
                            [&](int x, int y, int c) { return above[index(x, y, c)]; });
    for (size_t i = 0; i < level.size(); ++i) values[to.offset + i] = encode(level[i]);
    above = std::move(level);
  }
}

void checkSize(int width, int height, int channels, size_t count) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
      count != size_t(width) * size_t(height) * size_t(channels))
    throw std::invalid_argument("texture image: " + std::to_string(count) + " values for " +
                                std::to_string(width) + "x" + std::to_string(height) + "x" +
                                std::to_string(channels));
}

// ---- lookups --------------------------------------------------------------------------------

// i modulo n in [0, n), by a compare for i in [-1, n) (bilinear's first texel of a repeating
// axis) and by divisions otherwise; the same index either way.
inline int wrapIndex(int i, int n) {
  if (i >= 0 && i < n) return i;
  if (i == -1) return n - 1;
  return ((i % n) + n) % n;
}

// Bilinear at one level through texel(index of the texel's first value) -> linear RGB.
template <typename Texel>
vec3 bilinear(const TextureImage::Level& level, int channels, glm::vec2 uv, Texel texel) {
  const int w = level.width, h = level.height;
  const float x = (uv.x - std::floor(uv.x)) * float(w) - 0.5f;
  const float y = (1.0f - (uv.y - std::floor(uv.y))) * float(h) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  // The four texels wrap. The fraction of uv puts the first texel at -1 .. n - 1, so a compare
  // finds it; the divisions are left for what is not finite.
  const int x0 = wrapIndex(int(fx), w), y0 = wrapIndex(int(fy), h);
  const int x1 = x0 + 1 == w ? 0 : x0 + 1, y1 = y0 + 1 == h ? 0 : y0 + 1;
  const size_t row0 = level.offset + size_t(y0) * size_t(w) * size_t(channels);
  const size_t row1 = level.offset + size_t(y1) * size_t(w) * size_t(channels);
  const size_t c0 = size_t(x0) * size_t(channels), c1 = size_t(x1) * size_t(channels);
  return (1 - ty) * ((1 - tx) * texel(row0 + c0) + tx * texel(row0 + c1)) +
         ty * ((1 - tx) * texel(row1 + c0) + tx * texel(row1 + c1));
}

// The two texels, along one axis of n texels, that a bilinear lookup at texel coordinate x
// (texel centres at i + 0.5) blends, and the weight of the second: Repeat wraps round as
// bilinear's own path does (x already taken from the fraction of uv), ClampToEdge extends the
// edge texels, MirroredRepeat reads the image backwards every other period.
void wrappedPair(TextureWrap wrap, float x, int n, int& i0, int& i1, float& t) {
  const float f = std::floor(x);
  t = x - f;
  if (wrap == TextureWrap::Repeat) {
    i0 = wrapIndex(int(f), n);
    i1 = i0 + 1 == n ? 0 : i0 + 1;
    return;
  }
  // Far outside the image every texel is an edge texel (clamp) or the period repeats: bound
  // the coordinate before it becomes an int.
  const float period = 2.0f * float(n);
  float bounded = wrap == TextureWrap::ClampToEdge ? (!(f >= -1.0f) ? -1.0f : std::min(f, float(n)))
                                                   : f - period * std::floor(f / period);
  if (!(bounded >= -1.0f && bounded <= period)) bounded = 0.0f;  // not finite
  const int a = int(bounded), b = a + 1;
  if (wrap == TextureWrap::ClampToEdge) {
    i0 = std::clamp(a, 0, n - 1);
    i1 = std::clamp(b, 0, n - 1);
    return;
  }
  const int twice = 2 * n;
  const auto mirror = [n, twice](int i) {
    i = ((i % twice) + twice) % twice;
    return i < n ? i : twice - 1 - i;
  };
  i0 = mirror(a);
  i1 = mirror(b);
}

// Bilinear at one level under wrap modes that are not both Repeat; the nearest texel (the
// pair's nearer one along each axis) with wrap.nearest.
template <typename Texel>
vec3 bilinearWrapped(const TextureImage::Level& level, int channels, glm::vec2 uv,
                     TextureWrapModes wrap, Texel texel) {
  const int w = level.width, h = level.height;
  // Repeat along one axis takes the same coordinates as bilinear's.
  const float x = wrap.u == TextureWrap::Repeat ? (uv.x - std::floor(uv.x)) * float(w) - 0.5f
                                                : uv.x * float(w) - 0.5f;
  const float y = wrap.v == TextureWrap::Repeat
                      ? (1.0f - (uv.y - std::floor(uv.y))) * float(h) - 0.5f
                      : (1.0f - uv.y) * float(h) - 0.5f;
  int x0, x1, y0, y1;
  float tx, ty;
  wrappedPair(wrap.u, x, w, x0, x1, tx);
  wrappedPair(wrap.v, y, h, y0, y1, ty);
  if (wrap.nearest)
    return texel(level.offset +
                 (size_t(ty < 0.5f ? y0 : y1) * size_t(w) + size_t(tx < 0.5f ? x0 : x1)) *
                     size_t(channels));
  const size_t row0 = level.offset + size_t(y0) * size_t(w) * size_t(channels);
  const size_t row1 = level.offset + size_t(y1) * size_t(w) * size_t(channels);
  const size_t c0 = size_t(x0) * size_t(channels), c1 = size_t(x1) * size_t(channels);
  return (1 - ty) * ((1 - tx) * texel(row0 + c0) + tx * texel(row0 + c1)) +
         ty * ((1 - tx) * texel(row1 + c0) + tx * texel(row1 + c1));
}

// Calls f with the function that reads a texel of `image` as linear RGB.
template <typename F>
vec3 withTexelReader(const TextureImage& image, F f) {
  const bool grey = image.channels == 1;
  switch (image.encoding) {
    case TexelEncoding::Srgb8: {
      const uint8_t* v = image.bytes->data();
      if (grey) return f([v](size_t i) { return vec3(srgb8ToLinear(v[i])); });
      return f([v](size_t i) {
        return vec3(srgb8ToLinear(v[i]), srgb8ToLinear(v[i + 1]), srgb8ToLinear(v[i + 2]));
      });
    }
    case TexelEncoding::Linear8: {
      const uint8_t* v = image.bytes->data();
      const float* k = kLinear8.data();
      if (grey) return f([v, k](size_t i) { return vec3(k[v[i]]); });
      return f([v, k](size_t i) { return vec3(k[v[i]], k[v[i + 1]], k[v[i + 2]]); });
    }
    case TexelEncoding::Float: {
      const float* v = image.floats->data();
      if (grey) return f([v](size_t i) { return vec3(v[i]); });
      return f([v](size_t i) { return vec3(v[i], v[i + 1], v[i + 2]); });
    }
  }
  return vec3(0.0f);
}

}  // namespace

size_t TextureImage::byteSize() const {
  return (bytes ? bytes->size() : 0) + (floats ? floats->size() * sizeof(float) : 0);
}

size_t textureValueCount(int width, int height, int channels, bool mips) {
  const std::vector<TextureImage::Level> levels = levelSizes(width, height, channels, mips);
  return levels.back().offset +
         size_t(levels.back().width) * size_t(levels.back().height) * size_t(channels);
}

TextureImage withoutFinestLevel(const TextureImage& image) {
  if (image.levels.size() < 2)
    throw std::invalid_argument("texture image: no coarser level to fall back to");
  TextureImage out;
  out.encoding = image.encoding;
  out.channels = image.channels;
  const size_t start = image.levels[1].offset;
  out.levels.assign(image.levels.begin() + 1, image.levels.end());
  for (TextureImage::Level& l : out.levels) l.offset -= start;
  if (image.bytes)
    out.bytes = std::make_shared<const std::vector<uint8_t>>(
        image.bytes->begin() + std::ptrdiff_t(start), image.bytes->end());
  if (image.floats)
    out.floats = std::make_shared<const std::vector<float>>(
        image.floats->begin() + std::ptrdiff_t(start), image.floats->end());
  return out;
}

int fitTexturesToBudget(std::vector<TextureImage>& images, size_t budgetBytes) {
  size_t total = 0;
  for (const TextureImage& image : images) total += image.byteSize();
  int dropped = 0;
  while (total > budgetBytes) {
    TextureImage* largest = nullptr;
    for (TextureImage& image : images)
      if (image.levels.size() > 1 && (!largest || image.byteSize() > largest->byteSize()))
        largest = &image;
    if (!largest) break;
    const size_t before = largest->byteSize();
    *largest = withoutFinestLevel(*largest);
    total -= before - largest->byteSize();
    ++dropped;
  }
  return dropped;
}

std::string textureBudgetWarning(size_t beforeBytes, size_t budgetBytes, size_t afterBytes,
                                 int dropped) {
  const auto megabytes = [](size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, bytes >= 10000000 ? "%.0f MB" : "%.2f MB",
                  double(bytes) / 1e6);
    return std::string(text);
  };
  return "the image textures take " + megabytes(beforeBytes) + ", over the texture budget of " +
         megabytes(budgetBytes) + ": the largest were halved " +
         (dropped == 1 ? std::string("once") : std::to_string(dropped) + " times") +
         " (a mip level each), leaving " + megabytes(afterBytes) +
         " (--texture-budget MB changes the budget)";
}

TextureImage makeTextureImage8(int width, int height, int channels, std::vector<uint8_t> texels,
                               TexelEncoding encoding, bool mips) {
  checkSize(width, height, channels, texels.size());
  if (encoding == TexelEncoding::Float)
    throw std::invalid_argument("texture image: 8-bit texels cannot be Float");
  TextureImage image;
  image.encoding = encoding;
  image.channels = channels;
  image.levels = levelSizes(width, height, channels, mips);
  const TextureImage::Level& last = image.levels.back();
  texels.resize(last.offset + size_t(last.width) * size_t(last.height) * size_t(channels));
  buildMips(
      image.levels, channels, texels, [encoding](uint8_t v) { return decode8(v, encoding); },
      [encoding](float v) { return encode8(v, encoding); });
  image.bytes = std::make_shared<const std::vector<uint8_t>>(std::move(texels));
  return image;
}

TextureImage makeTextureImageFloat(int width, int height, int channels, std::vector<float> texels,
                                   bool mips) {
  checkSize(width, height, channels, texels.size());
  TextureImage image;
  image.encoding = TexelEncoding::Float;
  image.channels = channels;
  image.levels = levelSizes(width, height, channels, mips);
  const TextureImage::Level& last = image.levels.back();
  texels.resize(last.offset + size_t(last.width) * size_t(last.height) * size_t(channels));
  buildMips(
      image.levels, channels, texels, [](float v) { return v; }, [](float v) { return v; });
  image.floats = std::make_shared<const std::vector<float>>(std::move(texels));
  return image;
}

TextureImage makeTextureImage(const Image& image, bool mips) {
  std::vector<float> texels;
  texels.reserve(image.pixels.size() * 3);
  for (const vec3& c : image.pixels) texels.insert(texels.end(), {c.x, c.y, c.z});
  return makeTextureImageFloat(image.width, image.height, 3, std::move(texels), mips);
}

TextureImage readTextureImage(const std::string& path) {
  if (std::optional<Image8> raw = readImage8(path))
    return makeTextureImage8(raw->width, raw->height, raw->channels, std::move(raw->data),
                             TexelEncoding::Srgb8);
  return makeTextureImage(readImage(path));
}

vec3 textureTexel(const TextureImage& image, int level, int x, int y) {
  const TextureImage::Level& l = image.levels[size_t(level)];
  x = ((x % l.width) + l.width) % l.width;
  y = ((y % l.height) + l.height) % l.height;
  const size_t index =
      l.offset + (size_t(y) * size_t(l.width) + size_t(x)) * size_t(image.channels);
  return withTexelReader(image, [index](auto texel) { return texel(index); });
}

vec3 sampleTextureLevel(const TextureImage& image, int level, glm::vec2 uv, TextureWrapModes wrap) {
  const TextureImage::Level& l = image.levels[size_t(level)];
  if (!wrap.repeats() || wrap.nearest)
    return withTexelReader(
        image, [&](auto texel) { return bilinearWrapped(l, image.channels, uv, wrap, texel); });
  return withTexelReader(image, [&](auto texel) { return bilinear(l, image.channels, uv, texel); });
}

float textureMipLevel(const TextureImage& image, glm::vec2 dx, glm::vec2 dy) {
  const glm::vec2 size(float(image.width()), float(image.height()));
  const float footprint = std::max(glm::length(dx * size), glm::length(dy * size));
  if (!(footprint > 1.0f)) return 0.0f;  // finer than a texel of level 0 (or NaN)
  return std::min(std::log2(footprint), float(image.levels.size() - 1));
}

vec3 sampleTexture(const TextureImage& image, glm::vec2 uv, glm::vec2 dx, glm::vec2 dy,
                   TextureWrapModes wrap) {
  const float level = textureMipLevel(image, dx, dy);
  if (level <= 0.0f) return sampleTextureLevel(image, 0, uv, wrap);  // magnified
  wrap.nearest = false;
  const int fine = int(level);
  if (fine + 1 >= int(image.levels.size())) return sampleTextureLevel(image, fine, uv, wrap);
  const float t = level - float(fine);
  return (1 - t) * sampleTextureLevel(image, fine, uv, wrap) +
         t * sampleTextureLevel(image, fine + 1, uv, wrap);
}

float imageMeanLuminance(const TextureImage& image, vec3 factor) {
  if (image.empty()) return 0.0f;
  const int w = image.width(), h = image.height();
  double sum = 0;
  withTexelReader(image, [&](auto texel) {
    for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
      sum += double(luminance(factor * texel(i * size_t(image.channels))));
    return vec3(0.0f);
  });
  return float(sum / (double(w) * double(h)));
}

}  // namespace penumbra
