// Interactive camera moves for the viewer, as pure functions of a Camera: orbit around the
// look-at point, pan in the view plane, dolly towards the look-at point, and fly (move eye
// and look-at together along the camera's own axes). The viewer maps mouse and keys to
// these and restarts rendering with the result.
#pragma once

#include "scene/camera.h"

namespace penumbra {

// Turns the eye around lookAt by `yaw` about the up axis and `pitch` about the camera's
// right axis (radians), keeping the distance; pitch stops short of the up axis so that
// the view never flips.
Camera orbitCamera(const Camera& camera, float yaw, float pitch);

// Moves eye and lookAt together in the view plane by (dx, dy) times the height of the view
// at the look-at distance. (dx, dy) is a drag in screen directions (x right, y down): the
// scene follows it, so the camera moves the other way.
Camera panCamera(const Camera& camera, float dx, float dy);

// Scales the eye's distance to lookAt by `factor` (< 1 comes closer), never below 1e-3 of
// the original distance nor to zero; an orthographic camera's height instead, as if it had
// come that much closer.
Camera dollyCamera(const Camera& camera, float factor);

// Moves eye and lookAt together by `right`, `up` and `forward` in the camera's frame
// (world units).
Camera flyCamera(const Camera& camera, float right, float up, float forward);

}  // namespace penumbra
