// The window's frame pacing (app/window.h): with the renderer at work, frames keep to about a
// third of the time, within 30 and 5 a second while the user acts and at most 4 a second for
// new pictures alone; with it idle, 60 a second. And the resident memory the soak reads.
#include "viewer/app/window.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(WindowPacing, FramesTakeAThirdOfTheTimeWhileTheRendererWorks) {
  // A fast frame (a real GPU): 30 a second while acting, 4 with new pictures alone.
  EXPECT_DOUBLE_EQ(framePacing(true, true, 0.002), 1.0 / 30);
  EXPECT_DOUBLE_EQ(framePacing(true, false, 0.002), 0.25);
  // A slow one (llvmpipe): three times its cost apart.
  EXPECT_DOUBLE_EQ(framePacing(true, true, 0.05), 0.15);
  EXPECT_DOUBLE_EQ(framePacing(true, false, 0.1), 0.3);
  // A very slow one (the first, compiling shaders) holds input back at most 0.2 s.
  EXPECT_DOUBLE_EQ(framePacing(true, true, 2.0), 0.2);
  // Nothing to render: 60 a second.
  EXPECT_DOUBLE_EQ(framePacing(false, true, 0.05), 1.0 / 60);
  EXPECT_DOUBLE_EQ(framePacing(false, false, 2.0), 1.0 / 60);
}

TEST(WindowPacing, ReadsTheResidentMemory) {
  const long long kib = residentKiB();
  EXPECT_GT(kib, 1000) << "a test process holds more than a megabyte";
  EXPECT_LT(kib, 64LL << 20);
}

}  // namespace
}  // namespace penumbra
