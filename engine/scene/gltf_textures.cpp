#include "scene/gltf_textures.h"

#include "scene/gltf_accessors.h"

#include "core/image_io.h"
#include "core/image_webp.h"

#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace penumbra::gltf {

namespace {

bool hasMagic(const unsigned char* bytes, size_t size, size_t at, const char* magic) {
  const size_t length = std::strlen(magic);
  return size >= at + length && std::memcmp(bytes + at, magic, length) == 0;
}

// The format of an extension's image that is not read ("KTX2", "AVIF") by its contents or its
// MIME type; null for any other.
const char* extensionFormat(const unsigned char* bytes, size_t size, const std::string& mime) {
  if (hasMagic(bytes, size, 0, "\xabKTX 20\xbb") || mime == "image/ktx2") return "KTX2";
  if (hasMagic(bytes, size, 4, "ftypavi") || mime == "image/avif") return "AVIF";
  return nullptr;
}

}  // namespace

bool loadGltfImage(tinygltf::Image* image, int index, std::string* err, std::string*, int, int,
                   const unsigned char* bytes, int size, void* user) {
  const size_t length = size > 0 ? size_t(size) : 0;
  if (const char* format = extensionFormat(bytes, length, image->mimeType)) {
    (*static_cast<ImagesNotRead*>(user))[index] = format;
    return true;
  }
  try {
    // Checked now, decoded when converted (imageFromGltf): one decoded image at a time.
    const std::string name = indexed("images", size_t(std::max(index, 0)));
    const DecodedImage header = isWebp(bytes, length) ? inspectWebp(name, bytes, length)
                                                      : inspectPngOrJpeg(name, bytes, length);
    image->width = header.width;
    image->height = header.height;
    image->component = header.channels;
    image->bits = header.bits;
    image->pixel_type = header.bits == 16 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                          : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.assign(bytes, bytes + length);
    image->as_is = true;  // the file's bytes, not texels
    return true;
  } catch (const ImageIoError& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

TextureImage imageFromGltf(const std::string& path, const tinygltf::Image& source, size_t index,
                           Texels texels) {
  const std::string where = indexed("images", index);
  // loadGltfImage keeps the file's bytes: decoded here, with the checks it made.
  DecodedImage decoded;
  if (source.as_is) {
    try {
      const unsigned char* bytes = source.image.data();
      const size_t size = source.image.size();
      decoded = isWebp(bytes, size) ? decodeWebp(where, bytes, size)
                                    : decodePngOrJpeg(where, bytes, size);
    } catch (const ImageIoError& e) {
      fail(path, "", e.what());
    }
  } else {
    decoded.width = source.width;
    decoded.height = source.height;
    decoded.channels = source.component;
    decoded.bits = source.bits;
    decoded.data = source.image;
  }
  const std::vector<uint8_t>& texelBytes = decoded.data;
  const int w = decoded.width, h = decoded.height, n = decoded.channels;
  const size_t bytesPer = decoded.bits == 16 ? 2 : 1;
  if (w <= 0 || h <= 0 || n < 1 || n > 4 || (decoded.bits != 8 && decoded.bits != 16) ||
      texelBytes.size() != size_t(w) * size_t(h) * size_t(n) * bytesPer)
    fail(path, where,
         (source.uri.empty() || source.uri.rfind("data:", 0) == 0 ? std::string("its data")
                                                                  : "'" + source.uri + "'") +
             " could not be read or decoded as an image");
  // The channels kept: alpha alone for coverage (none without one), grey or RGB otherwise.
  if (texels == Texels::Alpha && n != 2 && n != 4) return {};
  const int first = texels == Texels::Alpha ? n - 1 : 0;
  const size_t channels = texels == Texels::Alpha || n < 3 ? 1 : 3;
  const size_t count = size_t(w) * size_t(h) * channels;
  // Shading lookups read the mip levels; coverage is tested at level 0 alone (by the
  // acceleration structure's filter), so it has none. Room for the levels is made now, so
  // that adding them does not copy level 0.
  const bool mips = texels != Texels::Alpha;
  const size_t withLevels = textureValueCount(w, h, int(channels), mips);
  std::vector<uint8_t> bytes;
  std::vector<float> values;
  if (bytesPer == 1) {
    bytes.reserve(withLevels);
    bytes.resize(count);
  } else {
    values.reserve(withLevels);
    values.resize(count);
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t at = ((i / channels) * size_t(n) + size_t(first) + i % channels) * bytesPer;
    if (bytesPer == 1) {
      bytes[i] = texelBytes[at];
    } else {
      const float v = float(texelBytes[at] | texelBytes[at + 1] << 8) / 65535.0f;
      values[i] = texels == Texels::Color ? srgbToLinear(v) : v;
    }
  }
  decoded = DecodedImage{};  // before the levels are built
  if (bytesPer == 2) return makeTextureImageFloat(w, h, int(channels), std::move(values), mips);
  return makeTextureImage8(w, h, int(channels), std::move(bytes),
                           texels == Texels::Color ? TexelEncoding::Srgb8 : TexelEncoding::Linear8,
                           mips);
}

TextureWrap wrapMode(const std::string& path, int mode, const std::string& where) {
  switch (mode) {
    case -1:
    case 10497:
      return TextureWrap::Repeat;
    case 33071:
      return TextureWrap::ClampToEdge;
    case 33648:
      return TextureWrap::MirroredRepeat;
    default:
      fail(path, where,
           "wrap mode " + std::to_string(mode) +
               " is not REPEAT (10497), CLAMP_TO_EDGE (33071) or "
               "MIRRORED_REPEAT (33648)");
  }
}

void textureTransform(const std::string& path, const tinygltf::ExtensionMap& extensions,
                      const std::string& where, Texture& t, int& texCoord) {
  const auto it = extensions.find("KHR_texture_transform");
  if (it == extensions.end() || !it->second.IsObject()) return;
  const tinygltf::Value& e = it->second;
  const std::string at = where + ".extensions.KHR_texture_transform";
  auto pair = [&](const char* key, double fallback) {
    glm::dvec2 v(fallback);
    if (!e.Has(key)) return v;
    const tinygltf::Value& a = e.Get(key);
    if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
      fail(path, at + "." + key, "must be an array of two numbers");
    v = glm::dvec2(a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble());
    return v;
  };
  const glm::dvec2 offset = pair("offset", 0.0), scale = pair("scale", 1.0);
  double rotation = 0.0;
  if (e.Has("rotation")) {
    if (!e.Get("rotation").IsNumber()) fail(path, at + ".rotation", "must be a number");
    rotation = e.Get("rotation").GetNumberAsDouble();
  }
  if (!std::isfinite(offset.x + offset.y + scale.x + scale.y + rotation))
    fail(path, at, "offset, rotation and scale must be finite");
  if (e.Has("texCoord") && e.Get("texCoord").IsInt()) texCoord = e.Get("texCoord").GetNumberAsInt();
  // glTF's map: u' = c sx u + s sy v + ox, v' = -s sx u + c sy v + oy. With v = 1 - v_ours on
  // both sides it becomes uvLinear (columns below) and uvOffset.
  const double c = std::cos(rotation), s = std::sin(rotation);
  t.uvLinear = glm::mat2(glm::vec2(float(c * scale.x), float(s * scale.x)),
                         glm::vec2(float(-s * scale.y), float(c * scale.y)));
  t.uvOffset = glm::vec2(float(s * scale.y + offset.x), float(1.0 - c * scale.y - offset.y));
  t.uvTransformed = t.uvLinear != glm::mat2(1.0f) || t.uvOffset != glm::vec2(0.0f);
}

int textureSource(const std::string& path, const tinygltf::Model& model,
                  const tinygltf::Texture& texture, const std::string& where) {
  const auto webp = texture.extensions.find(kWebpExtension);
  if (webp == texture.extensions.end() || !webp->second.IsObject() || !webp->second.Has("source"))
    return texture.source;
  const tinygltf::Value& source = webp->second.Get("source");
  if (!source.IsInt() || source.GetNumberAsInt() < 0 ||
      size_t(source.GetNumberAsInt()) >= model.images.size())
    fail(path, where + ".extensions." + kWebpExtension + ".source",
         "image " + (source.IsNumber() ? number(source.GetNumberAsDouble()) : "?") +
             " does not exist");
  return source.GetNumberAsInt();
}

int materialUvSet(const std::vector<UvSetUse>& uses, std::vector<std::string>& warnings) {
  if (uses.empty()) return 0;
  const int set = uses.front().set;
  for (const UvSetUse& use : uses)
    if (use.set != set)
      warnings.push_back(use.where + ": uv set " + std::to_string(use.set) +
                         " is not read; uv set " + std::to_string(set) + " is used (" +
                         uses.front().where +
                         "'s: the material's textures are read in one uv set)");
  return set;
}

}  // namespace penumbra::gltf
