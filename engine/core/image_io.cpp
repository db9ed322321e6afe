// Image file formats: EXR through OpenEXR, the stb formats, and our own PFM reader/writer.
// All writes are assembled in memory and then published through writeFileAtomically, so a
// crash or a full disk never leaves a half-written image where a viewer expects a whole one.
#include "core/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfPartType.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

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
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <span>
#include <stdexcept>

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

uint32_t byteSwapped(uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

void swapFloatBytes(std::vector<float>& values) {
  for (float& f : values) f = std::bit_cast<float>(byteSwapped(std::bit_cast<uint32_t>(f)));
}

// ---- EXR ---------------------------------------------------------------------------------

// Bounds on what a file's header may ask for, so that a damaged or hostile file cannot make the
// reader allocate without limit: OpenEXR's own check of the header's windows and tiles, and
// ours on the float planes we allocate. Deflate (ZIP) packs at most 1032 bytes into one, so at
// most about 260 four-byte values per byte of file; RLE and B44 pack fewer. More than
// kMaxValuesPerByte values per byte of file cannot be a real ZIP, RLE or B44 file (a constant
// image under PIZ or DWA could be one: such a file is refused with a message that says why).
constexpr int kMaxExrSide = 1 << 16;
constexpr uint64_t kMaxValuesPerByte = 1024;
constexpr uint64_t kMaxExrValues = uint64_t(1) << 30;

void limitOpenExrHeaders() {
  static const bool once = [] {
    Imf::Header::setMaxImageSize(kMaxExrSide, kMaxExrSide);
    Imf::Header::setMaxTileSize(kMaxExrSide, kMaxExrSide);
    return true;
  }();
  (void)once;
}

std::vector<unsigned char> readWholeFile(const std::string& path) {
  FilePtr file = openForReading(path);
  std::vector<unsigned char> bytes;
  unsigned char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0)
    bytes.insert(bytes.end(), buffer, buffer + n);
  if (std::ferror(file.get())) fail(path, std::string("read error: ") + std::strerror(errno));
  return bytes;
}

// OpenEXR reads the bytes already in memory (they were checked there first).
class MemoryStream : public Imf::IStream {
 public:
  MemoryStream(const std::string& name, const std::vector<unsigned char>& bytes)
      : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || uint64_t(n) > bytes_.size() - at_)
      throw std::runtime_error("unexpected end of file at byte " + std::to_string(at_));
    std::memcpy(c, bytes_.data() + at_, size_t(n));
    at_ += uint64_t(n);
    return at_ < bytes_.size();
  }
  uint64_t tellg() override { return at_; }
  void seekg(uint64_t pos) override { at_ = std::min<uint64_t>(pos, bytes_.size()); }

 private:
  const std::vector<unsigned char>& bytes_;
  uint64_t at_ = 0;
};

// What the reader needs to know of a header before OpenEXR reads it: the first part's data
// window and how many chunks (scanline blocks or tiles) it is stored in. Every chunk has an
// 8-byte entry in the offset table after the header, so a window whose chunk count does not
// fit in the file is damaged; checking that first bounds what OpenEXR allocates for its tables
// by the file's own size.
struct ExrLayout {
  int64_t width = 0, height = 0, chunks = 0;
  uint64_t headerBytes = 0;
};

