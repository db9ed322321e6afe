// Splitting a plain low-discrepancy render across processes (a job array on a farm) by tile.
// Every pixel draws the same samples from its own stream whichever process renders it, so the
// pixels of shard K are those of the unsharded render, bit for bit, and merging the shards'
// pixels back gives the unsharded image exactly. The image is cut into kShardTile x kShardTile
// tiles in row-major order, and tile t belongs to shard t mod N: a fixed assignment that needs
// no coordinator and spreads the expensive parts of a picture over the shards.
#pragma once

#include "core/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

constexpr int kShardTile = 32;

struct Shard {
  int index = 0;  // 0 .. count - 1 (a job array's task id)
  int count = 1;
  bool whole() const { return count == 1; }
};

// "K/N" with 0 <= K < N <= 65536; throws std::invalid_argument with a message saying why.
Shard parseShard(const std::string& text);

// The tiles (row-major indices) of `shard` in a width x height image.
std::vector<int> shardTiles(int width, int height, Shard shard);
// Per pixel (row-major): 1 where `shard` renders it.
std::vector<uint8_t> shardPixelMask(int width, int height, Shard shard);
// Copies the pixels `shard` renders from `part` into `image` (same size).
void copyShardPixels(const Image& part, Shard shard, Image& image);

}  // namespace penumbra
