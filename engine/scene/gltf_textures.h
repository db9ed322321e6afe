// A glTF file's textures for gltf_io.cpp: its decoded images turned into ours (8 bits stay 8
// bits, 16 become float), its samplers' wrap modes and KHR_texture_transform's uv maps. Errors
// name the file and the element. Internal to the glTF reader.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace penumbra::gltf {

// How a texture's texels become ours: colour (sRGB, RGB or grey), data (raw values, for
// normal maps and metallic-roughness) or coverage (the alpha channel alone). 8-bit images stay
// 8-bit, 16-bit ones become float; the factors are applied at lookup (Texture::factor).
enum class Texels { Color, Data, Alpha };

// A decoded glTF image (images[index]) turned into one of ours; empty for coverage of an image
// without alpha (the material's factor alone is its coverage).
TextureImage imageFromGltf(const std::string& path, const tinygltf::Image& source, size_t index,
                           Texels texels);

// The images tinygltf left undecoded, by index: their format ("KTX2", "AVIF").
using ImagesNotRead = std::map<int, std::string>;
// The extensions that give a texture an image in one of those formats.
inline constexpr const char* kImageFormatExtensions[] = {"KHR_texture_basisu", "EXT_texture_avif"};
// The extension that gives a texture a WebP image, which is read (core/image_webp.h).
inline constexpr const char* kWebpExtension = "EXT_texture_webp";

// tinygltf's image loader (TinyGLTF::SetImageLoader, `user` an ImagesNotRead): PNG, JPEG and
// WebP checked now and decoded when converted (decodePngOrJpeg, decodeWebp: their checks
// against damaged files; 8 or 16 bits, the channels as stored); KTX2 and AVIF, the formats of
// extensions, left undecoded and noted, so that a texture with a PNG or JPEG fallback still
// loads; anything else an error naming the image.
bool loadGltfImage(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                   int requiredWidth, int requiredHeight, const unsigned char* bytes, int size,
                   void* user);

// A sampler's wrap mode (10497 REPEAT, and -1, tinygltf's "not given"; 33071 CLAMP_TO_EDGE;
// 33648 MIRRORED_REPEAT); another value throws SceneError naming `where`.
TextureWrap wrapMode(const std::string& path, int mode, const std::string& where);

// A texture reference's KHR_texture_transform (offset, rotation counter-clockwise in radians,
// scale; uv' = T R S uv in glTF's uv, whose v runs down the image), if `extensions` has one,
// as an affine map of this engine's uv (v up) into `t`; its texCoord overrides `texCoord`.
// Malformed values throw SceneError naming `where`.
void textureTransform(const std::string& path, const tinygltf::ExtensionMap& extensions,
                      const std::string& where, Texture& t, int& texCoord);

// The image a texture reads: EXT_texture_webp's when it names one (a fallback in `source` is
// for viewers that read no WebP), else `source`. A WebP image that does not exist throws
// SceneError naming `where`.
int textureSource(const std::string& path, const tinygltf::Model& model,
                  const tinygltf::Texture& texture, const std::string& where);

// A texture reference of a material: where it is, and the uv set it reads.
struct UvSetUse {
  std::string where;
  int set = 0;
};
// The one uv set a material's textures are read in (this engine keeps one per vertex): its
// first texture's (the base colour's, when it has one), 0 without textures. Each reference on
// another set gets a warning in `warnings`.
int materialUvSet(const std::vector<UvSetUse>& uses, std::vector<std::string>& warnings);

}  // namespace penumbra::gltf
