// Shards of a plain LD render (methods/shard.h): the tiles of N shards cover the image once,
// and each shard's pixels are the unsharded render's bit for bit, whatever the thread count.
#include "methods/shard.h"

#include "methods/render.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

namespace penumbra {
namespace {

TEST(Shard, ParsesKOfNCountedFromZero) {
  const Shard s = parseShard("2/5");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  EXPECT_TRUE(parseShard("0/1").whole());
  for (const char* bad : {"5/5", "-1/3", "1", "1/0", "a/3", "1/3x", "", "1/70000"})
    EXPECT_THROW(parseShard(bad), std::invalid_argument) << bad;
}

TEST(Shard, TheShardsTilesCoverTheImageOnce) {
  // 100 x 70: 4 x 3 tiles of 32, the last row and column cut short.
  for (int count : {1, 2, 5, 12, 13}) {
    std::vector<int> covered(100 * 70, 0);
    std::set<int> tiles;
    for (int k = 0; k < count; ++k) {
      const std::vector<uint8_t> mask = shardPixelMask(100, 70, {k, count});
      for (size_t p = 0; p < mask.size(); ++p) covered[p] += mask[p];
      for (int t : shardTiles(100, 70, {k, count})) EXPECT_TRUE(tiles.insert(t).second);
    }
    for (size_t p = 0; p < covered.size(); ++p) ASSERT_EQ(covered[p], 1) << count << ": " << p;
    EXPECT_EQ(tiles.size(), 12u);
  }
  // Shard k of n owns tiles k, k + n, ...: shard 1 of 5 has tiles 1, 6 and 11.
  EXPECT_EQ(shardTiles(100, 70, {1, 5}), (std::vector<int>{1, 6, 11}));
}

TEST(Shard, MergedShardsAreTheUnshardedRenderBitForBit) {
  Scene scene = loadScene(test::sourcePath("scenes/balls.json"));
  scene.settings.width = 70;
  scene.settings.height = 40;
  const auto prepared = prepareScene(std::move(scene));
  RenderOptions options;
  options.spp = 8;
  options.seed = 5;
  const RenderResult whole = renderImage(*prepared, options);
  for (int count : {2, 3}) {
    Image image(70, 40), variance(70, 40);
    for (int k = 0; k < count; ++k) {
      RenderOptions part = options;
      part.threads = 1 + k % 2;  // the thread count must not matter
      part.pixelMask = shardPixelMask(70, 40, {k, count});
      const RenderResult r = renderImage(*prepared, part);
      // Pixels of other shards are not rendered: zero, with zero variance.
      for (size_t p = 0; p < part.pixelMask.size(); ++p)
        if (!part.pixelMask[p]) {
          ASSERT_EQ(r.image.pixels[p], vec3(0.0f));
          ASSERT_EQ(r.varianceOfMean.pixels[p], vec3(0.0f));
        }
      copyShardPixels(r.image, {k, count}, image);
      copyShardPixels(r.varianceOfMean, {k, count}, variance);
    }
    EXPECT_EQ(image.pixels, whole.image.pixels) << count << " shards";
    EXPECT_EQ(variance.pixels, whole.varianceOfMean.pixels) << count << " shards";
  }
}

}  // namespace
}  // namespace penumbra
