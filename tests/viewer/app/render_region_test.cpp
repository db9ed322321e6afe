// The viewer's render region: only the region's pixels are rendered (the method's image is the
// region's size), they land where they belong in the shown image, the rest shows the last full
// picture dimmed, maps and the inspector follow the region, and clearing it renders all again.
// No GL is needed.
#include "viewer/app/view_app.h"

#include "methods/ld/ld.h"
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace penumbra {
namespace {

ViewOptions cornell() {
  ViewOptions o;
  Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.json");
  scene.settings.width = 32;
  scene.settings.height = 24;
  o.scene = prepareScene(std::move(scene));
  o.method = &ldMethod();
  o.threads = 1;
  o.preview = false;
  o.rounds = 2;
  return o;
}

// Waits (at most 20 s) for a round of the current view: a snapshot other than the one shown
// before the last restart.
void waitForRound(ViewerApp& app) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  const auto old = app.snapshot();
  while (std::chrono::steady_clock::now() < end) {
    app.update();
    if (app.roundShown() && app.snapshot() != old) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  FAIL() << "no round within 20 s";
}

TEST(RenderRegion, OnlyTheRegionRendersAndTheRestIsTheLastPictureDimmed) {
  // The sample counts' overlay is shown: the snapshots carry the maps.
  ViewOptions options = cornell();
  options.overlay = maps::SampleCount;
  ViewerApp app(options);
  waitForRound(app);
  // What the viewer shows (the reconstruction; raw when there is none) stays, dimmed.
  const Image before = shownImage(*app.snapshot(), app.options());
  ASSERT_EQ(before.width, 32);

  app.setRegion({10, 6, 8, 5});
  waitForRound(app);
  const auto snap = app.snapshot();
  ASSERT_EQ(snap->width, 32);
  ASSERT_EQ(snap->height, 24);
  int inside = 0, changedInside = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      const vec3 now = shownImage(*snap, app.options()).at(x, y), was = before.at(x, y);
      if (x >= 10 && x < 18 && y >= 6 && y < 11) {
        ++inside;
        changedInside += now != 0.35f * was;
      } else {
        EXPECT_EQ(now, 0.35f * was) << x << "," << y;
      }
    }
  EXPECT_EQ(inside, 40);
  EXPECT_GT(changedInside, 30) << "the region's pixels are rendered, not dimmed";
  // Sample counts exist inside the region only.
  const SnapshotMap* samples = snap->map(maps::SampleCount);
  ASSERT_NE(samples, nullptr);
  EXPECT_EQ(samples->values.size(), size_t(32 * 24));
  EXPECT_GT(samples->values[size_t(8 * 32 + 12)], 0.0f);
  EXPECT_EQ(samples->values[size_t(2 * 32 + 2)], 0.0f);

  app.inspectPixel(1, 1);
  EXPECT_NE(app.lastMessage().find("outside the render region"), std::string::npos);

  app.setRegion({});
  waitForRound(app);
  EXPECT_EQ(app.snapshot()->width, 32);
  EXPECT_GT(app.snapshot()->map(maps::SampleCount)->values[size_t(2 * 32 + 2)], 0.0f);
}

TEST(RenderRegion, ARegionIsClampedToTheImage) {
  ViewerApp app(cornell());
  app.setRegion({28, 20, 10, 10});
  EXPECT_EQ(app.viewState().region, (RenderRegion{28, 20, 4, 4}));
  app.setRegion({40, 0, 5, 5});  // wholly outside: none
  EXPECT_FALSE(app.viewState().region.active());
}

}  // namespace
}  // namespace penumbra