ExrLayout readExrLayout(const std::string& path, const std::vector<unsigned char>& bytes) {
  size_t at = 0;
  auto need = [&](size_t n, const char* what) {
    if (bytes.size() - at < n)
      fail(path,
           std::string("truncated EXR header (") + what + " at byte " + std::to_string(at) + ")");
  };
  auto readInt = [&](const char* what) {
    need(4, what);
    const uint32_t v = uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 |
                       uint32_t(bytes[at + 2]) << 16 | uint32_t(bytes[at + 3]) << 24;
    at += 4;
    return v;
  };
  auto readName = [&](const char* what) {
    const size_t start = at;
    while (at < bytes.size() && bytes[at] != 0 && at - start < 256) ++at;
    if (at >= bytes.size() || bytes[at] != 0)
      fail(path, std::string("damaged EXR header (") + what + " at byte " + std::to_string(start) +
                     " has no end)");
    return std::string(reinterpret_cast<const char*>(bytes.data()) + start, at++ - start);
  };
  if (readInt("magic number") != 20000630u) fail(path, "not an OpenEXR file");
  const uint32_t version = readInt("version");
  if (version & 0x1000u) fail(path, "multi-part EXR files are not supported");
  if (version & 0x800u) fail(path, "deep EXR files are not supported");
  const bool tiled = (version & 0x200u) != 0;

  bool haveWindow = false, haveTiles = false;
  int64_t box[4] = {};
  uint32_t tileX = 0, tileY = 0;
  int compression = 0;
  for (;;) {
    const std::string name = readName("attribute name");
    if (name.empty()) break;
    const std::string type = readName("attribute type");
    const uint32_t size = readInt("attribute size");
    const size_t valueAt = at;
    need(size, ("attribute '" + name + "'").c_str());
    if (name == "dataWindow" && type == "box2i" && size == 16) {
      for (int64_t& v : box) v = int32_t(readInt("dataWindow"));
      haveWindow = true;
    } else if (name == "tiles" && type == "tiledesc" && size >= 8) {
      tileX = readInt("tiles");
      tileY = readInt("tiles");
      haveTiles = true;
    } else if (name == "compression" && type == "compression" && size == 1) {
      compression = bytes[at];
    }
    at = valueAt + size;
  }
  if (!haveWindow) fail(path, "EXR header has no dataWindow");
  ExrLayout layout;
  layout.width = box[2] - box[0] + 1;
  layout.height = box[3] - box[1] + 1;
  layout.headerBytes = at;
  if (layout.width <= 0 || layout.height <= 0) fail(path, "image has no pixels");
  if (tiled) {
    if (!haveTiles || tileX == 0 || tileY == 0) fail(path, "tiled EXR file without a tile size");
    layout.chunks = ((layout.width + tileX - 1) / tileX) * ((layout.height + tileY - 1) / tileY);
  } else {
    // Scanlines per chunk of each compression (NONE, RLE, ZIPS: 1; ZIP, PXR24: 16; PIZ, B44,
    // B44A, DWAA: 32; DWAB: 256).
    static const int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    const int lines = compression >= 0 && compression < 10 ? kLines[compression] : 1;
    layout.chunks = (layout.height + lines - 1) / lines;
  }
  const uint64_t room = (bytes.size() - layout.headerBytes) / 8;
  if (uint64_t(layout.chunks) > room)
    fail(path, "truncated or damaged: its " + std::to_string(layout.width) + "x" +
                   std::to_string(layout.height) + " data window needs " +
                   std::to_string(layout.chunks) + " chunks, the file has room for " +
                   std::to_string(room));
  return layout;
}

struct ExrPlanes {
  int width = 0, height = 0;
  std::vector<ExrChannel> channels;  // in the file's (sorted) order
};

