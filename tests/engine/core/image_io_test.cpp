// Tests for engine/image_io: exact float round trips, PNG within 8-bit quantisation, the PFM
// reader on hand-made files, clean errors on bad input, and atomic (all-or-nothing) writes.
#include "core/image_io.h"
#include "tests/test_paths.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <ImfTiledOutputFile.h>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// Each test works in its own empty directory so leftover-file checks are meaningful.
std::string freshDir(const std::string& name) {
  const fs::path dir = test::outputPath("image_io/" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::vector<std::string> listDir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

void writeRaw(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string readRaw(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Values a lossy or clamping path would not preserve: negative, > 1, tiny, huge.
Image hdrTestImage() {
  Image image(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      image.at(x, y) = vec3(0.1f * x - 0.2f, 1e-7f * float(y + 1), 1234.5f * float(x * y) + 0.3f);
  return image;
}

void expectExactlyEqual(const Image& a, const Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(a.at(x, y)[k], b.at(x, y)[k]) << x << "," << y;
}

// Expects ImageIoError whose message names `path` and contains `reason`.
template <typename F>
void expectIoError(F&& f, const std::string& path, const std::string& reason) {
  try {
    f();
    ADD_FAILURE() << "no ImageIoError for " << path;
  } catch (const ImageIoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

TEST(ImageIo, ExrRoundTripIsExact) {
  const std::string path = freshDir("exr") + "/image.exr";
  const Image image = hdrTestImage();
  writeImage(path, image);
  expectExactlyEqual(readImage(path), image);
}

TEST(ImageIo, AlphaGoesIntoExrAndStraightIntoPng) {
  const std::string dir = freshDir("alpha");
  Image image(2, 1);
  image.at(0, 0) = vec3(0.25f);  // premultiplied by alpha 0.5: straight 0.5
  const std::vector<float> alpha = {0.5f, 0.0f};
  writeImage(dir + "/a.exr", image, 0.0f, &alpha);
  const auto channels = readExrChannels(dir + "/a.exr");
  ASSERT_EQ(channels.size(), 4u);
  EXPECT_EQ(channels[0].first, "A");  // sorted by name
  EXPECT_EQ(channels[0].second, alpha);
  writeImage(dir + "/a.png", image, 0.0f, &alpha);
  int w = 0, h = 0;
  const std::vector<uint8_t> rgba = readPng8(dir + "/a.png", w, h);
  ASSERT_EQ(rgba.size(), 8u);
  EXPECT_EQ(rgba[0], uint8_t(std::lround(linearToSrgb(0.5f) * 255)));  // straight colour
  EXPECT_EQ(rgba[3], 128);
  EXPECT_EQ(rgba[7], 0);
  expectIoError([&] { writeImage(dir + "/a.pfm", image, 0.0f, &alpha); }, dir + "/a.pfm",
                "no alpha channel");
}

TEST(ImageIo, PfmRoundTripIsExact) {
  const std::string path = freshDir("pfm") + "/image.pfm";
  const Image image = hdrTestImage();
  writeImage(path, image);
  expectExactlyEqual(readImage(path), image);
  // Little-endian with scale -1, as promised to other tools.
  EXPECT_EQ(readRaw(path).substr(0, 10), "PF\n5 3\n-1\n");
}

TEST(ImageIo, ExtensionIsCaseInsensitive) {
  const std::string path = freshDir("case") + "/image.PfM";
  const Image image = hdrTestImage();
  writeImage(path, image);
  expectExactlyEqual(readImage(path), image);
}

TEST(ImageIo, PngRoundTripWithinQuantisation) {
  const std::string path = freshDir("png") + "/image.png";
  Image image(16, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 16; ++x) image.at(x, y) = vec3(x / 15.0f, y / 3.0f, 0.5f * (x + y) / 18.0f);
  writeImage(path, image);
  const Image back = readImage(path);
  ASSERT_EQ(back.width, 16);
  ASSERT_EQ(back.height, 4);
  // 8-bit sRGB rounds to the nearest level: at most half a level off in the encoded domain.
  for (size_t i = 0; i < image.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(linearToSrgb(back.pixels[i][k]), linearToSrgb(image.pixels[i][k]),
                  0.5f / 255.0f + 1e-5f);
}

TEST(ImageIo, PngAppliesExposureAndClamps) {
  const std::string path = freshDir("png_exposure") + "/image.png";
  Image image(2, 1);
  image.at(0, 0) = vec3(0.25f);  // one stop up: 0.5
  image.at(1, 0) = vec3(3.0f);   // clamps to 1
  writeImage(path, image, 1.0f);
  const Image back = readImage(path);
  EXPECT_NEAR(back.at(0, 0).x, 0.5f, 0.005f);
  EXPECT_FLOAT_EQ(back.at(1, 0).y, 1.0f);
}

TEST(ImageIo, ReadsRadianceHdrAsLinear) {
  const std::string path = freshDir("hdr") + "/image.hdr";
  const float rgb[] = {0.5f, 2.0f, 10.0f, 0.0f, 0.25f, 1.0f};
  ASSERT_TRUE(stbi_write_hdr(path.c_str(), 2, 1, 3, rgb));
  const Image image = readImage(path);
  ASSERT_EQ(image.width, 2);
  for (int i = 0; i < 6; ++i)  // RGBE keeps about 8 bits of mantissa
    EXPECT_NEAR(image.pixels[i / 3][i % 3], rgb[i], 0.01f * rgb[i] + 1e-6f);
}

// Appends a float with its most significant byte first.
void appendBigEndian(std::string& bytes, float value) {
  const uint32_t bits = std::bit_cast<uint32_t>(value);
  for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(char((bits >> shift) & 0xff));
}

TEST(ImageIo, ReadsBigEndianGreyscalePfm) {
  const std::string path = freshDir("pfm_be") + "/grey.pfm";
  // Positive scale = big-endian; the first row in the file is the bottom of the image.
  std::string bytes = "Pf\n2 2\n1.0\n";
  appendBigEndian(bytes, 1.0f);   // bottom-left  (0,1)
  appendBigEndian(bytes, 2.0f);   // bottom-right (1,1)
  appendBigEndian(bytes, 3.0f);   // top-left     (0,0)
  appendBigEndian(bytes, -4.5f);  // top-right    (1,0)
  writeRaw(path, bytes);
  const Image image = readImage(path);
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  EXPECT_EQ(image.at(0, 0), vec3(3.0f));
  EXPECT_EQ(image.at(1, 0), vec3(-4.5f));
  EXPECT_EQ(image.at(0, 1), vec3(1.0f));
  EXPECT_EQ(image.at(1, 1), vec3(2.0f));
}

TEST(ImageIo, MalformedPfmThrowsNamingTheFile) {
  const std::string dir = freshDir("pfm_bad");
  const std::string eightFloats(8 * 4, '\0');
  const struct {
    const char* name;
    std::string bytes;
    const char* reason;
  } cases[] = {
      {"magic.pfm", "P6\n2 2\n255\n" + eightFloats, "not a PFM file"},
      {"empty.pfm", "", "not a PFM file"},
      {"noheight.pfm", "PF\n2\n", "malformed PFM header"},
      {"letters.pfm", "PF\n2x 2\n-1\n" + eightFloats, "malformed PFM header"},
      {"zero.pfm", "PF\n0 2\n-1\n", "invalid PFM size"},
      {"negative.pfm", "PF\n2 -2\n-1\n", "invalid PFM size"},
      {"overflow.pfm", "PF\n99999999999 2\n-1\n", "malformed PFM header"},
      {"scale.pfm", "PF\n1 1\n0\n" + eightFloats, "non-zero scale"},
      {"noscale.pfm", "PF\n1 1\n", "non-zero scale"},
      {"truncated.pfm", "PF\n2 2\n-1\n" + eightFloats.substr(0, 40), "truncated pixel data"},
      {"nodata.pfm", "PF\n2 2\n-1\n", "truncated pixel data"},
      // Would be 4.8e19 bytes: must be rejected from the file size, not attempted.
      {"huge.pfm", "PF\n2000000000 2000000000\n-1\n" + eightFloats, "truncated pixel data"},
      {"hugegrey.pfm", "Pf\n2147483647 2147483647\n1\n" + eightFloats, "truncated pixel data"},
  };
  for (const auto& c : cases) {
    const std::string path = dir + "/" + c.name;
    writeRaw(path, c.bytes);
    expectIoError([&] { readImage(path); }, path, c.reason);
  }
}

TEST(ImageIo, MissingFileThrowsNamingTheFile) {
  const std::string dir = freshDir("missing");
  for (const char* name : {"a.png", "a.exr", "a.pfm", "a.hdr", "a.JPG"}) {
    const std::string path = dir + "/" + name;
    expectIoError([&] { readImage(path); }, path, "cannot open file");
  }
  expectIoError([&] { readExrChannels(dir + "/b.exr"); }, dir + "/b.exr", "cannot open file");
  expectIoError([&] { readImage(dir); }, dir, "");  // a directory is not an image
}

TEST(ImageIo, CorruptFilesThrowInsteadOfCrashing) {
  const std::string dir = freshDir("corrupt");
  const std::string garbage = "this is certainly not an image, but it is long enough to parse";
  for (const char* name : {"g.png", "g.exr", "g.hdr", "g.jpg", "g.bmp"}) {
    writeRaw(dir + "/" + name, garbage);
    expectIoError([&] { readImage(dir + "/" + name); }, dir + "/" + name, "");
  }
  // A valid file cut short, as a crashed writer without atomic rename would leave it.
  writeImage(dir + "/whole.exr", hdrTestImage());
  writeImage(dir + "/whole.png", hdrTestImage());
  for (const char* ext : {".exr", ".png"}) {
    const std::string bytes = readRaw(dir + "/whole" + ext);
    const std::string cut = dir + "/cut" + ext;
    writeRaw(cut, bytes.substr(0, bytes.size() / 2));
    expectIoError([&] { readImage(cut); }, cut, "");
  }
  writeRaw(dir + "/g2.exr", garbage);
  expectIoError([&] { readExrChannels(dir + "/g2.exr"); }, dir + "/g2.exr", "");
}

// A PNG whose header claims 10000x10000 pixels in a file of a hundred bytes is refused before
// the decoder allocates the 300 MB such an image would take (stb_image's own limit is 1 GB).
TEST(ImageIo, PngHeaderAskingForTooManyPixelsIsRefused) {
  const std::string dir = freshDir("png_huge");
  writeImage(dir + "/small.png", hdrTestImage());
  std::ifstream in(dir + "/small.png", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 24u);
  ASSERT_EQ(bytes.substr(12, 4), "IHDR");
  const unsigned char size[8] = {0, 0, 0x27, 0x10, 0, 0, 0x27, 0x10};  // 10000, big-endian
  bytes.replace(16, 8, reinterpret_cast<const char*>(size), 8);
  writeRaw(dir + "/huge.png", bytes);
  expectIoError([&] { readImage(dir + "/huge.png"); }, dir + "/huge.png",
                "10000x10000 pixels are too many for a file of");
}

// A PNG chunk whose length field claims a gigabyte in a small file (the fuzzer's find: stb_image
// grew its buffer to the claimed size first) is refused before stb reads it.
TEST(ImageIo, PngChunkLongerThanTheFileIsRefused) {
  const std::string dir = freshDir("png_chunk");
  const std::vector<uint8_t> png = encodePng8(2, 2, 3, std::vector<uint8_t>(12, 200));
  std::string bytes(png.begin(), png.end());
  const size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  const unsigned char huge[4] = {0x40, 0, 0, 0};  // 2^30, big-endian
  bytes.replace(idat - 4, 4, reinterpret_cast<const char*>(huge), 4);
  writeRaw(dir + "/chunk.png", bytes);
  expectIoError([&] { readImage(dir + "/chunk.png"); }, dir + "/chunk.png",
                "chunk 'IDAT' at byte " + std::to_string(idat - 4) + " claims 1073741824 bytes");
}

// stb_image reads by content: a 16-bit PGM named .png (the fuzzer's find: stb's PNM reader
// returned an 8-bit buffer that the 16-bit path read past) and the other formats stb knows but
// Penumbra does not list are refused by their magic, whatever the extension; an 8-bit PGM too.
TEST(ImageIo, ContentsOfUnlistedFormatsAreRefusedWhateverTheExtension) {
  const std::string dir = freshDir("unlisted");
  const std::string pgm16 = std::string("P5\t22\t22\t1212") + "\xdb\x18";
  const std::string pgm8 = "P5 2 2 255\n" + std::string(4, '\x80');
  const std::string ppm = "P6 1 1 255\n" + std::string(3, '\x80');
  const std::pair<const char*, std::string> cases[] = {{"pgm16.png", pgm16},
                                                       {"pgm8.jpg", pgm8},
                                                       {"ppm.bmp", ppm},
                                                       {"psd.png", "8BPS\x00\x01"},
                                                       {"gif.tga", "GIF89a\x01\x00"}};
  for (const auto& [name, bytes] : cases) {
    const std::string path = dir + "/" + name;
    writeRaw(path, bytes);
    expectIoError([&] { readImage(path); }, path, "which Penumbra does not read");
    expectIoError([&] { readImage8(path); }, path, "which Penumbra does not read");
  }
}

TEST(ImageIo, UnsupportedExtensionListsTheSupportedOnes) {
  const std::string dir = freshDir("ext");
  const Image image(2, 2);
  expectIoError([&] { writeImage(dir + "/a.jpg", image); }, dir + "/a.jpg", ".exr, .pfm, .png");
  expectIoError([&] { writeImage(dir + "/noext", image); }, dir + "/noext", ".exr, .pfm, .png");
  writeRaw(dir + "/a.gif", "GIF89a");
  expectIoError([&] { readImage(dir + "/a.gif"); }, dir + "/a.gif", ".pfm");
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"a.gif"});
}

TEST(ImageIo, EmptyImageIsNotWritten) {
  const std::string dir = freshDir("empty");
  expectIoError([&] { writeImage(dir + "/e.png", Image()); }, dir + "/e.png", "empty image");
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(ImageIo, WriteToMissingDirectoryThrowsAndLeavesNoFile) {
  const std::string dir = freshDir("nodir");
  const Image image = hdrTestImage();
  for (const char* name : {"x.png", "x.exr", "x.pfm"}) {
    const std::string path = dir + "/missing/" + name;
    expectIoError([&] { writeImage(path, image); }, path, "No such file or directory");
  }
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(ImageIo, WriteWhereTheParentIsAFileThrowsAndLeavesNoFile) {
  // Unlike a read-only directory, this fails for root too, so CI (as root) checks it.
  const std::string dir = freshDir("parent_is_file");
  const std::string blocker = dir + "/blocker";
  { std::ofstream(blocker) << "x"; }
  expectIoError([&] { writeImage(blocker + "/x.exr", hdrTestImage()); }, blocker + "/x.exr", "");
  EXPECT_EQ(listDir(dir), (std::vector<std::string>{"blocker"}));
}

TEST(ImageIo, AtomicWritesLeaveNoTemporaries) {
  const std::string dir = freshDir("atomic");
  const Image image = hdrTestImage();
  for (int round = 0; round < 2; ++round) {  // the second round replaces existing files
    writeImage(dir + "/a.exr", image);
    writeImage(dir + "/a.pfm", image);
    writeImage(dir + "/a.png", image);
  }
  writeExrLayers(dir + "/layers.exr", 1, 1, {{"Y", {1.0f}}});
  EXPECT_EQ(listDir(dir), (std::vector<std::string>{"a.exr", "a.pfm", "a.png", "layers.exr"}));
}

TEST(ImageIo, FailedWriteKeepsThePreviousFile) {
  const std::string dir = freshDir("keep");
  const std::string path = dir + "/stats.json";
  writeFileAtomically(path, [](const std::string& tmp) { std::ofstream(tmp) << "old"; });
  EXPECT_THROW(writeFileAtomically(path,
                                   [](const std::string& tmp) {
                                     std::ofstream(tmp) << "half wri";
                                     throw std::runtime_error("disk full");
                                   }),
               std::runtime_error);
  EXPECT_EQ(readRaw(path), "old");
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"stats.json"});
  // The target exists only once the writer has finished.
  writeFileAtomically(dir + "/new.json", [&](const std::string& tmp) {
    EXPECT_FALSE(fs::exists(dir + "/new.json"));
    EXPECT_EQ(fs::path(tmp).parent_path(), fs::path(dir));
    std::ofstream(tmp) << "new";
  });
  EXPECT_EQ(readRaw(dir + "/new.json"), "new");
}

TEST(ImageIo, ExrLayersRoundTrip) {
  const std::string path = freshDir("layers") + "/render.exr";
  const int width = 3, height = 2;
  std::vector<ExrChannel> channels;
  // Deliberately unsorted: the writer must sort them as EXR requires.
  for (const char* name : {"R", "G", "B", "variance.R", "variance.G", "variance.B", "A"}) {
    std::vector<float> values(width * height);
    for (size_t i = 0; i < values.size(); ++i)
      values[i] = float(name[0]) * 0.01f + float(i) * 0.37f - float(std::strlen(name));
    channels.emplace_back(name, values);
  }
  writeExrLayers(path, width, height, channels);

  const std::vector<ExrChannel> back = readExrChannels(path);
  ASSERT_EQ(back.size(), channels.size());
  std::map<std::string, std::vector<float>> byName(back.begin(), back.end());
  for (const auto& [name, values] : channels) EXPECT_EQ(byName[name], values) << name;
  for (size_t i = 1; i < back.size(); ++i) EXPECT_LT(back[i - 1].first, back[i].first);

  // The plain reader sees the colour channels of the same file.
  const Image colour = readImage(path);
  ASSERT_EQ(colour.width, width);
  EXPECT_EQ(colour.at(2, 1).x, byName["R"][5]);
  EXPECT_EQ(colour.at(2, 1).z, byName["B"][5]);
}

TEST(ImageIo, ReadExrChannelsConvertsHalfToFloat) {
  const std::string path = freshDir("half") + "/half.exr";
  // Values exact in half precision, written as a half RGB file.
  const Imf::Rgba pixels[] = {Imf::Rgba(0.5f, 1.25f, -3.0f), Imf::Rgba(1024.0f, 0.0f, 0.125f)};
  {
    Imf::RgbaOutputFile file(path.c_str(), 2, 1, Imf::WRITE_RGB);
    file.setFrameBuffer(pixels, 1, 2);
    file.writePixels(1);
  }
  std::map<std::string, std::vector<float>> byName;
  for (auto& [name, values] : readExrChannels(path)) byName[name] = values;
  EXPECT_EQ(byName["R"], (std::vector<float>{0.5f, 1024.0f}));
  EXPECT_EQ(byName["G"], (std::vector<float>{1.25f, 0.0f}));
  EXPECT_EQ(byName["B"], (std::vector<float>{-3.0f, 0.125f}));
  // The image reader takes R, G, B; a file of one channel reads as grey.
  const Image rgb = readImage(path);
  EXPECT_EQ(rgb.at(1, 0), vec3(1024.0f, 0.0f, 0.125f));
}

// Tiled EXRs (as some compositors write), with partial tiles at the right and bottom edges and
// a data window that does not start at the origin. Pixel (x, y) of the window holds 10 y + x.
TEST(ImageIo, ReadExrChannelsReadsTiledFiles) {
  const std::string path = freshDir("tiled") + "/tiled.exr";
  const int width = 5, height = 3, tileSize = 2;
  std::vector<float> values;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) values.push_back(float(10 * y + x));
  {
    const Imath::Box2i window(Imath::V2i(7, -2), Imath::V2i(7 + width - 1, -2 + height - 1));
    Imf::Header header(window, window);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    header.setTileDescription(Imf::TileDescription(tileSize, tileSize, Imf::ONE_LEVEL));
    Imf::TiledOutputFile file(path.c_str(), header);
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, values.data(), window, sizeof(float),
                                       sizeof(float) * width));
    file.setFrameBuffer(frame);
    file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
  }
  const std::vector<ExrChannel> channels = readExrChannels(path);
  ASSERT_EQ(channels.size(), 1u);
  EXPECT_EQ(channels[0].first, "Y");
  EXPECT_EQ(channels[0].second, values);
  const Image grey = readImage(path);
  ASSERT_EQ(grey.width, width);
  ASSERT_EQ(grey.height, height);
  EXPECT_EQ(grey.at(3, 2), vec3(23.0f));
}

// A header that asks for far more pixels than the file could hold is refused before any
// allocation; so is a file whose channels are not R, G, B when read as an image.
TEST(ImageIo, ExrReaderRefusesImplausibleSizesAndMissingColour) {
  const std::string dir = freshDir("exr_bad");
  {
    const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(60000, 60000));
    Imf::Header header(window, window);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    header.compression() = Imf::ZIP_COMPRESSION;
    // Only the header and offsets are written: the file is a few hundred kilobytes.
    Imf::OutputFile file((dir + "/huge.exr").c_str(), header);
  }
  expectIoError([&] { readExrChannels(dir + "/huge.exr"); }, dir + "/huge.exr",
                "too large for a file of");
  // A file cut short inside its offset table: the header's window needs more chunks than
  // the rest of the file can list.
  writeExrLayers(dir + "/tall.exr", 1, 4096, {{"Y", std::vector<float>(4096, 0.5f)}});
  fs::resize_file(dir + "/tall.exr", 600);
  expectIoError([&] { readExrChannels(dir + "/tall.exr"); }, dir + "/tall.exr",
                "truncated or damaged: its 1x4096 data window needs 256 chunks");
  writeExrLayers(dir + "/two.exr", 1, 1, {{"depth", {1.0f}}, {"alpha", {1.0f}}});
  expectIoError([&] { readImage(dir + "/two.exr"); }, dir + "/two.exr",
                "no R, G, B channels to read as an image (it has alpha, depth)");
}

TEST(ImageIo, ExrLayersRejectsBadChannels) {
  const std::string dir = freshDir("layers_bad");
  const std::string path = dir + "/bad.exr";
  expectIoError([&] { writeExrLayers(path, 2, 1, {{"R", {1.0f}}}); }, path, "expected 2");
  expectIoError(
      [&] {
        writeExrLayers(path, 1, 1, {{"R", {1.0f}}, {"R", {2.0f}}});
      },
      path, "duplicate");
  expectIoError([&] { writeExrLayers(path, 1, 1, {{"", {1.0f}}}); }, path, "channel name");
  expectIoError([&] { writeExrLayers(path, 1, 1, {}); }, path, "without channels");
  EXPECT_TRUE(listDir(dir).empty());
}

}  // namespace
}  // namespace penumbra
