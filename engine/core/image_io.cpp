// Image file formats: EXR through tinyexr, the stb formats, and our own PFM reader/writer.
// All writes are assembled in memory and then published through writeFileAtomically, so a
// crash or a full disk never leaves a half-written image where a viewer expects a whole one.
#include "core/image_io.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <numeric>
#include <set>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

const char* const kReadableFormats = ".exr, .pfm, .png, .jpg, .jpeg, .hdr, .tga, .bmp";
const char* const kWritableFormats = ".exr, .pfm, .png";

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
  throw ImageIoError(path + ": " + reason);
}

std::string unsupportedFormat(const std::string& ext, const char* supported) {
  if (ext.empty())
    return std::string("no file extension to choose a format by (supported: ") + supported + ")";
  return "unsupported image format '" + ext + "' (supported: " + supported + ")";
}

using FilePtr = std::unique_ptr<FILE, int (*)(FILE*)>;

// fopen succeeds on a directory under Linux and the reader then fails obscurely, hence the check.
FilePtr openForReading(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail(path, "cannot open file: it is a directory");
  FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) fail(path, std::string("cannot open file: ") + std::strerror(errno));
  return FilePtr(file, &std::fclose);
}

// `displayPath` is what the user asked for; `filePath` is the temporary actually written.
void writeBytes(const std::string& displayPath, const std::string& filePath, const void* data,
                size_t size) {
  FILE* file = std::fopen(filePath.c_str(), "wb");
  if (!file) fail(displayPath, std::string("cannot write file: ") + std::strerror(errno));
  const bool written = std::fwrite(data, 1, size, file) == size;
  const int writeErrno = errno;
  // fclose flushes the buffered tail, so its failure (e.g. disk full) matters as much.
  const bool closed = std::fclose(file) == 0;
  const int closeErrno = errno;
  if (!written || !closed)
    fail(displayPath,
         std::string("cannot write file: ") + std::strerror(written ? closeErrno : writeErrno));
}

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

// Takes ownership of a tinyexr error string (which must be released through tinyexr).
std::string takeExrError(const char* err, int code) {
  if (!err) return "OpenEXR error " + std::to_string(code);
  std::string message = trimmed(err);
  FreeEXRErrorMessage(err);
  return message;
}

uint32_t byteSwapped(uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

void swapFloatBytes(std::vector<float>& values) {
  for (float& f : values) f = std::bit_cast<float>(byteSwapped(std::bit_cast<uint32_t>(f)));
}

// ---- EXR ---------------------------------------------------------------------------------

Image readExr(const std::string& path) {
  openForReading(path);  // turns a missing file into our usual message, not tinyexr's
  float* rgba = nullptr;
  int width = 0, height = 0;
  const char* err = nullptr;
  const int code = LoadEXR(&rgba, &width, &height, path.c_str(), &err);
  if (code != TINYEXR_SUCCESS) fail(path, takeExrError(err, code));
  std::unique_ptr<float, decltype(&std::free)> owned(rgba, &std::free);
  if (width <= 0 || height <= 0) fail(path, "image has no pixels");
  Image image(width, height);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
  return image;
}

struct ExrHeaderOwner {
  EXRHeader header;
  ExrHeaderOwner() { InitEXRHeader(&header); }
  ~ExrHeaderOwner() { FreeEXRHeader(&header); }
};

struct ExrImageOwner {
  EXRImage image;
  ExrImageOwner() { InitEXRImage(&image); }
  ~ExrImageOwner() { FreeEXRImage(&image); }
};

// Converts one loaded channel (FLOAT or UINT after tinyexr's HALF->FLOAT request) to floats.
float exrValue(const unsigned char* plane, int pixelType, size_t index) {
  if (pixelType == TINYEXR_PIXELTYPE_UINT) {
    uint32_t v;
    std::memcpy(&v, plane + 4 * index, 4);
    return float(v);
  }
  float v;
  std::memcpy(&v, plane + 4 * index, 4);
  return v;
}

// ---- PFM ---------------------------------------------------------------------------------

// Reads one whitespace-delimited header token and the single whitespace byte ending it (the
// format puts exactly one between the scale and the binary data). Header tokens are short,
// so a long run of non-space bytes means this is not a PFM header.
bool readPfmToken(FILE* file, std::string& token) {
  token.clear();
  int c = std::getc(file);
  while (c != EOF && std::isspace(c)) c = std::getc(file);
  while (c != EOF && !std::isspace(c)) {
    if (token.size() >= 32) return false;
    token.push_back(char(c));
    c = std::getc(file);
  }
  return !token.empty();
}

template <typename T>
bool parseWhole(const std::string& s, T& value) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && end == s.data() + s.size();
}

