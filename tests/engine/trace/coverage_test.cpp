// The alpha of a transparent render: which share of each pixel the scene covers.
#include "trace/coverage.h"
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

TEST(Coverage, SharesOfThePixelThatHitTheScene) {
  // A square of side 2 at distance 5 seen through a 8 x 8 image spanning 4 x 4 units (fov
  // 2 atan(0.4)): the middle 4 x 4 pixels are covered, the rest not; the square's edges fall
  // on pixel edges, so every alpha is 0 or 1. Moved by a quarter pixel, the edge columns
  // are covered by 3/4 (or 1/4).
  const std::string json = R"({
    "render": {"width": 8, "height": 8},
    "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "fov": 43.602818},
    "materials": {"m": {"type": "diffuse"}},
    "objects": [{"shape": "rectangle", "size": [2, 2], "material": "m",
                 "transform": {"rotate": [90, 1, 0, 0], "translate": [OFFSET, 0, 0]}}]})";
  auto withOffset = [&](const char* offset) {
    std::string text = json;
    text.replace(text.find("OFFSET"), 6, offset);
    return prepareScene(parseSceneJson(text, "coverage.json", "."));
  };
  const auto centred = cameraCoverage(*withOffset("0"));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool inside = x >= 2 && x < 6 && y >= 2 && y < 6;
      EXPECT_EQ(centred[size_t(y * 8 + x)], inside ? 1.0f : 0.0f) << x << "," << y;
    }
  const auto moved = cameraCoverage(*withOffset("0.125"));  // a quarter pixel to the right
  EXPECT_FLOAT_EQ(moved[size_t(3 * 8 + 2)], 0.75f);
  EXPECT_FLOAT_EQ(moved[size_t(3 * 8 + 6)], 0.25f);
  EXPECT_FLOAT_EQ(moved[size_t(3 * 8 + 4)], 1.0f);
}

}  // namespace
}  // namespace penumbra
