// ViewerApp's input, in framebuffer pixels (y down) with GLFW's key and button codes: keys
// (overlays, display, pause, fit, windows, save, quit), mouse (click to inspect, drag to pan
// the image or orbit and pan the camera), scroll (zoom about the cursor, dolly), resize and
// flying with held keys. It edits the view state and restarts on camera moves.
#include "viewer/app/view_app.h"

#include "scene/camera_control.h"

// GLFW only for its key and button codes here.
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>

namespace penumbra {

void ViewerApp::resized(int width, int height) {
  if (width <= 0 || height <= 0) return;  // minimised or zero-sized: keep the last view
  const bool refit = view_.fitted && view_.width > 1;
  if (width != view_.width) overlayStale_ = true;  // the legend strip follows the width
  view_.width = width;
  view_.height = height;
  texturesStale_ = true;
  if (refit) fitView();
}

void ViewerApp::setView(float zoom, float x, float y) {
  view_.zoom = std::clamp(zoom, 0.05f, 256.0f);
  if (x >= 0 && y >= 0) {
    view_.centerX = x;
    view_.centerY = y;
  }
  view_.fitted = true;
}

void ViewerApp::zoomAt(float factor, double x, double y) {
  float ix, iy;
  view_.toImage(x, y, ix, iy);
  view_.zoom = std::clamp(view_.zoom * factor, 0.05f, 256.0f);
  // Keep the image point under the cursor where it was.
  view_.centerX = ix - float(x - 0.5 * view_.width) / view_.zoom;
  view_.centerY = iy - float(y - 0.5 * view_.height) / view_.zoom;
}

void ViewerApp::keyEvent(int key, bool down, int mods) {
  if (key >= 0 && key < 512) input_.held[key] = down;
  if (!down) return;
  const auto list = overlayList(*options_.methods);
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9 && key < GLFW_KEY_1 + int(list.size())) {
    setOverlay(*list[size_t(key - GLFW_KEY_1)]);
    return;
  }
  switch (key) {
    case GLFW_KEY_0:
    case GLFW_KEY_GRAVE_ACCENT:
      setOverlay(MapId());
      break;
    case GLFW_KEY_R:
      options_.showRaw = !options_.showRaw;
      overlayStale_ = true;  // the reference error follows the shown image
      break;
    case GLFW_KEY_SPACE:
      if (session_->state() == RenderSession::State::Paused)
        session_->resume();
      else
        session_->pause();
      break;
    case GLFW_KEY_N:
      session_->step();
      break;
    case GLFW_KEY_F:
      fitView();
      break;
    case GLFW_KEY_TAB:
      view_.showPanel = !view_.showPanel;
      break;
    case GLFW_KEY_I:
      view_.showInspector = !view_.showInspector;
      break;
    case GLFW_KEY_F1:
    case GLFW_KEY_H:
      view_.showHelp = !view_.showHelp;
      break;
    case GLFW_KEY_MINUS:
      options_.display.exposure -= 0.5f;
      break;
    case GLFW_KEY_EQUAL:
      options_.display.exposure += 0.5f;
      break;
    case GLFW_KEY_T:
      options_.display.curve =
          options_.display.curve == ToneCurve::Srgb ? ToneCurve::Filmic : ToneCurve::Srgb;
      break;
    case GLFW_KEY_LEFT_BRACKET:
      options_.blend = std::max(0.0f, options_.blend - 0.1f);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      options_.blend = std::min(1.0f, options_.blend + 0.1f);
      break;
    case GLFW_KEY_P:
      requestScreenshot(options_.saveDirectory + "/" + view_.screenshotField);
      break;
    case GLFW_KEY_S:
      if (mods & GLFW_MOD_CONTROL)
        message_ = saveImage(options_.saveDirectory + "/" + view_.savePath);
      break;
    case GLFW_KEY_ESCAPE:
      view_.quit = true;
      break;
    default:
      break;
  }
}

