// Thin-lens camera with a shutter interval, or an orthographic one. A camera sample is the 5D
// point (imageX, imageY, lensU, lensV, time): image position in raster pixels (x right,
// y down), lens and time in [0,1). Radius 0 gives a pinhole camera.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace penumbra {

using glm::vec3;

struct Camera {
  vec3 eye = vec3(0.0f, 0.0f, 5.0f);
  vec3 lookAt = vec3(0.0f);
  vec3 up = vec3(0.0f, 1.0f, 0.0f);
  float vfovDegrees = 40.0f;
  // > 0: an orthographic camera whose view is this tall (world units) at any distance; its
  // rays start on the plane through the eye, parallel to the view direction, and vfovDegrees
  // and the lens are not used.
  float orthographicHeight = 0.0f;
  float lensRadius = 0.0f;
  float focusDistance = 0.0f;  // <= 0: distance from eye to lookAt
  float shutterOpen = 0.0f;    // scene time in [0,1] at which the shutter opens
  float shutterClose = 1.0f;
  // A render region: the image is the window [regionX, regionX + width) x [regionY, ...) of
  // a fullWidth x fullHeight image of this camera. fullWidth 0 = the whole image.
  int regionX = 0, regionY = 0, fullWidth = 0, fullHeight = 0;
};

// The 5D point every sampler produces and the integrator consumes.
struct CameraSample {
  float imageX = 0.5f, imageY = 0.5f;  // raster position, pixel (px,py) covers [px,px+1)x[py,py+1)
  float lensU = 0.5f, lensV = 0.5f;
  float time = 0.5f;  // fraction of the shutter interval
};

struct Ray {
  vec3 origin;
  vec3 direction;     // unit length
  float time = 0.0f;  // scene time in [0,1]
};

// Precomputed frame for generating rays at a given resolution.
struct CameraFrame {
  vec3 eye, right, upAxis, forward;     // orthonormal; forward points into the scene
  float halfHeight = 0, halfWidth = 0;  // film extent on the plane at distance 1
  // (orthographic: the view's half extents on the plane through the eye, world units)
  bool orthographic = false;
  float lensRadius = 0, focusDistance = 1;
  float shutterOpen = 0, shutterClose = 1;
  int width = 1, height = 1;          // the image rendered (the region, with one)
  int offsetX = 0, offsetY = 0;       // of the region in the full image
  int fullWidth = 1, fullHeight = 1;  // the full image
};

// Throws std::invalid_argument on a degenerate camera (eye == lookAt, up parallel to view, an
// orthographic height that is not a finite number above 0) or
// a region that does not fit its full image (a width x height region of it at regionX,
// regionY).
CameraFrame makeCameraFrame(const Camera& camera, int width, int height);
Ray generateRay(const CameraFrame& frame, const CameraSample& sample);

// The rays through the film points one pixel right of the sample (x) and one pixel below it
// (y), through the same lens point at the same time: pbrt's ray differentials, which give a
// texture lookup at a camera ray's hit the footprint of one pixel whatever the sample's place
// in the pixel.
struct RayDifferentials {
  vec3 xOrigin, xDirection;
  vec3 yOrigin, yDirection;
};
RayDifferentials cameraRayDifferentials(const CameraFrame& frame, const CameraSample& sample);
// The differentials the camera would give a point it saw directly: those of the film point
// that the point projects to, through the lens centre. pbrt-v4's approximation for the hits of
// rays that carry none (a bounce's), so that their texture lookups take the footprint of about
// one pixel at the point's distance. False for a point behind the camera (or in its plane).
bool approximateRayDifferentials(const CameraFrame& frame, vec3 point, RayDifferentials& out);

// Concentric mapping of [0,1)^2 onto the unit disk (Shirley-Chiu).
glm::vec2 sampleUnitDisk(float u, float v);

}  // namespace penumbra
