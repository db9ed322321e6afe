// The window's frame pacing (app/window.h): with the renderer at work, frames keep to about a
// third of the time, within 30 and 5 a second while the user acts and at most 4 a second for
// new pictures alone; with it idle, 60 a second. And the resident memory the soak reads.
#include "viewer/app/window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

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

TEST(WindowPacing, ThePeakResidentMemoryFollowsAnAllocation) {
  // The resident memory is read before the peak each time: the peak only ever rises, so it is
  // at least what was resident a moment earlier (other threads, ASan's own, may add pages in
  // between, so the other order could see more resident than the peak read before it).
  const long long residentBefore = residentKiB();
  const long long before = peakResidentKiB();
  EXPECT_GE(before, residentBefore) << "the peak is at least what was resident";
  // A block that takes the resident memory 64 MB past the earlier peak, touched (VmHWM counts
  // touched pages): the peak must rise by about 64 MB.
  const long long gapKiB = std::max(0LL, before - residentBefore);
  const size_t bytes = size_t(gapKiB + (64 << 10)) << 10;
  std::vector<char> block(bytes, 1);
  const long long residentAfter = residentKiB();
  const long long after = peakResidentKiB();
  EXPECT_GE(after, residentAfter);
  EXPECT_GE(after - before, 32 << 10) << before << " -> " << after;
  EXPECT_EQ(block[bytes / 2], 1);
}

}  // namespace
}  // namespace penumbra