void ViewerApp::fly(double dt) {
  float right = 0, up = 0, forward = 0;
  const auto pressed = [&](int key) { return input_.held[key] ? 1.0f : 0.0f; };
  forward = pressed(GLFW_KEY_W) - pressed(GLFW_KEY_S);
  right = pressed(GLFW_KEY_D) - pressed(GLFW_KEY_A);
  up = pressed(GLFW_KEY_E) - pressed(GLFW_KEY_Q);
  if (right == 0 && up == 0 && forward == 0) return;
  // Speed: a third of the distance to the look-at point per second.
  const float distance = std::max(1e-3f, glm::length(view_.camera.lookAt - view_.camera.eye));
  const float step = float(dt) * distance / 3.0f;
  setCamera(flyCamera(view_.camera, right * step, up * step, forward * step));
}

void ViewerApp::mouseButton(int button, bool down, double x, double y, int mods) {
  if (button < 0 || button > 2) return;
  if (down) {
    input_.dragging[button] = true;
    input_.lastX = x;
    input_.lastY = y;
    view_.cursorX = x;
    view_.cursorY = y;
    // Ctrl + left drag draws a render region (a ctrl + click clears it).
    if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_CONTROL)) {
      input_.dragging[button] = false;
      input_.regionDrag = true;
    }
    // Shift + left pans the image, like the middle button.
    if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)) {
      input_.dragging[button] = false;
      input_.dragging[GLFW_MOUSE_BUTTON_MIDDLE] = true;
    }
    input_.pressX = x;
    input_.pressY = y;
    return;
  }
  if (button == GLFW_MOUSE_BUTTON_LEFT && input_.regionDrag) {
    input_.regionDrag = false;
    float x0, y0, x1, y1;
    view_.toImage(input_.pressX, input_.pressY, x0, y0);
    view_.toImage(x, y, x1, y1);
    const bool click = std::abs(x - input_.pressX) < 3 && std::abs(y - input_.pressY) < 3;
    const int left = int(std::floor(std::min(x0, x1))), top = int(std::floor(std::min(y0, y1)));
    const int right = int(std::ceil(std::max(x0, x1))), bottom = int(std::ceil(std::max(y0, y1)));
    setRegion(click ? RenderRegion{} : RenderRegion{left, top, right - left, bottom - top});
    return;
  }
  const bool wasLeft = button == GLFW_MOUSE_BUTTON_LEFT && input_.dragging[button];
  input_.dragging[button] = false;
  if (button == GLFW_MOUSE_BUTTON_LEFT) input_.dragging[GLFW_MOUSE_BUTTON_MIDDLE] = false;
  // A click (no drag) on the left button inspects the pixel under the cursor.
  if (wasLeft && std::abs(x - input_.pressX) < 3 && std::abs(y - input_.pressY) < 3) {
    float ix, iy;
    view_.toImage(x, y, ix, iy);
    inspectPixel(int(std::floor(ix)), int(std::floor(iy)));
  }
}

void ViewerApp::mouseMoved(double x, double y) {
  const double dx = x - input_.lastX, dy = y - input_.lastY;
  input_.lastX = x;
  input_.lastY = y;
  view_.cursorX = x;
  view_.cursorY = y;
  if (dx == 0 && dy == 0) return;
  if (input_.dragging[GLFW_MOUSE_BUTTON_MIDDLE]) {
    view_.centerX -= float(dx) / view_.zoom;
    view_.centerY -= float(dy) / view_.zoom;
    return;
  }
  const bool clickSized = std::abs(x - input_.pressX) < 3 && std::abs(y - input_.pressY) < 3;
  if (input_.dragging[GLFW_MOUSE_BUTTON_LEFT] && !clickSized) {
    setCamera(orbitCamera(view_.camera, float(-dx) * 0.006f, float(dy) * 0.006f));
  } else if (input_.dragging[GLFW_MOUSE_BUTTON_RIGHT]) {
    const float shown = float(options_.scene->scene.settings.height) * view_.zoom;
    setCamera(panCamera(view_.camera, float(dx) / shown, float(dy) / shown));
  }
}

void ViewerApp::scrolled(double dy, double x, double y, int mods) {
  if (dy == 0) return;
  if (mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT)) {
    setCamera(dollyCamera(view_.camera, std::pow(0.9f, float(dy))));
    return;
  }
  zoomAt(std::pow(1.25f, float(dy)), x, y);
}

}  // namespace penumbra
