// Camera tests: pinhole rays start at the eye; thin-lens rays through one film point
// meet on the focus plane; orthographic rays run parallel from the plane through the eye; the
// shutter maps sample time to scene time.
#include "scene/camera.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <limits>
#include <stdexcept>

namespace penumbra {
namespace {

Camera testCamera() {
  Camera c;
  c.eye = vec3(1, 2, 3);
  c.lookAt = vec3(0, 0, -2);
  c.up = vec3(0, 1, 0);
  c.vfovDegrees = 50;
  return c;
}

TEST(Camera, PinholeRaysStartAtTheEyeAndCentreLooksForward) {
  const Camera c = testCamera();
  const CameraFrame f = makeCameraFrame(c, 64, 48);
  for (float lu : {0.1f, 0.5f, 0.9f}) {
    CameraSample s{12.3f, 40.1f, lu, 1 - lu, 0.3f};
    const Ray r = generateRay(f, s);
    EXPECT_NEAR(glm::length(r.origin - c.eye), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(r.direction), 1.0f, 1e-5f);
  }
  const Ray centre = generateRay(f, CameraSample{32, 24, 0.3f, 0.7f, 0});
  EXPECT_NEAR(glm::length(centre.direction - glm::normalize(c.lookAt - c.eye)), 0.0f, 1e-5f);
  // The top edge of the image is half the vertical fov above the view axis.
  const Ray top = generateRay(f, CameraSample{32, 0, 0.5f, 0.5f, 0});
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(top.direction, centre.direction))), 25.0f, 1e-3f);
  EXPECT_GT(glm::dot(top.direction, f.upAxis), 0.0f);
}

TEST(Camera, ThinLensRaysConvergeOnTheFocusPlane) {
  Camera c = testCamera();
  c.lensRadius = 0.2f;
  c.focusDistance = 4.0f;
  const CameraFrame f = makeCameraFrame(c, 64, 64);
  for (auto [x, y] : {std::pair{5.5f, 7.25f}, std::pair{32.0f, 32.0f}, std::pair{60.0f, 2.0f}}) {
    vec3 meeting(0.0f);
    bool first = true;
    float spread = 0;
    for (float u : {0.05f, 0.3f, 0.6f, 0.95f})
      for (float v : {0.1f, 0.5f, 0.9f}) {
        const Ray r = generateRay(f, CameraSample{x, y, u, v, 0});
        // Advance to the plane at distance focusDistance along the view axis.
        const float t = (c.focusDistance - glm::dot(r.origin - c.eye, f.forward)) /
                        glm::dot(r.direction, f.forward);
        const vec3 p = r.origin + t * r.direction;
        if (first) meeting = p, first = false;
        spread = std::max(spread, glm::length(p - meeting));
        EXPECT_LE(glm::length(r.origin - c.eye), c.lensRadius + 1e-5f);
      }
    EXPECT_LT(spread, 1e-4f) << "film point " << x << "," << y;
  }
  // Points off the focus plane are blurred: rays spread at half the focus distance.
  const Ray a = generateRay(f, CameraSample{32, 32, 0.05f, 0.5f, 0});
  const Ray b = generateRay(f, CameraSample{32, 32, 0.95f, 0.5f, 0});
  const vec3 pa = a.origin + 2.0f / glm::dot(a.direction, f.forward) * a.direction;
  const vec3 pb = b.origin + 2.0f / glm::dot(b.direction, f.forward) * b.direction;
  EXPECT_GT(glm::length(pa - pb), 0.1f);
}

TEST(Camera, FocusDistanceDefaultsToLookAt) {
  Camera c = testCamera();
  c.lensRadius = 0.5f;
  const CameraFrame f = makeCameraFrame(c, 32, 32);
  EXPECT_NEAR(f.focusDistance, glm::length(c.lookAt - c.eye), 1e-5f);
}

TEST(Camera, ShutterMapsSampleTimeToSceneTime) {
  Camera c = testCamera();
  c.shutterOpen = 0.25f;
  c.shutterClose = 0.75f;
  const CameraFrame f = makeCameraFrame(c, 8, 8);
  EXPECT_FLOAT_EQ(generateRay(f, CameraSample{4, 4, 0.5f, 0.5f, 0.0f}).time, 0.25f);
  EXPECT_FLOAT_EQ(generateRay(f, CameraSample{4, 4, 0.5f, 0.5f, 0.5f}).time, 0.5f);
}