Image readPfm(const std::string& path) {
  FilePtr file = openForReading(path);
  std::string magic, widthToken, heightToken, scaleToken;
  if (!readPfmToken(file.get(), magic) || (magic != "PF" && magic != "Pf"))
    fail(path, "not a PFM file (expected \"PF\" or \"Pf\" at the start)");
  const int channels = magic == "PF" ? 3 : 1;
  int width = 0, height = 0;
  float scale = 0.0f;
  if (!readPfmToken(file.get(), widthToken) || !readPfmToken(file.get(), heightToken) ||
      !parseWhole(widthToken, width) || !parseWhole(heightToken, height))
    fail(path, "malformed PFM header (expected width and height)");
  if (width <= 0 || height <= 0) fail(path, "invalid PFM size " + widthToken + "x" + heightToken);
  if (!readPfmToken(file.get(), scaleToken) || !parseWhole(scaleToken, scale) ||
      !std::isfinite(scale) || scale == 0.0f)
    fail(path, "malformed PFM header (expected a non-zero scale)");

  // Compare against the bytes actually present before allocating anything, so a header
  // claiming billions of pixels is rejected instead of exhausting memory.
  const off_t dataStart = ftello(file.get());
  if (dataStart < 0 || fseeko(file.get(), 0, SEEK_END) != 0) fail(path, "cannot seek in file");
  const off_t fileEnd = ftello(file.get());
  if (fileEnd < dataStart || fseeko(file.get(), dataStart, SEEK_SET) != 0)
    fail(path, "cannot seek in file");
  const uint64_t available = uint64_t(fileEnd - dataStart);
  const uint64_t rowBytes = uint64_t(width) * channels * sizeof(float);
  if (available / rowBytes < uint64_t(height))
    fail(path, "truncated pixel data (" + widthToken + "x" + heightToken + " pixels of " +
                   std::to_string(channels * sizeof(float)) + " bytes, but only " +
                   std::to_string(available) + " bytes follow the header)");

  std::vector<float> values(size_t(width) * height * channels);
  if (std::fread(values.data(), sizeof(float), values.size(), file.get()) != values.size())
    fail(path, "truncated pixel data");
  // A negative scale means little-endian data; the magnitude is a unit hint we ignore.
  const bool fileLittleEndian = scale < 0.0f;
  if (fileLittleEndian != (std::endian::native == std::endian::little)) swapFloatBytes(values);

  Image image(width, height);
  for (int row = 0; row < height; ++row) {
    const float* src = values.data() + size_t(row) * width * channels;
    const int y = height - 1 - row;  // PFM stores the bottom row first
    for (int x = 0; x < width; ++x, src += channels)
      image.at(x, y) = channels == 3 ? vec3(src[0], src[1], src[2]) : vec3(src[0]);
  }
  return image;
}

std::vector<unsigned char> encodePfm(const Image& image) {
  const std::string header =
      "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1\n";
  std::vector<float> values;
  values.reserve(image.pixels.size() * 3);
  for (int row = 0; row < image.height; ++row) {
    for (int x = 0; x < image.width; ++x) {
      const vec3 c = image.at(x, image.height - 1 - row);
      values.insert(values.end(), {c.x, c.y, c.z});
    }
  }
  if constexpr (std::endian::native != std::endian::little) swapFloatBytes(values);
  std::vector<unsigned char> bytes(header.begin(), header.end());
  const auto* raw = reinterpret_cast<const unsigned char*>(values.data());
  bytes.insert(bytes.end(), raw, raw + values.size() * sizeof(float));
  return bytes;
}

