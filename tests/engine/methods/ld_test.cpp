// The low-discrepancy method in rounds: the same image as a one-shot render.
#include "methods/ld.h"

#include "methods/render.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method) {
  while (!method.done()) method.runRound(nullptr);
  return method.snapshot();
}

TEST(LdMethod, FinalImageEqualsRenderImage) {
  auto prepared = test::shippedScene("cornell", 16);
  LdConfig config;
  config.spp = 8;
  config.seed = 3;
  config.roundSpp = 3;  // rounds of 3, 3, 2 samples
  auto method = makeLdMethod(*prepared, config);
  const auto snap = runToEnd(*method);
  EXPECT_EQ(snap->round, 3);
  RenderOptions options;
  options.spp = 8;
  options.seed = 3;
  const RenderResult direct = renderImage(*prepared, options);
  EXPECT_EQ(snap->raw.pixels, direct.image.pixels);
  EXPECT_EQ(snap->rays, direct.rays);
}

}  // namespace
}  // namespace penumbra
