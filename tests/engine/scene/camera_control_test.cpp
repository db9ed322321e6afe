// Camera moves of the viewer: orbit keeps the distance and never flips, pan and fly move eye
// and look-at together, dolly scales the distance.
#include "scene/camera_control.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>

namespace penumbra {
namespace {

Camera start() {
  Camera c;
  c.eye = vec3(0, 1, 5);
  c.lookAt = vec3(0, 1, 0);
  c.vfovDegrees = 40.0f;
  return c;
}

constexpr float kCameraTolerance = 1e-4f;
using test::expectNear;

TEST(CameraControl, OrbitKeepsDistanceAndLookAt) {
  const Camera c = orbitCamera(start(), float(M_PI) / 2, 0.0f);
  expectNear(c.lookAt, vec3(0, 1, 0), kCameraTolerance);
  EXPECT_NEAR(glm::length(c.eye - c.lookAt), 5.0f, 1e-4f);
  expectNear(c.eye, vec3(5, 1, 0), kCameraTolerance);  // a quarter turn about +y takes +z to +x
  const Camera up = orbitCamera(start(), 0.0f, 0.3f);
  EXPECT_GT(up.eye.y, 1.0f);
  EXPECT_NEAR(glm::length(up.eye - up.lookAt), 5.0f, 1e-4f);
}

TEST(CameraControl, OrbitStopsShortOfThePoles) {
  const Camera top = orbitCamera(start(), 0.0f, 10.0f);
  const vec3 dir = glm::normalize(top.eye - top.lookAt);
  EXPECT_LT(dir.y, 1.0f);
  EXPECT_GT(dir.y, 0.99f);
  EXPECT_GT(glm::length(glm::cross(dir, vec3(0, 1, 0))), 1e-3f);  // still a valid camera
  const Camera bottom = orbitCamera(start(), 0.0f, -10.0f);
  EXPECT_LT(glm::normalize(bottom.eye - bottom.lookAt).y, -0.99f);
}

TEST(CameraControl, PanMovesBothPointsInTheViewPlane) {
  const Camera c = panCamera(start(), 0.1f, 0.0f);
  const vec3 move = c.eye - start().eye;
  expectNear(c.lookAt - start().lookAt, move, kCameraTolerance);
  EXPECT_NEAR(move.z, 0.0f, 1e-5f);  // perpendicular to the view direction (-z)
  // A drag to the right moves the camera left by 0.1 view heights at distance 5.
  const float viewHeight = 2.0f * 5.0f * std::tan(20.0f * float(M_PI) / 180.0f);
  EXPECT_NEAR(move.x, -0.1f * viewHeight, 1e-4f);
  const Camera down = panCamera(start(), 0.0f, 0.1f);
  EXPECT_GT(down.eye.y, start().eye.y);
}

TEST(CameraControl, DollyScalesTheDistanceAndNeverReachesZero) {
  const Camera closer = dollyCamera(start(), 0.5f);
  EXPECT_NEAR(glm::length(closer.eye - closer.lookAt), 2.5f, 1e-4f);
  expectNear(closer.lookAt, start().lookAt, kCameraTolerance);
  const Camera tiny = dollyCamera(start(), 0.0f);  // ignored
  EXPECT_NEAR(glm::length(tiny.eye - tiny.lookAt), 5.0f, 1e-4f);
  const Camera floor = dollyCamera(start(), 1e-9f);
  EXPECT_GT(glm::length(floor.eye - floor.lookAt), 0.0f);
}

TEST(CameraControl, AnOrthographicViewZoomsByItsHeightAndPansByIt) {
  Camera ortho = start();
  ortho.orthographicHeight = 4.0f;
  const Camera closer = dollyCamera(ortho, 0.5f);
  EXPECT_NEAR(closer.orthographicHeight, 2.0f, 1e-6f);
  expectNear(closer.eye, ortho.eye, kCameraTolerance);
  // A drag to the right by 0.1 of the window moves the camera left by 0.1 of the view's height.
  const Camera moved = panCamera(ortho, 0.1f, 0.0f);
  EXPECT_NEAR(moved.eye.x - ortho.eye.x, -0.4f, 1e-5f);
}

TEST(CameraControl, FlyMovesAlongTheCameraAxes) {
  const Camera c = flyCamera(start(), 0.0f, 0.0f, 1.0f);  // forward is -z
  expectNear(c.eye, vec3(0, 1, 4), kCameraTolerance);
  expectNear(c.lookAt, vec3(0, 1, -1), kCameraTolerance);
  const Camera r = flyCamera(start(), 2.0f, 0.0f, 0.0f);
  expectNear(r.eye, vec3(2, 1, 5), kCameraTolerance);
}

}  // namespace
}  // namespace penumbra
