// Headless rendering of the viewer: N rounds of the session, then one frame drawn by the
// same ViewerApp and shaders as the window into an offscreen framebuffer of an EGL or
// OSMesa context. `penumbra view --headless` and the screenshot tests both call this.
#pragma once

#include "viewer/app/gl/context.h"
#include "viewer/app/view_app.h"

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

struct HeadlessRequest {
  HeadlessBackend backend = HeadlessBackend::Auto;
  int rounds = 4;
  bool withUi = false;
  int width = 0, height = 0;  // 0: the image (plus the legend), or 1024x720 with the UI
  int inspectX = -1, inspectY = -1;
  float zoom = 0;                    // 0: fit
  float centerX = -1, centerY = -1;  // image position at the centre (-1: the fit's)
};

struct HeadlessFrame {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // display-encoded, top row first
  std::string backend;       // "egl" or "osmesa"
  std::string description;   // the context, e.g. "egl surfaceless, ... llvmpipe"
  std::shared_ptr<const Snapshot> snapshot;
  std::string overlayUnavailable;  // why the requested overlay could not be drawn
  std::string failure;             // the session's error, if rendering failed
};

// Throws GlError when no context can be made or a shader is broken.
HeadlessFrame renderHeadless(ViewOptions options, const HeadlessRequest& request);

}  // namespace penumbra
