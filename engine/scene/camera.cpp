#include "scene/camera.h"

#include "core/constants.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra {

CameraFrame makeCameraFrame(const Camera& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  const vec3 view = camera.lookAt - camera.eye;
  const float viewLength = glm::length(view);
  if (!(viewLength > 1e-8f)) throw std::invalid_argument("camera eye and look-at coincide");
  const bool orthographic = camera.orthographicHeight != 0.0f;
  if (orthographic &&
      !(camera.orthographicHeight > 0.0f && std::isfinite(camera.orthographicHeight)))
    throw std::invalid_argument("camera orthographic height must be a finite number above 0");
  if (!orthographic && !(camera.vfovDegrees > 0.0f && camera.vfovDegrees < 180.0f))
    throw std::invalid_argument("camera fov must be in (0, 180) degrees");
  CameraFrame f;
  f.orthographic = orthographic;
  f.eye = camera.eye;
  f.forward = view / viewLength;
  const vec3 right = glm::cross(f.forward, camera.up);
  if (!(glm::length(right) > 1e-6f))
    throw std::invalid_argument("camera up vector is parallel to the view direction");
  f.right = glm::normalize(right);
  f.upAxis = glm::cross(f.right, f.forward);
  f.fullWidth = width;
  f.fullHeight = height;
  if (camera.fullWidth > 0 || camera.fullHeight > 0) {
    if (camera.fullWidth <= 0 || camera.fullHeight <= 0 || camera.regionX < 0 ||
        camera.regionY < 0 || camera.regionX > camera.fullWidth - width ||
        camera.regionY > camera.fullHeight - height)
      throw std::invalid_argument(
          "region " + std::to_string(camera.regionX) + "," + std::to_string(camera.regionY) + "," +
          std::to_string(width) + "," + std::to_string(height) + " does not fit the " +
          std::to_string(camera.fullWidth) + "x" + std::to_string(camera.fullHeight) + " image");
    f.offsetX = camera.regionX;
    f.offsetY = camera.regionY;
    f.fullWidth = camera.fullWidth;
    f.fullHeight = camera.fullHeight;
  }
  f.halfHeight = f.orthographic ? 0.5f * camera.orthographicHeight
                                : std::tan(0.5f * camera.vfovDegrees * kPi / 180.0f);
  f.halfWidth = f.halfHeight * float(f.fullWidth) / float(f.fullHeight);
  f.lensRadius = f.orthographic ? 0.0f : camera.lensRadius;
  f.focusDistance = camera.focusDistance > 0.0f ? camera.focusDistance : viewLength;
  f.shutterOpen = camera.shutterOpen;
  f.shutterClose = camera.shutterClose;
  f.width = width;
  f.height = height;
  return f;
}

glm::vec2 sampleUnitDisk(float u, float v) {
  const float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
  if (a == 0.0f && b == 0.0f) return glm::vec2(0.0f);
  constexpr float quarterPi = 0.78539816339f;
  float r, theta;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    theta = quarterPi * (b / a);
  } else {
    r = b;
    theta = 2.0f * quarterPi - quarterPi * (a / b);
  }
  return r * glm::vec2(std::cos(theta), std::sin(theta));
}

Ray generateRay(const CameraFrame& f, const CameraSample& s) {
  // Point on the film plane at distance 1 along forward.
  const float ndcX = 2.0f * (s.imageX + float(f.offsetX)) / float(f.fullWidth) - 1.0f;
  const float ndcY = 1.0f - 2.0f * (s.imageY + float(f.offsetY)) / float(f.fullHeight);
  Ray ray;
  ray.time = f.shutterOpen + s.time * (f.shutterClose - f.shutterOpen);
  if (f.orthographic) {
    ray.origin = f.eye + ndcX * f.halfWidth * f.right + ndcY * f.halfHeight * f.upAxis;
    ray.direction = f.forward;
    return ray;
  }
  const vec3 dir = f.forward + ndcX * f.halfWidth * f.right + ndcY * f.halfHeight * f.upAxis;
  if (f.lensRadius <= 0.0f) {
    ray.origin = f.eye;
    ray.direction = glm::normalize(dir);
    return ray;
  }
  // Thin lens: every ray through this film point meets at the focus plane, which lies
  // at distance focusDistance along forward (dir has unit forward component).
  const vec3 focusPoint = f.eye + f.focusDistance * dir;
  const glm::vec2 lens = f.lensRadius * sampleUnitDisk(s.lensU, s.lensV);
  ray.origin = f.eye + lens.x * f.right + lens.y * f.upAxis;
  ray.direction = glm::normalize(focusPoint - ray.origin);
  return ray;
}

RayDifferentials cameraRayDifferentials(const CameraFrame& frame, const CameraSample& sample) {
  CameraSample x = sample, y = sample;
  x.imageX += 1.0f;
  y.imageY += 1.0f;
  const Ray rx = generateRay(frame, x), ry = generateRay(frame, y);
  return {rx.origin, rx.direction, ry.origin, ry.direction};
}

bool approximateRayDifferentials(const CameraFrame& f, vec3 point, RayDifferentials& out) {
  const vec3 v = point - f.eye;
  const float z = glm::dot(v, f.forward);
  if (!(z > 1e-6f * glm::length(v)) || !(f.halfWidth > 0.0f) || !(f.halfHeight > 0.0f))
    return false;
  // generateRay's film point, inverted: the point's place on the plane at distance 1 (or,
  // orthographic, on the plane through the eye).
  const float depth = f.orthographic ? 1.0f : z;
  const float ndcX = glm::dot(v, f.right) / (depth * f.halfWidth);
  const float ndcY = glm::dot(v, f.upAxis) / (depth * f.halfHeight);
  CameraSample s;
  s.imageX = 0.5f * (ndcX + 1.0f) * float(f.fullWidth) - float(f.offsetX);
  s.imageY = 0.5f * (1.0f - ndcY) * float(f.fullHeight) - float(f.offsetY);
  s.lensU = s.lensV = 0.5f;  // the lens centre: the rays start at the eye
  s.time = 0.5f;
  if (!std::isfinite(s.imageX) || !std::isfinite(s.imageY)) return false;
  out = cameraRayDifferentials(f, s);
  return true;
}

}  // namespace penumbra
