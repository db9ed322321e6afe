// The viewer in a GLFW window (OpenGL 3.3 core): events go to the ViewerApp, frames are drawn
// only when something changed (a new picture, input, a change of what is shown), paced so that
// the render threads keep most of the machine (framePacing), and an input script can drive it.
// `penumbra view` opens it where there is a display (cli/cmd_view.cpp).
#pragma once

#include "viewer/app/view_app.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

// What the window measured about itself, for the command's --report (the soak test's figures).
struct WindowStats {
  // The longest the UI thread went without taking events (seconds), and when (seconds after
  // opening): a stall a person would feel.
  double longestBusy = 0, longestBusyAt = 0;
  // Resident memory (VmRSS, KiB) sampled twice a second: (seconds after opening, KiB).
  std::vector<std::pair<double, long long>> rss;
  // The script's marks: when each ran (seconds after opening) and the peak resident memory up
  // to then (VmHWM, KiB), exact where the samples above can miss a peak between two of them.
  struct Mark {
    std::string name;
    double seconds = 0;
    long long peakKiB = -1;
  };
  std::vector<Mark> marks;
  long long peakKiB = -1;  // the peak resident memory when the window closed (VmHWM)
};

// The shortest time between two frames (seconds). With the renderer at work, a frame costs it
// the cores the frame takes (on software GL, all of them), so frames keep to about a third of
// the time (three times the last frame's cost apart): while the user acts at most 30 a second
// and at least 5, and at most 4 a second when only a new picture arrived; with the renderer
// idle, 60 a second.
double framePacing(bool rendering, bool interacting, double lastFrameSeconds);

// The process's resident memory in KiB (VmRSS from /proc/self/status), -1 where unknown.
long long residentKiB();
// The process's peak resident memory so far in KiB (VmHWM), -1 where unknown.
long long peakResidentKiB();

struct WindowRequest {
  int width = 0, height = 0;  // 0: the image at zoom 1 right of the panel, room for a legend
  std::string title = "Penumbra";
  std::string script;       // an input script to run, then close (view_script.h); empty: none
  bool continuous = false;  // redraw every frame even when nothing changed
  // Called once the window has closed, with the app and the seconds it was open (the
  // command's --report).
  std::function<void(const ViewerApp&, double seconds, const WindowStats&)> closed;
};

// Opens the window and returns when it closes. Throws std::runtime_error when GLFW or an
// OpenGL 3.3 core context cannot be had, or when rendering fails.
void runWindow(ViewOptions options, const WindowRequest& request);

}  // namespace penumbra