// ---- stb formats -------------------------------------------------------------------------

std::string stbReason() {
  const char* reason = stbi_failure_reason();
  return std::string("cannot decode image: ") + (reason ? reason : "unknown error");
}

float srgb8ToLinear(unsigned char v) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgbToLinear(float(i) / 255.0f);
    return t;
  }();
  return table[v];
}

Image readStb(const std::string& path, bool radianceHdr) {
  FilePtr file = openForReading(path);
  int width = 0, height = 0, channelsInFile = 0;
  Image image;
  const auto fill = [&](const auto* data, auto toLinear) {
    if (!data) fail(path, stbReason());
    image = Image(width, height);
    for (size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] =
          vec3(toLinear(data[3 * i]), toLinear(data[3 * i + 1]), toLinear(data[3 * i + 2]));
  };
  if (radianceHdr) {
    // stbi_loadf would silently gamma-decode an LDR file renamed to .hdr; refuse instead.
    if (!stbi_is_hdr_from_file(file.get())) fail(path, "not a Radiance HDR file");
    std::unique_ptr<float, decltype(&stbi_image_free)> data(
        stbi_loadf_from_file(file.get(), &width, &height, &channelsInFile, 3), &stbi_image_free);
    fill(data.get(), [](float v) { return v; });
  } else if (stbi_is_16_bit_from_file(file.get())) {
    std::unique_ptr<stbi_us, decltype(&stbi_image_free)> data(
        stbi_load_from_file_16(file.get(), &width, &height, &channelsInFile, 3), &stbi_image_free);
    fill(data.get(), [](stbi_us v) { return srgbToLinear(float(v) / 65535.0f); });
  } else {
    std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
        stbi_load_from_file(file.get(), &width, &height, &channelsInFile, 3), &stbi_image_free);
    fill(data.get(), srgb8ToLinear);
  }
  return image;
}

void appendToVector(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// Flushes the temporary to disk before the rename, so that after a power loss the target
// holds the old or the new contents, not an empty file. Filesystems without fsync say EINVAL.
void syncToDisk(const std::string& displayPath, const std::string& filePath) {
  const int fd = ::open(filePath.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    fail(displayPath, std::string("cannot reopen temporary file: ") + std::strerror(errno));
  const bool synced = ::fsync(fd) == 0 || errno == EINVAL;
  const int syncErrno = errno;
  ::close(fd);
  if (!synced) fail(displayPath, std::string("cannot flush file: ") + std::strerror(syncErrno));
}

}  // namespace

void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string& tmpPath)>& write) {
  // pid + counter keeps concurrent writers (other processes, other threads) apart; O_EXCL
  // guarantees we never adopt a leftover temporary of a crashed run.
  static std::atomic<unsigned> counter{0};
  std::string tmpPath;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    tmpPath = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    fd = ::open(tmpPath.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0)
    fail(path, std::string("cannot write file: ") + std::strerror(errno) + " (creating temporary " +
                   tmpPath + ")");
  ::close(fd);
  try {
    write(tmpPath);
    syncToDisk(path, tmpPath);
    std::error_code ec;
    fs::rename(tmpPath, path, ec);
    if (ec) fail(path, "cannot replace file: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmpPath, ignored);
    throw;
  }
}

Image readImage(const std::string& path) {
  const std::string ext = lowercaseExtension(path);
  if (ext == ".exr") return readExr(path);
  if (ext == ".pfm") return readPfm(path);
  if (ext == ".hdr") return readStb(path, true);
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tga" || ext == ".bmp")
    return readStb(path, false);
  fail(path, unsupportedFormat(ext, kReadableFormats));
}

std::string lowercaseExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void checkWritableImagePath(const std::string& path) {
  const std::string ext = lowercaseExtension(path);
  if (ext != ".exr" && ext != ".pfm" && ext != ".png")
    fail(path, unsupportedFormat(ext, kWritableFormats));
}

void writeImage(const std::string& path, const Image& image, float exposureStops) {
  checkWritableImagePath(path);
  const std::string ext = lowercaseExtension(path);
  if (image.width <= 0 || image.height <= 0)
    fail(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                   std::to_string(image.height) + ")");
  if (image.pixels.size() != size_t(image.width) * image.height)
    fail(path, "image has " + std::to_string(image.pixels.size()) + " pixels, expected " +
                   std::to_string(image.width) + "x" + std::to_string(image.height));

  if (ext == ".exr") {
    std::vector<ExrChannel> planes = {{"R", {}}, {"G", {}}, {"B", {}}};
    for (int c = 0; c < 3; ++c) {
      planes[c].second.resize(image.pixels.size());
      for (size_t i = 0; i < image.pixels.size(); ++i) planes[c].second[i] = image.pixels[i][c];
    }
    writeExrLayers(path, image.width, image.height, planes);
    return;
  }

  std::vector<unsigned char> bytes;
  if (ext == ".pfm") {
    bytes = encodePfm(image);
  } else {
    const std::vector<uint8_t> rgb = toSrgb8(image, exposureStops);
    if (!stbi_write_png_to_func(appendToVector, &bytes, image.width, image.height, 3, rgb.data(),
                                image.width * 3))
      fail(path, "PNG encoding failed");
  }
  writeFileAtomically(path, [&](const std::string& tmpPath) {
    writeBytes(path, tmpPath, bytes.data(), bytes.size());
  });
}

void writePng8(const std::string& path, int width, int height, int channels,
               const std::vector<uint8_t>& data) {
  if (lowercaseExtension(path) != ".png") fail(path, "expected a .png file name");
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      data.size() != size_t(width) * height * channels)
    fail(path, "cannot write " + std::to_string(data.size()) + " bytes as a " +
                   std::to_string(width) + "x" + std::to_string(height) + "x" +
                   std::to_string(channels) + " PNG");
  std::vector<unsigned char> bytes;
  if (!stbi_write_png_to_func(appendToVector, &bytes, width, height, channels, data.data(),
                              width * channels))
    fail(path, "PNG encoding failed");
  writeFileAtomically(path, [&](const std::string& tmpPath) {
    writeBytes(path, tmpPath, bytes.data(), bytes.size());
  });
}

