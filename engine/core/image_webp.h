// WebP images held in memory (a glTF file's EXT_texture_webp images), decoded by libwebp with
// the same contract as decodePngOrJpeg (core/image_io.h): 8-bit values, 3 channels or 4 with
// alpha, top row first, errors as ImageIoError starting with `name`.
#pragma once

#include "core/image_io.h"

#include <cstddef>
#include <string>

namespace penumbra {

// Whether the bytes are a WebP file (RIFF....WEBP).
bool isWebp(const unsigned char* bytes, size_t size);

// The header's size and channels without decoding (`data` empty); throws ImageIoError for
// contents that are not WebP, a header libwebp cannot read, or more than kMaxWebpPixels pixels
// (a damaged header: libwebp would allocate the whole image before decoding).
DecodedImage inspectWebp(const std::string& name, const unsigned char* bytes, size_t size);
// The decoded image; throws ImageIoError as inspectWebp does, or for data that does not decode.
DecodedImage decodeWebp(const std::string& name, const unsigned char* bytes, size_t size);

// 8192 x 8192: past it a texture is refused rather than allocated (WebP's own limit is 16383
// a side, a gigabyte decoded).
inline constexpr size_t kMaxWebpPixels = size_t(1) << 26;

}  // namespace penumbra
