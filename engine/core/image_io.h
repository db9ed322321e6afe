// Reading and writing images on disk (EXR, PFM, PNG and the stb-readable formats), the
// multi-channel EXR used to store a render with its per-pixel variance, and the atomic
// "write to a temporary file, then rename" helper every file output goes through.
#pragma once

#include "core/image.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

// Every failure names the file first: "<path>: <reason>".
struct ImageIoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an image by extension (case-insensitive) into linear RGB:
//   .exr                     RGB(A) through OpenEXR (alpha dropped, a single channel as grey)
//   .pfm                     "PF" colour or "Pf" greyscale, either endianness
//   .hdr                     Radiance RGBE, already linear
//   .png .jpg .jpeg .tga .bmp  8/16-bit, decoded from sRGB to linear
// Throws ImageIoError on a missing, unreadable, malformed or unsupported file.
Image readImage(const std::string& path);

// An 8-bit image as its file stores it (sRGB-encoded for colour): width x height pixels of
// `channels` bytes each, top row first.
struct Image8 {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> data;
};
// Reads an 8-bit PNG, JPEG, TGA or BMP file without converting its values: one channel for a
// grey file, three otherwise (alpha dropped). Returns nothing for the other formats and for
// 16-bit PNG files, which readImage reads as float. Throws ImageIoError as readImage does.
std::optional<Image8> readImage8(const std::string& path);

// A PNG or JPEG held in memory (a glTF file's image), decoded with the checks a file gets
// (damaged PNG chunks, headers asking for too many pixels): `channels` as stored (1-4), `bits`
// 8, or 16 for a 16-bit PNG (two bytes a value, little-endian), top row first. Any other
// contents are refused. `name` starts every error message ("<name>: <reason>").
struct DecodedImage {
  int width = 0, height = 0, channels = 0, bits = 8;
  std::vector<uint8_t> data;
};
DecodedImage decodePngOrJpeg(const std::string& name, const unsigned char* bytes, size_t size);
// The same checks and the header's size, channels and bits, without decoding (`data` empty):
// what decodePngOrJpeg will give, or the error it would throw for the header.
DecodedImage inspectPngOrJpeg(const std::string& name, const unsigned char* bytes, size_t size);

// Writes an image by extension (case-insensitive), atomically (see writeFileAtomically):
//   .exr  float32 RGB, ZIP compressed       .pfm  little-endian float RGB
//   .png  8-bit sRGB after scaling by 2^exposureStops and clamping to [0,1]
// The exposure only affects PNG: the HDR formats store the radiance unchanged. With `alpha`
// (one coverage value per pixel; the colour premultiplied by it), EXR gets an "A" channel and
// PNG an alpha channel (straight, as PNG stores it); PFM has none and is refused.
// Throws ImageIoError for an empty image, an unsupported extension or an I/O failure.
void writeImage(const std::string& path, const Image& image, float exposureStops = 0.0f,
                const std::vector<float>* alpha = nullptr);
// Throws the ImageIoError writeImage would give for an unsupported extension, so a command
// can reject a bad output name before spending minutes on a render.
void checkWritableImagePath(const std::string& path);
// The file extension of `path`, lower-cased, with its dot (".exr"); empty if none.
std::string lowercaseExtension(const std::string& path);

// Writes display-encoded 8-bit pixels (channels 1-4 per pixel, top row first) as PNG,
// atomically; for screenshots, whose bytes are already what the screen shows.
void writePng8(const std::string& path, int width, int height, int channels,
               const std::vector<uint8_t>& data);
// The PNG file bytes of display-encoded 8-bit pixels (channels 1-4, top row first), for
// embedding or writing elsewhere. Throws ImageIoError on bad sizes or an encoding failure.
std::vector<uint8_t> encodePng8(int width, int height, int channels,
                                const std::vector<uint8_t>& data);
// Reads an 8-bit image file as RGBA bytes, top row first, with no colour conversion.
std::vector<uint8_t> readPng8(const std::string& path, int& width, int& height);

// One named float plane of width*height values, top row first.
using ExrChannel = std::pair<std::string, std::vector<float>>;

// Writes a float32, ZIP-compressed scanline EXR holding any set of named channels
// ("R", "G", "B", "variance.R", ...), atomically. Channel names must be unique and non-empty;
// they are stored sorted by name, as the EXR format requires.
void writeExrLayers(const std::string& path, int width, int height,
                    const std::vector<ExrChannel>& channels);

// Reads every channel of a single-part EXR as float (HALF and UINT are converted), in the
// order the file lists them (sorted by name). Throws ImageIoError.
std::vector<ExrChannel> readExrChannels(const std::string& path);

// Calls write(tmpPath) with a fresh temporary path in the same directory as `path`, then
// renames it over `path`, so readers see either the old file or the complete new one. If
// `write` throws or the rename fails, the temporary is removed and the error propagates
// (I/O failures here throw ImageIoError). The temporary file already exists (empty) when
// `write` is called, which proves the directory is writable.
void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string& tmpPath)>& write);

}  // namespace penumbra
