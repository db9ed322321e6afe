// The first-hit features and the directly seen emission a camera path records: they leave the
// radiance and the random stream exactly as they are, and say what the camera saw.
#include "trace/integrator.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cstring>

namespace penumbra {
namespace {

TEST(PathFeatures, RecordingThemChangesNoRadianceAndConsumesNoRandomNumbers) {
  auto prepared = test::shippedScene("cornell", 16);
  PixelSampler plain(SamplerKind::LowDiscrepancy, 5, 8),
      recorded(SamplerKind::LowDiscrepancy, 5, 8);
  PathCounters a, b;
  int emitterPixels = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (uint32_t i = 0; i < 8; ++i) {
        plain.startSample(x, y, i);
        recorded.startSample(x, y, i);
        const vec3 l1 = traceRadiance(*prepared, plain.cameraSample(false, false), plain, a);
        PathFeatures f;
        const vec3 l2 =
            traceRadiance(*prepared, recorded.cameraSample(false, false), recorded, b, &f);
        ASSERT_EQ(std::memcmp(&l1, &l2, sizeof l1), 0) << x << "," << y << " sample " << i;
        ASSERT_EQ(plain.next1D(), recorded.next1D());  // the stream is where it was
        // Cornell is closed: every camera ray hits a diffuse surface.
        EXPECT_NEAR(glm::length(f.normal), 1.0f, 1e-3f);
        EXPECT_GT(f.depth, 0.0f);
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(f.albedo[k], 0.0f);
          EXPECT_LE(f.albedo[k], 1.0f);
          EXPECT_GE(f.emission[k], 0.0f);
          EXPECT_LE(f.emission[k], l2[k] * (1 + 1e-5f) + 1e-6f);  // a part of the radiance
        }
        if (f.emission.x > 0) ++emitterPixels;
      }
  EXPECT_EQ(a.rays, b.rays);
  EXPECT_GT(emitterPixels, 0);  // the ceiling light is seen directly
}

}  // namespace
}  // namespace penumbra
