#include "scene/camera_control.h"

#include "core/constants.h"

#include <glm/geometric.hpp>
#include <glm/gtx/rotate_vector.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

struct Frame {
  vec3 forward, right, up;
  float distance;
};

// The camera's orthonormal frame; a degenerate camera keeps a usable default frame so
// that a move never produces NaN.
Frame frameOf(const Camera& c) {
  Frame f;
  const vec3 view = c.lookAt - c.eye;
  f.distance = glm::length(view);
  f.forward = f.distance > 0 ? view / f.distance : vec3(0, 0, -1);
  vec3 right = glm::cross(f.forward, c.up);
  if (glm::length(right) < 1e-6f) right = glm::cross(f.forward, vec3(1, 0, 0));
  if (glm::length(right) < 1e-6f) right = vec3(1, 0, 0);
  f.right = glm::normalize(right);
  f.up = glm::cross(f.right, f.forward);
  return f;
}

}  // namespace

Camera orbitCamera(const Camera& camera, float yaw, float pitch) {
  Camera c = camera;
  const Frame f = frameOf(camera);
  if (!(f.distance > 0)) return c;
  const vec3 worldUp = glm::length(camera.up) > 0 ? glm::normalize(camera.up) : vec3(0, 1, 0);
  vec3 offset = camera.eye - camera.lookAt;
  // Limit pitch so the offset stays at least ~1 degree away from the up axis.
  const float current = std::acos(std::clamp(glm::dot(offset / f.distance, worldUp), -1.0f, 1.0f));
  const float limit = 0.0175f;
  const float target = std::clamp(current - pitch, limit, kPi - limit);
  offset = glm::rotate(offset, target - current, f.right);
  offset = glm::rotate(offset, yaw, worldUp);
  c.eye = camera.lookAt + offset;
  return c;
}

Camera panCamera(const Camera& camera, float dx, float dy) {
  Camera c = camera;
  const Frame f = frameOf(camera);
  const float viewHeight =
      camera.orthographicHeight > 0
          ? camera.orthographicHeight
          : 2.0f * std::max(f.distance, 1e-6f) * std::tan(0.5f * camera.vfovDegrees * kPi / 180.0f);
  const vec3 move = (-dx * f.right + dy * f.up) * viewHeight;
  c.eye += move;
  c.lookAt += move;
  return c;
}

Camera dollyCamera(const Camera& camera, float factor) {
  Camera c = camera;
  const Frame f = frameOf(camera);
  if (!(f.distance > 0) || !(factor > 0) || !std::isfinite(factor)) return c;
  const float distance = std::max(f.distance * factor, 1e-3f * f.distance);
  // An orthographic view shows as much at any distance: it grows or shrinks instead.
  if (camera.orthographicHeight > 0) {
    c.orthographicHeight = camera.orthographicHeight * distance / f.distance;
    return c;
  }
  c.eye = camera.lookAt - f.forward * distance;
  return c;
}

Camera flyCamera(const Camera& camera, float right, float up, float forward) {
  Camera c = camera;
  const Frame f = frameOf(camera);
  const vec3 move = right * f.right + up * f.up + forward * f.forward;
  c.eye += move;
  c.lookAt += move;
  return c;
}

}  // namespace penumbra
