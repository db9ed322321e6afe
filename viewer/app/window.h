// The viewer in a GLFW window (OpenGL 3.3 core): events go to the ViewerApp, frames are drawn
// when something changed (at most 60 a second), and an input script can drive it. `penumbra
// view` opens it where there is a display (cli/cmd_view.cpp).
#pragma once

#include "viewer/app/view_app.h"

#include <functional>
#include <string>

namespace penumbra {

struct WindowRequest {
  int width = 0, height = 0;  // 0: the image at zoom 1 right of the panel, room for a legend
  std::string title = "Penumbra";
  std::string script;       // an input script to run, then close (view_script.h); empty: none
  bool continuous = false;  // redraw every frame even when nothing changed
  // Called once the window has closed, with the app and the seconds it was open (the
  // command's --report).
  std::function<void(const ViewerApp&, double seconds)> closed;
};

// Opens the window and returns when it closes. Throws std::runtime_error when GLFW or an
// OpenGL 3.3 core context cannot be had, or when rendering fails.
void runWindow(ViewOptions options, const WindowRequest& request);

}  // namespace penumbra