std::vector<uint8_t> encodePng8(int width, int height, int channels,
                                const std::vector<uint8_t>& data) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      data.size() != size_t(width) * height * channels)
    throw ImageIoError("cannot encode " + std::to_string(data.size()) + " bytes as a " +
                       std::to_string(width) + "x" + std::to_string(height) + "x" +
                       std::to_string(channels) + " PNG");
  std::vector<unsigned char> bytes;
  if (!stbi_write_png_to_func(appendToVector, &bytes, width, height, channels, data.data(),
                              width * channels))
    throw ImageIoError("PNG encoding failed");
  return bytes;
}

std::vector<uint8_t> readPng8(const std::string& path, int& width, int& height) {
  int channels = 0;
  unsigned char* pixels = stbi_load(path.c_str(), &width, &height, &channels, 4);
  if (!pixels) fail(path, std::string("cannot read: ") + stbi_failure_reason());
  std::vector<uint8_t> out(pixels, pixels + size_t(width) * height * 4);
  stbi_image_free(pixels);
  return out;
}

void writeExrLayers(const std::string& path, int width, int height,
                    const std::vector<ExrChannel>& channels) {
  if (width <= 0 || height <= 0)
    fail(path, "cannot write an empty image (" + std::to_string(width) + "x" +
                   std::to_string(height) + ")");
  if (channels.empty()) fail(path, "cannot write an EXR without channels");
  const size_t pixelCount = size_t(width) * height;
  std::set<std::string> seen;
  for (const auto& [name, values] : channels) {
    if (name.empty() || name.size() >= sizeof(EXRChannelInfo::name))
      fail(path, "invalid EXR channel name '" + name + "' (must be 1 to 255 bytes)");
    if (!seen.insert(name).second) fail(path, "duplicate EXR channel '" + name + "'");
    if (values.size() != pixelCount)
      fail(path, "channel '" + name + "' has " + std::to_string(values.size()) +
                     " values, expected " + std::to_string(pixelCount));
  }

  // OpenEXR readers expect the channel list in byte-wise name order (what std::string's < does).
  std::vector<size_t> order(channels.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return channels[a].first < channels[b].first; });

  const size_t count = channels.size();
  std::vector<EXRChannelInfo> infos(count);
  std::vector<int> pixelTypes(count, TINYEXR_PIXELTYPE_FLOAT);
  std::vector<unsigned char*> planes(count);
  for (size_t i = 0; i < count; ++i) {
    const ExrChannel& channel = channels[order[i]];
    std::memset(&infos[i], 0, sizeof(EXRChannelInfo));
    std::memcpy(infos[i].name, channel.first.data(), channel.first.size());
    infos[i].pixel_type = TINYEXR_PIXELTYPE_FLOAT;
    infos[i].x_sampling = infos[i].y_sampling = 1;
    // tinyexr only reads through this pointer while saving.
    planes[i] = reinterpret_cast<unsigned char*>(const_cast<float*>(channel.second.data()));
  }

  // Header and image point into the vectors above, so they are not Free'd through tinyexr.
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = int(count);
  header.channels = infos.data();
  header.pixel_types = pixelTypes.data();
  header.requested_pixel_types = pixelTypes.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  EXRImage image;
  InitEXRImage(&image);
  image.images = planes.data();
  image.width = width;
  image.height = height;
  image.num_channels = int(count);

  unsigned char* memory = nullptr;
  const char* err = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
  if (size == 0 || !memory) fail(path, takeExrError(err, TINYEXR_ERROR_SERIALZATION_FAILED));
  std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
  writeFileAtomically(path,
                      [&](const std::string& tmpPath) { writeBytes(path, tmpPath, memory, size); });
}

