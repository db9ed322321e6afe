#include "core/large_pages.h"

#include <gtest/gtest.h>

#include <cstring>

namespace penumbra {
namespace {

constexpr size_t kMiB = size_t(1) << 20;

TEST(LargePages, AFreedBlockIsReusedForTheSameSizeAndItsValuesAreFreshlyInitialised) {
  returnFreedMemory();
  const void* first;
  {
    LargeVector<float> plane(kLargePageBytes, 7.0f);  // 8 MiB
    first = plane.data();
    EXPECT_EQ(reinterpret_cast<uintptr_t>(first) % kLargePageBytes, 0u);
  }
  EXPECT_EQ(largeBlockBytes().kept, 8 * kMiB);
  LargeVector<float> again(kLargePageBytes);
  EXPECT_EQ(again.data(), first);  // the kept block, not a new mapping
  EXPECT_EQ(largeBlockBytes().kept, 0u);
  for (size_t i = 0; i < again.size(); i += 4099) ASSERT_EQ(again[i], 0.0f) << i;
  returnFreedMemory();
}

TEST(LargePages, KeptBlocksNeverRaiseTheMappedBytesAboveTheMostInUse) {
  returnFreedMemory();
  const size_t base = largeBlockBytes().inUse;  // whatever other tests still hold
  { LargeVector<char> a(4 * kMiB), b(4 * kMiB), c(4 * kMiB); }
  LargeBlockBytes now = largeBlockBytes();
  EXPECT_EQ(now.kept, 12 * kMiB);
  EXPECT_EQ(now.mostInUse, base + 12 * kMiB);
  {
    // A size not kept: two of the kept 4 MiB blocks go so that in use plus kept stays
    // within 12 MiB; the third stays.
    LargeVector<char> d(8 * kMiB);
    now = largeBlockBytes();
    EXPECT_EQ(now.inUse, base + 8 * kMiB);
    EXPECT_EQ(now.kept, 4 * kMiB);
    EXPECT_LE(now.inUse + now.kept, now.mostInUse);
  }
  // A block larger than everything at once raises the most in use and drops every kept block.
  {
    LargeVector<char> e(20 * kMiB);
    now = largeBlockBytes();
    EXPECT_EQ(now.kept, 0u);
    EXPECT_EQ(now.mostInUse, base + 20 * kMiB);
  }
  returnFreedMemory();
  now = largeBlockBytes();
  EXPECT_EQ(now.kept, 0u);
  EXPECT_EQ(now.mostInUse, now.inUse);
}

TEST(LargePages, SmallBlocksComeFromMallocAndAreNotKept) {
  returnFreedMemory();
  { LargeVector<char> small(kLargePageBytes - 1, 'x'); }
  EXPECT_EQ(largeBlockBytes().kept, 0u);
}

}  // namespace
}  // namespace penumbra
