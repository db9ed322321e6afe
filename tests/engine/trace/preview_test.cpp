// The viewer's first preview after a camera move, and views that share the BVH.
#include "trace/preview.h"

#include "scene/scene.h"
#include "tests/test_paths.h"
#include "trace/integrator.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(Preview, FlatBlocksTracedAtTheirCentres) {
  auto prepared = test::shippedScene("cornell", 20);
  const Image preview = renderPreview(*prepared, 1, 8);
  ASSERT_EQ(preview.width, 20);
  ASSERT_EQ(preview.height, 20);
  // Blocks of 8 (the last ones clipped to 4): every pixel of a block has the block's value.
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      EXPECT_EQ(preview.at(x, y), preview.at(x / 8 * 8, y / 8 * 8)) << x << "," << y;
  bool lit = false;
  for (const vec3& c : preview.pixels) lit = lit || c.x > 0;
  EXPECT_TRUE(lit);
  // Deterministic for a seed; block 1 is one path per pixel.
  EXPECT_EQ(renderPreview(*prepared, 1, 8).pixels, preview.pixels);
  EXPECT_EQ(renderPreview(*prepared, 1, 1).width, 20);
}

TEST(PrepareView, SharesTheBvhAndRendersTheNewCamera) {
  auto prepared = test::shippedScene("cornell", 8);
  Camera moved = prepared->scene.camera;
  moved.eye += vec3(0.1f, 0.0f, 0.0f);
  auto view = prepareView(*prepared, moved);
  EXPECT_EQ(view->accel, prepared->accel);
  EXPECT_EQ(view->scene.camera.eye, moved.eye);
  EXPECT_NE(view->camera.eye, prepared->camera.eye);
  Camera broken = moved;
  broken.lookAt = broken.eye;
  EXPECT_THROW(prepareView(*prepared, broken), SceneError);
}

}  // namespace
}  // namespace penumbra