std::vector<ExrChannel> readExrChannels(const std::string& path) {
  openForReading(path);
  EXRVersion version;
  const int versionCode = ParseEXRVersionFromFile(&version, path.c_str());
  if (versionCode != TINYEXR_SUCCESS) fail(path, "not an OpenEXR file");
  if (version.multipart || version.non_image)
    fail(path, "multi-part and deep EXR files are not supported");

  ExrHeaderOwner header;
  const char* err = nullptr;
  int code = ParseEXRHeaderFromFile(&header.header, &version, path.c_str(), &err);
  if (code != TINYEXR_SUCCESS) fail(path, takeExrError(err, code));
  for (int c = 0; c < header.header.num_channels; ++c) {
    if (header.header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
      header.header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }

  ExrImageOwner image;
  code = LoadEXRImageFromFile(&image.image, &header.header, path.c_str(), &err);
  if (code != TINYEXR_SUCCESS) fail(path, takeExrError(err, code));
  const EXRImage& loaded = image.image;
  const int width = loaded.width, height = loaded.height;
  if (width <= 0 || height <= 0 || loaded.num_channels != header.header.num_channels)
    fail(path, "image has no pixels");

  std::vector<ExrChannel> channels;
  for (int c = 0; c < loaded.num_channels; ++c) {
    const int type = header.header.requested_pixel_types[c];
    std::vector<float> values(size_t(width) * height, 0.0f);
    if (loaded.images) {
      for (size_t i = 0; i < values.size(); ++i) values[i] = exrValue(loaded.images[c], type, i);
    } else if (loaded.tiles) {
      // Tiled file: reassemble the full-resolution level; tile offsets count tiles.
      const int tileW = header.header.tile_size_x, tileH = header.header.tile_size_y;
      for (int t = 0; t < loaded.num_tiles; ++t) {
        const EXRTile& tile = loaded.tiles[t];
        for (int j = 0; j < tile.height; ++j) {
          for (int i = 0; i < tile.width; ++i) {
            const long x = long(tile.offset_x) * tileW + i, y = long(tile.offset_y) * tileH + j;
            if (x < width && y < height)
              values[size_t(y) * width + x] = exrValue(tile.images[c], type, size_t(j) * tileW + i);
          }
        }
      }
    } else {
      fail(path, "EXR file holds no pixel data");
    }
    channels.emplace_back(header.header.channels[c].name, std::move(values));
  }
  return channels;
}

}  // namespace penumbra