TEST(Camera, DegenerateCamerasAreRejected) {
  Camera c = testCamera();
  c.lookAt = c.eye;
  EXPECT_THROW(makeCameraFrame(c, 8, 8), std::invalid_argument);
  c = testCamera();
  c.up = c.lookAt - c.eye;
  EXPECT_THROW(makeCameraFrame(c, 8, 8), std::invalid_argument);
  EXPECT_THROW(makeCameraFrame(testCamera(), 0, 8), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// A render region is a window of the full image: its pixel (x, y) sees what the full image's
// pixel (x + regionX, y + regionY) sees, through a lens too; a region that does not fit is
// refused.
TEST(Camera, RegionRaysAreTheFullImagesRaysOffset) {
  Camera c;
  c.eye = vec3(0.3f, 1.0f, 4.0f);
  c.lookAt = vec3(0.0f, 0.5f, 0.0f);
  c.vfovDegrees = 35.0f;
  c.lensRadius = 0.05f;
  const CameraFrame full = makeCameraFrame(c, 200, 100);
  Camera r = c;
  r.regionX = 120;
  r.regionY = 30;
  r.fullWidth = 200;
  r.fullHeight = 100;
  const CameraFrame region = makeCameraFrame(r, 50, 40);
  EXPECT_EQ(region.width, 50);
  for (const auto& [x, y] :
       {std::pair{0.5f, 0.5f}, std::pair{49.9f, 39.1f}, std::pair{12.3f, 7.7f}}) {
    CameraSample s;
    s.imageX = x;
    s.imageY = y;
    s.lensU = 0.3f;
    s.lensV = 0.8f;
    const Ray a = generateRay(region, s);
    s.imageX += 120.0f;
    s.imageY += 30.0f;
    const Ray b = generateRay(full, s);
    EXPECT_LT(glm::length(a.origin - b.origin), 1e-5f);
    EXPECT_LT(glm::length(a.direction - b.direction), 1e-5f);
  }
  r.regionX = 160;  // 160 + 50 > 200
  EXPECT_THROW(makeCameraFrame(r, 50, 40), std::invalid_argument);
  r.regionX = -1;
  EXPECT_THROW(makeCameraFrame(r, 50, 40), std::invalid_argument);
}

TEST(Camera, APointsApproximateDifferentialsAreThoseOfTheCameraRayThatSeesIt) {
  // A point off the image's centre, 7 from the camera along a tilted ray, in a region of the
  // image (the offsets matter): its approximate differentials are the camera's for the film
  // point it projects to, through the lens centre, so its footprint on any plane is the one a
  // camera ray would give it.
  Camera camera = testCamera();
  camera.lensRadius = 0.3f;
  camera.focusDistance = 8.0f;
  camera.regionX = 40, camera.regionY = 30, camera.fullWidth = 200, camera.fullHeight = 100;
  const CameraFrame frame = makeCameraFrame(camera, 100, 60);
  const CameraSample sample{37.25f, 21.5f, 0.5f, 0.5f, 0.5f};
  const Ray ray = generateRay(frame, sample);
  const vec3 point = ray.origin + 7.0f * ray.direction;
  RayDifferentials approximate;
  ASSERT_TRUE(approximateRayDifferentials(frame, point, approximate));
  const RayDifferentials exact = cameraRayDifferentials(frame, sample);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(approximate.xOrigin[i], exact.xOrigin[i], 1e-5f);
    EXPECT_NEAR(approximate.yOrigin[i], exact.yOrigin[i], 1e-5f);
    EXPECT_NEAR(approximate.xDirection[i], exact.xDirection[i], 1e-4f);
    EXPECT_NEAR(approximate.yDirection[i], exact.yDirection[i], 1e-4f);
  }
  // Behind the camera, or in its plane: none.
  EXPECT_FALSE(approximateRayDifferentials(frame, camera.eye + (camera.eye - point), approximate));
  EXPECT_FALSE(approximateRayDifferentials(frame, camera.eye, approximate));
}

TEST(Camera, OrthographicRaysRunParallelFromThePlaneThroughTheEye) {
  Camera c = testCamera();
  c.orthographicHeight = 3.0f;
  c.lensRadius = 0.5f;  // not used
  const CameraFrame f = makeCameraFrame(c, 64, 48);
  EXPECT_TRUE(f.orthographic);
  const vec3 forward = glm::normalize(c.lookAt - c.eye);
  // The image's centre starts at the eye, its top edge 1.5 above it, its right edge 2 to the
  // right (the 4:3 image's width); every ray looks along the view direction.
  const Ray centre = generateRay(f, CameraSample{32, 24, 0.1f, 0.9f, 0});
  const Ray top = generateRay(f, CameraSample{32, 0, 0.5f, 0.5f, 0});
  const Ray right = generateRay(f, CameraSample{64, 24, 0.5f, 0.5f, 0});
  for (const Ray& r : {centre, top, right})
    EXPECT_NEAR(glm::length(r.direction - forward), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(centre.origin - c.eye), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(top.origin - (c.eye + 1.5f * f.upAxis)), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(right.origin - (c.eye + 2.0f * f.right)), 0.0f, 1e-5f);
  // A point's approximate differentials: one pixel (3 / 48) apart, whatever its distance.
  const vec3 point = top.origin + 9.0f * forward;
  RayDifferentials d;
  ASSERT_TRUE(approximateRayDifferentials(f, point, d));
  const RayDifferentials exact = cameraRayDifferentials(f, CameraSample{32, 0, 0.5f, 0.5f, 0.5f});
  EXPECT_NEAR(glm::length(d.yOrigin - exact.yOrigin), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(d.yOrigin - top.origin), 3.0f / 48.0f, 1e-5f);
  EXPECT_NEAR(glm::length(d.xDirection - forward), 0.0f, 1e-6f);
  // A height that is not a finite number above 0 is refused.
  for (float bad : {-1.0f, std::numeric_limits<float>::infinity()}) {
    c.orthographicHeight = bad;
    EXPECT_THROW(makeCameraFrame(c, 64, 48), std::invalid_argument);
  }
}

}  // namespace
}  // namespace penumbra