ExrPlanes readExrPlanes(const std::string& path) {
  const std::vector<unsigned char> bytes = readWholeFile(path);
  const uint64_t fileBytes = bytes.size();
  readExrLayout(path, bytes);
  limitOpenExrHeaders();
  ExrPlanes out;
  try {
    MemoryStream stream(path, bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    if (header.hasType() && Imf::isDeepData(header.type()))
      fail(path, "deep EXR files are not supported");
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1;
    const int64_t height = int64_t(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0) fail(path, "image has no pixels");
    uint64_t channelCount = 0;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        fail(path, std::string("channel '") + c.name() + "' is subsampled, which is not supported");
      ++channelCount;
    }
    if (channelCount == 0) fail(path, "EXR file has no channels");
    const uint64_t values = uint64_t(width) * uint64_t(height) * channelCount;
    if (values > kMaxExrValues || values > kMaxValuesPerByte * uint64_t(fileBytes))
      fail(path, "data window " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                     std::to_string(channelCount) + " channels is too large for a file of " +
                     std::to_string(fileBytes) + " bytes");
    out.width = int(width);
    out.height = int(height);
    Imf::FrameBuffer frame;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      out.channels.emplace_back(c.name(), std::vector<float>(size_t(width) * size_t(height), 0.0f));
      frame.insert(c.name(), Imf::Slice::Make(Imf::FLOAT, out.channels.back().second.data(), window,
                                              sizeof(float), sizeof(float) * size_t(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, trimmed(e.what()));
  }
  return out;
}

// RGB from R, G, B (alpha and other channels dropped), or a single channel as grey.
Image readExr(const std::string& path) {
  const ExrPlanes planes = readExrPlanes(path);
  const std::vector<float>* rgb[3] = {nullptr, nullptr, nullptr};
  for (const auto& [name, values] : planes.channels) {
    if (name == "R") rgb[0] = &values;
    if (name == "G") rgb[1] = &values;
    if (name == "B") rgb[2] = &values;
  }
  if (!(rgb[0] && rgb[1] && rgb[2])) {
    if (planes.channels.size() != 1) {
      std::string names;
      for (const auto& channel : planes.channels)
        names += (names.empty() ? "" : ", ") + channel.first;
      fail(path, "no R, G, B channels to read as an image (it has " + names + ")");
    }
    rgb[0] = rgb[1] = rgb[2] = &planes.channels[0].second;
  }
  Image image(planes.width, planes.height);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = vec3((*rgb[0])[i], (*rgb[1])[i], (*rgb[2])[i]);
  return image;
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

// stb_image allocates the whole decoded image from the header's size before it inflates a
// byte. No PNG, JPEG, TGA, BMP or HDR codec packs more than about a thousand samples into a byte
// of file (Deflate's limit is 1032 bytes per byte), so a header asking for more than this many
// samples per byte of file, past a small floor, is damaged: refused before stb allocates.
constexpr uint64_t kMaxSamplesPerByte = 2048;
constexpr uint64_t kMinSampleAllowance = uint64_t(1) << 20;

// stb_image grows its buffer to a PNG chunk's stated length before it reads the chunk, so a
// length field of gigabytes in a small file makes it allocate gigabytes (found by fuzzing).
// Every chunk of a PNG must fit in the file: checked first, up to IEND.
void checkPngChunks(const std::string& path, std::span<const unsigned char> bytes) {
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) return;
  size_t at = 8;
  while (bytes.size() - at >= 8) {
    const uint32_t length = uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 |
                            uint32_t(bytes[at + 2]) << 8 | uint32_t(bytes[at + 3]);
    const std::string type(reinterpret_cast<const char*>(bytes.data()) + at + 4, 4);
    if (uint64_t(length) + 12 > bytes.size() - at) {
      std::string shown = type;
      for (char& c : shown)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '?';
      fail(path, "truncated or damaged PNG: chunk '" + shown + "' at byte " + std::to_string(at) +
                     " claims " + std::to_string(length) + " bytes, " +
                     std::to_string(bytes.size() - at - std::min<size_t>(bytes.size() - at, 12)) +
                     " are left");
    }
    if (type == "IEND") return;
    at += 12 + size_t(length);
  }
}

bool startsWith(std::span<const unsigned char> bytes, const char* magic, size_t length) {
  return bytes.size() >= length && std::memcmp(bytes.data(), magic, length) == 0;
}

// stb_image decodes by content, not by name, and also reads PNM, PSD, GIF and Softimage PIC,
// which Penumbra does not list. Its PNM reader hands back an 8-bit buffer for a 16-bit file
// whose channel count it converts, which the 16-bit path then reads past (found by fuzzing):
// such contents are refused by their magic, whatever the file's extension says.
void refuseUnlistedContents(const std::string& path, std::span<const unsigned char> bytes) {
  const char* format = nullptr;
  if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7')
    format = "a PNM (PBM/PGM/PPM) image";
  else if (startsWith(bytes, "8BPS", 4))
    format = "a Photoshop image";
  else if (startsWith(bytes, "GIF8", 4))
    format = "a GIF image";
  else if (startsWith(bytes, "\x53\x80\xf6\x34", 4))
    format = "a Softimage PIC image";
  if (format)
    fail(path, std::string("its contents are ") + format +
                   ", which Penumbra does not read (readable: " + kReadableFormats + ")");
}

// stb's view of a header's size and channels, refused when the bytes are too many for stb or
// the header asks for more samples (`samplesPerPixel` a pixel; 0: its channels) than the
// bytes can hold. `noun` ("file", "image") names the bytes in the messages.
void checkStbHeader(const std::string& path, std::span<const unsigned char> bytes, const char* noun,
                    int samplesPerPixel, int& width, int& height, int& channels) {
  const std::string what(noun);
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) fail(path, what + " too large");
  if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels))
    fail(path, stbReason());
  const uint64_t samples = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0)) *
                           uint64_t(samplesPerPixel > 0 ? samplesPerPixel : channels);
  if (samples > std::max(kMinSampleAllowance, kMaxSamplesPerByte * uint64_t(bytes.size())))
    fail(path, "its header's " + std::to_string(width) + "x" + std::to_string(height) +
                   " pixels are too many for " + (what[0] == 'i' ? "an " : "a ") + what + " of " +
                   std::to_string(bytes.size()) + " bytes");
}

