#include "methods/shard.h"

#include <charconv>
#include <stdexcept>

namespace penumbra {

namespace {
int tilesAcross(int size) { return (size + kShardTile - 1) / kShardTile; }

bool parseInt(const std::string& text, int& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(text.data(), end, value);
  return error == std::errc() && ptr == end;
}
}  // namespace

Shard parseShard(const std::string& text) {
  const size_t slash = text.find('/');
  Shard s;
  if (slash == std::string::npos || !parseInt(text.substr(0, slash), s.index) ||
      !parseInt(text.substr(slash + 1), s.count))
    throw std::invalid_argument("expected K/N (shard K of N, counted from 0), got '" + text + "'");
  if (!(s.count >= 1 && s.count <= 65536))
    throw std::invalid_argument("the shard count must be between 1 and 65536, got '" + text + "'");
  if (!(s.index >= 0 && s.index < s.count))
    throw std::invalid_argument("the shard must be between 0 and " + std::to_string(s.count - 1) +
                                " (counted from 0), got '" + text + "'");
  return s;
}

std::vector<int> shardTiles(int width, int height, Shard shard) {
  std::vector<int> tiles;
  const int count = tilesAcross(width) * tilesAcross(height);
  for (int t = shard.index; t < count; t += shard.count) tiles.push_back(t);
  return tiles;
}

std::vector<uint8_t> shardPixelMask(int width, int height, Shard shard) {
  std::vector<uint8_t> mask(size_t(width) * size_t(height), 0);
  const int across = tilesAcross(width);
  for (int t : shardTiles(width, height, shard)) {
    const int x0 = (t % across) * kShardTile, y0 = (t / across) * kShardTile;
    for (int y = y0; y < std::min(height, y0 + kShardTile); ++y)
      for (int x = x0; x < std::min(width, x0 + kShardTile); ++x)
        mask[size_t(y) * size_t(width) + size_t(x)] = 1;
  }
  return mask;
}

void copyShardPixels(const Image& part, Shard shard, Image& image) {
  if (part.width != image.width || part.height != image.height)
    throw std::invalid_argument("copyShardPixels: the part is not the image's size");
  const std::vector<uint8_t> mask = shardPixelMask(image.width, image.height, shard);
  for (size_t p = 0; p < mask.size(); ++p)
    if (mask[p]) image.pixels[p] = part.pixels[p];
}

}  // namespace penumbra
