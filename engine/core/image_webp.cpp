#include "core/image_webp.h"

#include <webp/decode.h>

#include <cstring>
#include <limits>
#include <memory>

namespace penumbra {

namespace {

[[noreturn]] void refuse(const std::string& name, const std::string& reason) {
  throw ImageIoError(name + ": " + reason);
}

}  // namespace

bool isWebp(const unsigned char* bytes, size_t size) {
  return size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
}

DecodedImage inspectWebp(const std::string& name, const unsigned char* bytes, size_t size) {
  if (!isWebp(bytes, size)) refuse(name, "not a WebP image");
  WebPBitstreamFeatures features;
  if (WebPGetFeatures(bytes, size, &features) != VP8_STATUS_OK)
    refuse(name, "cannot decode image: a damaged WebP header");
  if (features.width <= 0 || features.height <= 0 ||
      size_t(features.width) * size_t(features.height) > kMaxWebpPixels)
    refuse(name, "its header's " + std::to_string(features.width) + "x" +
                     std::to_string(features.height) +
                     " pixels are more than a texture may have (" + std::to_string(kMaxWebpPixels) +
                     ")");
  if (features.has_animation) refuse(name, "an animated WebP is not a texture");
  DecodedImage image;
  image.width = features.width;
  image.height = features.height;
  image.channels = features.has_alpha ? 4 : 3;
  image.bits = 8;
  return image;
}

DecodedImage decodeWebp(const std::string& name, const unsigned char* bytes, size_t size) {
  DecodedImage image = inspectWebp(name, bytes, size);
  int width = 0, height = 0;
  std::unique_ptr<uint8_t, decltype(&WebPFree)> decoded(
      image.channels == 4 ? WebPDecodeRGBA(bytes, size, &width, &height)
                          : WebPDecodeRGB(bytes, size, &width, &height),
      &WebPFree);
  if (!decoded) refuse(name, "cannot decode image: damaged WebP data");
  if (width != image.width || height != image.height)
    refuse(name, "cannot decode image: its size changed while it was decoded");
  const size_t length = size_t(width) * size_t(height) * size_t(image.channels);
  image.data.assign(decoded.get(), decoded.get() + length);
  return image;
}

}  // namespace penumbra