// The file's bytes once its contents' format, PNG chunks and header's size are checked; stb's
// view of its size and channels in width, height and channels.
std::vector<unsigned char> readStbFile(const std::string& path, int& width, int& height,
                                       int& channels) {
  std::vector<unsigned char> bytes = readWholeFile(path);
  refuseUnlistedContents(path, bytes);
  checkPngChunks(path, bytes);
  checkStbHeader(path, bytes, "file", 3, width, height, channels);
  return bytes;
}

Image readStb(const std::string& path, bool radianceHdr) {
  // Read once; the checks and stb all work on the bytes in memory.
  int width = 0, height = 0, channelsInFile = 0;
  const std::vector<unsigned char> bytes = readStbFile(path, width, height, channelsInFile);
  const stbi_uc* data = bytes.data();
  const int size = int(bytes.size());
  Image image;
  const auto fill = [&](const auto* decoded, auto toLinear) {
    if (!decoded) fail(path, stbReason());
    image = Image(width, height);
    for (size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = vec3(toLinear(decoded[3 * i]), toLinear(decoded[3 * i + 1]),
                             toLinear(decoded[3 * i + 2]));
  };
  if (radianceHdr) {
    // stbi_loadf would silently gamma-decode an LDR file renamed to .hdr; refuse instead.
    if (!stbi_is_hdr_from_memory(data, size)) fail(path, "not a Radiance HDR file");
    std::unique_ptr<float, decltype(&stbi_image_free)> decoded(
        stbi_loadf_from_memory(data, size, &width, &height, &channelsInFile, 3), &stbi_image_free);
    fill(decoded.get(), [](float v) { return v; });
  } else if (stbi_is_16_bit_from_memory(data, size)) {
    std::unique_ptr<stbi_us, decltype(&stbi_image_free)> decoded(
        stbi_load_16_from_memory(data, size, &width, &height, &channelsInFile, 3),
        &stbi_image_free);
    fill(decoded.get(), [](stbi_us v) { return srgbToLinear(float(v) / 65535.0f); });
  } else {
    std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> decoded(
        stbi_load_from_memory(data, size, &width, &height, &channelsInFile, 3), &stbi_image_free);
    fill(decoded.get(), srgb8ToLinear);
  }
  return image;
}

bool isStbLdrExtension(const std::string& ext) {
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tga" || ext == ".bmp";
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
  if (isStbLdrExtension(ext)) return readStb(path, false);
  fail(path, unsupportedFormat(ext, kReadableFormats));
}

std::optional<Image8> readImage8(const std::string& path) {
  if (!isStbLdrExtension(lowercaseExtension(path))) return std::nullopt;
  Image8 image;
  int channelsInFile = 0;
  const std::vector<unsigned char> bytes =
      readStbFile(path, image.width, image.height, channelsInFile);
  if (stbi_is_16_bit_from_memory(bytes.data(), int(bytes.size()))) return std::nullopt;
  image.channels = channelsInFile <= 2 ? 1 : 3;
  std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> decoded(
      stbi_load_from_memory(bytes.data(), int(bytes.size()), &image.width, &image.height,
                            &channelsInFile, image.channels),
      &stbi_image_free);
  if (!decoded) fail(path, stbReason());
  image.data.assign(decoded.get(), decoded.get() + size_t(image.width) * size_t(image.height) *
                                                       size_t(image.channels));
  return image;
}

DecodedImage inspectPngOrJpeg(const std::string& name, const unsigned char* bytes, size_t size) {
  const std::span<const unsigned char> file(bytes, size);
  const bool png = startsWith(file, "\x89PNG\r\n\x1a\n", 8);
  if (!png && !startsWith(file, "\xff\xd8\xff", 3))
    fail(name, "not a PNG or JPEG image (glTF's image formats)");
  checkPngChunks(name, file);
  DecodedImage image;
  checkStbHeader(name, file, "image", 0, image.width, image.height, image.channels);
  image.bits = png && stbi_is_16_bit_from_memory(bytes, int(size)) ? 16 : 8;
  return image;
}

DecodedImage decodePngOrJpeg(const std::string& name, const unsigned char* bytes, size_t size) {
  DecodedImage image = inspectPngOrJpeg(name, bytes, size);
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<void, decltype(&stbi_image_free)> decoded(
      image.bits == 16 ? static_cast<void*>(stbi_load_16_from_memory(
                             bytes, int(size), &width, &height, &channels, image.channels))
                       : static_cast<void*>(stbi_load_from_memory(bytes, int(size), &width, &height,
                                                                  &channels, image.channels)),
      &stbi_image_free);
  if (!decoded) fail(name, stbReason());
  if (width != image.width || height != image.height)
    fail(name, "cannot decode image: its size changed while it was decoded");
  const size_t length =
      size_t(width) * size_t(height) * size_t(image.channels) * size_t(image.bits / 8);
  const auto* first = static_cast<const uint8_t*>(decoded.get());
  image.data.assign(first, first + length);
  return image;
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

void writeImage(const std::string& path, const Image& image, float exposureStops,
                const std::vector<float>* alpha) {
  checkWritableImagePath(path);
  const std::string ext = lowercaseExtension(path);
  if (image.width <= 0 || image.height <= 0)
    fail(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                   std::to_string(image.height) + ")");
  if (image.pixels.size() != size_t(image.width) * image.height)
    fail(path, "image has " + std::to_string(image.pixels.size()) + " pixels, expected " +
                   std::to_string(image.width) + "x" + std::to_string(image.height));
  if (alpha && alpha->size() != image.pixels.size())
    fail(path, "alpha has " + std::to_string(alpha->size()) + " values for " +
                   std::to_string(image.pixels.size()) + " pixels");
  if (alpha && ext == ".pfm") fail(path, "a PFM file has no alpha channel: use .exr or .png");

  if (ext == ".exr") {
    std::vector<ExrChannel> planes = {{"R", {}}, {"G", {}}, {"B", {}}};
    for (int c = 0; c < 3; ++c) {
      planes[c].second.resize(image.pixels.size());
      for (size_t i = 0; i < image.pixels.size(); ++i) planes[c].second[i] = image.pixels[i][c];
    }
    if (alpha) planes.push_back({"A", *alpha});  // the colour is premultiplied, as EXR expects
    writeExrLayers(path, image.width, image.height, planes);
    return;
  }

  std::vector<unsigned char> bytes;
  if (ext == ".pfm") {
    bytes = encodePfm(image);
  } else if (alpha) {
    // PNG's alpha is straight: undo the premultiplication before encoding.
    Image straight = image;
    for (size_t i = 0; i < straight.pixels.size(); ++i)
      if ((*alpha)[i] > 0) straight.pixels[i] /= (*alpha)[i];
    const std::vector<uint8_t> rgb = toSrgb8(straight, exposureStops);
    std::vector<uint8_t> rgba(straight.pixels.size() * 4);
    for (size_t i = 0; i < straight.pixels.size(); ++i) {
      for (int c = 0; c < 3; ++c) rgba[4 * i + size_t(c)] = rgb[3 * i + size_t(c)];
      rgba[4 * i + 3] = uint8_t(std::lround(std::clamp((*alpha)[i], 0.0f, 1.0f) * 255.0f));
    }
    if (!stbi_write_png_to_func(appendToVector, &bytes, image.width, image.height, 4, rgba.data(),
                                image.width * 4))
      fail(path, "PNG encoding failed");
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
    if (name.empty() || name.size() > 255)
      fail(path, "invalid EXR channel name '" + name + "' (must be 1 to 255 bytes)");
    if (!seen.insert(name).second) fail(path, "duplicate EXR channel '" + name + "'");
    if (values.size() != pixelCount)
      fail(path, "channel '" + name + "' has " + std::to_string(values.size()) +
                     " values, expected " + std::to_string(pixelCount));
  }

  // The header's channel list keeps the names sorted, as the format requires; every channel
  // is written as 32-bit float, ZIP-compressed.
  writeFileAtomically(path, [&](const std::string& tmpPath) {
    try {
      Imf::Header header(width, height);
      header.compression() = Imf::ZIP_COMPRESSION;
      Imf::FrameBuffer frame;
      for (const auto& [name, values] : channels) {
        header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        // OpenEXR only reads through this pointer while writing.
        frame.insert(
            name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(values.data())),
                             sizeof(float), sizeof(float) * size_t(width)));
      }
      Imf::OutputFile file(tmpPath.c_str(), header);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    } catch (const std::exception& e) {
      fail(path, "cannot write file: " + trimmed(e.what()));
    }
  });
}

std::vector<ExrChannel> readExrChannels(const std::string& path) {
  return readExrPlanes(path).channels;
}

}  // namespace penumbra
