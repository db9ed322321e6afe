// The viewer's first preview and the chaining of methods: blocks are flat and traced at their
// centre, and a chain runs the preview then the real method to the same final image.
#include "engine/preview.h"

#include "engine/bp_method.h"
#include "engine/integrator.h"
#include "engine/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

std::unique_ptr<PreparedScene> cornell(int size) { return test::shippedScene("cornell", size); }

TEST(Preview, OneRoundOfFlatBlocks) {
  auto prepared = cornell(20);
  auto preview = makePreviewMethod(*prepared, 1, 8);
  EXPECT_FALSE(preview->done());
  preview->runRound(nullptr);
  EXPECT_TRUE(preview->done());
  const auto snap = preview->snapshot();
  EXPECT_EQ(snap->method, "preview");
  ASSERT_EQ(snap->raw.width, 20);
  // Blocks of 8 (the last ones clipped to 4): every pixel of a block has the block's value.
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      EXPECT_EQ(snap->raw.at(x, y), snap->raw.at(x / 8 * 8, y / 8 * 8)) << x << "," << y;
  // 3 x 3 blocks, one camera path each (plus its bounce and shadow rays).
  EXPECT_GE(snap->rays, 9u);
  bool lit = false;
  for (const vec3& c : snap->raw.pixels) lit = lit || c.x > 0;
  EXPECT_TRUE(lit);
}

TEST(Preview, ChainRunsThePreviewThenTheMethodToTheSameImage) {
  auto prepared = cornell(12);
  BpConfig config;
  config.spp = 8;
  config.seed = 4;
  config.network.epochs = 10;
  auto chain = chainMethods(makePreviewMethod(*prepared, 4, 4),
                            [&] { return makeBpMethod(*prepared, config); });
  chain->runRound(nullptr);
  EXPECT_EQ(chain->snapshot()->method, "preview");
  EXPECT_FALSE(chain->done());
  while (!chain->done()) chain->runRound(nullptr);
  const auto chained = chain->snapshot();
  EXPECT_EQ(chained->method, "bp");

  auto plain = makeBpMethod(*prepared, config);
  while (!plain->done()) plain->runRound(nullptr);
  const auto direct = plain->snapshot();
  EXPECT_EQ(chain->roundsDone(), plain->roundsDone() + 1);
  EXPECT_EQ(chained->reconstructed.pixels, direct->reconstructed.pixels);
}

TEST(PrepareView, SharesTheBvhAndRendersTheNewCamera) {
  auto prepared = cornell(8);
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
