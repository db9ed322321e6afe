// Ray query tests on Embree, including motion blur: a moving sphere is hit where it is
// at the ray's time.
#include "trace/accel.h"
#include "scene/scene_loader.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(Accel, MovingSphereIsHitWhereItIsAtTheRaysTime) {
  const Scene scene = parseSceneJson(R"({
    "materials": {"m": {"type": "diffuse"}},
    "objects": [{"shape": "sphere", "radius": 0.5, "material": "m",
                 "motion": {"translate": [3, 0, 0]}}]})",
                                     "moving.json", ".");
  Accel accel(scene);
  Hit hit;
  // A ray down the z axis through x = 0 meets the sphere at t=0 only; through x = 1.5,
  // only half way through the shutter; through x = 3, at the end.
  auto hits = [&](float x, float time) {
    return accel.intersect(Ray{vec3(x, 0, 5), vec3(0, 0, -1), time}, 0.0f, 100.0f, hit);
  };
  EXPECT_TRUE(hits(0, 0));
  EXPECT_NEAR(hit.t, 4.5f, 1e-2f);
  EXPECT_FALSE(hits(0, 1));
  EXPECT_TRUE(hits(1.5f, 0.5f));
  EXPECT_FALSE(hits(1.5f, 0.0f));
  EXPECT_TRUE(hits(3, 1));
  EXPECT_TRUE(accel.occluded(Ray{vec3(0, 0, 5), vec3(0, 0, -1), 0.0f}, 0.0f, 100.0f));
  EXPECT_FALSE(accel.occluded(Ray{vec3(0, 0, 5), vec3(0, 0, -1), 0.0f}, 0.0f, 4.0f));
}

}  // namespace
}  // namespace penumbra
