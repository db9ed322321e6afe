#include "viewer/app/window.h"

#include "viewer/app/gl/context.h"
#include "viewer/app/view_script.h"

#include <glad/gl.h>
// After glad, which provides the GL declarations.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

struct Window final : ScriptHost {
  GLFWwindow* window = nullptr;
  ViewerApp* app = nullptr;
  bool iconified = false;
  bool dirty = true;
  Clock::time_point lastInput = Clock::now();
  Clock::time_point opened = Clock::now();
  WindowStats* stats = nullptr;  // where marks go

  // GLFW reports the cursor in window coordinates; the app works in framebuffer pixels.
  double scaleX() const {
    int w = 0, fw = 0, h = 0;
    glfwGetWindowSize(window, &w, &h);
    glfwGetFramebufferSize(window, &fw, &h);
    return w > 0 ? double(fw) / w : 1.0;
  }
  void touched() {
    dirty = true;
    lastInput = Clock::now();
  }
  void key(int k, bool down, int mods) override {
    touched();
    app->keyEvent(k, down, mods);
  }
  void mouseButton(int button, bool down, double x, double y, int mods) override {
    touched();
    app->mouseButton(button, down, x, y, mods);
  }
  void mouseMove(double x, double y) override {
    touched();
    app->mouseMoved(x, y);
  }
  void scroll(double dy, double x, double y, int mods) override {
    touched();
    app->scrolled(dy, x, y, mods);
  }
  void resize(int w, int h) override {
    touched();
    glfwSetWindowSize(window, std::max(w, 1), std::max(h, 1));
    if (w == 0 || h == 0) app->resized(w, h);  // GLFW refuses a zero size; the app must not
  }
  void iconify(bool minimise) override {
    touched();
    if (minimise)
      glfwIconifyWindow(window);
    else
      glfwRestoreWindow(window);
  }
  void screenshot(const std::string& path) override {
    touched();
    app->requestScreenshot(path);
  }
  void saveImage(const std::string& path) override {
    const std::string message = app->saveImage(path);
    std::fprintf(stderr, "penumbra view: %s\n", message.c_str());
  }
  void region(int x, int y, int width, int height) override {
    touched();
    app->setRegion(RenderRegion{x, y, width, height});
  }
  void mark(const std::string& name) override {
    if (stats)
      stats->marks.push_back(
          {name, std::chrono::duration<double>(Clock::now() - opened).count(), peakResidentKiB()});
  }
  void quit() override { glfwSetWindowShouldClose(window, GLFW_TRUE); }
  bool roundShown() override { return app->roundShown(); }
};

Window* windowOf(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }

void installCallbacks(GLFWwindow* window) {
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard) return;
    if (action == GLFW_REPEAT) return;
    windowOf(w)->key(key, action == GLFW_PRESS, mods);
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    Window* self = windowOf(w);
    const bool down = action == GLFW_PRESS;
    if (down && ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    const double s = self->scaleX();
    self->mouseButton(button, down, x * s, y * s, mods);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    Window* self = windowOf(w);
    const double s = self->scaleX();
    self->mouseMove(x * s, y * s);
  });
  // A scene file dropped on the window opens (the first, when several are dropped).
  glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
    if (count < 1) return;
    Window* self = windowOf(w);
    self->touched();
    self->app->openScene(paths[0]);
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
    Window* self = windowOf(w);
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    const double s = self->scaleX();
    int mods = 0;
    if (glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
        glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS)
      mods |= GLFW_MOD_CONTROL;
    self->scroll(dy, x * s, y * s, mods);
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int width, int height) {
    Window* self = windowOf(w);
    self->touched();
    self->app->resized(width, height);
  });
  glfwSetWindowIconifyCallback(window, [](GLFWwindow* w, int iconified) {
    windowOf(w)->iconified = iconified == GLFW_TRUE;
    windowOf(w)->touched();
  });
  glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { windowOf(w)->dirty = true; });
}

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Draws a frame of the window's framebuffer and swaps; returns its cost in seconds.
double drawWindowFrame(Window& host, double dt) {
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(host.window, &fw, &fh);
  const auto frameStart = Clock::now();
  ImGui_ImplGlfw_NewFrame();
  host.app->drawFrame(fw, fh, true, dt);
  const auto drawn = Clock::now();
  static const bool debugFrames = std::getenv("PENUMBRA_DEBUG_FRAMES") != nullptr;
  if (debugFrames) glFinish();
  const auto finished = Clock::now();
  glfwSwapBuffers(host.window);
  const auto swapped = Clock::now();
  if (debugFrames)
    std::fprintf(stderr, "frame at %.3f s: draw %.1f finish %.1f swap %.1f ms\n",
                 seconds(frameStart.time_since_epoch()), seconds(drawn - frameStart) * 1e3,
                 seconds(finished - drawn) * 1e3, seconds(swapped - finished) * 1e3);
  const double cost = seconds(swapped - frameStart);
  host.app->recordFrame(cost);
  host.dirty = false;
  return cost;
}

// The window's loop: events, the script, new pictures, and frames drawn only when something
// changed, paced by framePacing; the UI thread sleeps in glfwWaitEventsTimeout between them.
void frameLoop(Window& host, std::optional<InputScript>& script, const WindowRequest& request,
               Clock::time_point opened, WindowStats& stats) {
  ViewerApp& app = *host.app;
  const auto start = Clock::now();
  auto last = start, lastFrame = Clock::time_point{}, lastRss = Clock::time_point{};
  double frameCost = 0;
  bool scriptRunning = script.has_value();
  bool pictureWaiting = false;  // a published picture not drawn yet
  uint64_t publishedSeen = app.session().version();
  // PENUMBRA_FRAME_PACING=off: the pacing before it (any change drawn at up to 60 frames a
  // second, and every frame for half a second after input), for bench/viewer_fps.sh to compare.
  const char* pacingVariable = std::getenv("PENUMBRA_FRAME_PACING");
  const bool unpaced = pacingVariable && std::string(pacingVariable) == "off";
  while (!glfwWindowShouldClose(host.window) && !app.quitRequested()) {
    const auto now = Clock::now();
    const double dt = seconds(now - last);
    last = now;
    if (seconds(now - lastRss) >= 0.5) {
      stats.rss.push_back({seconds(now - opened), residentKiB()});
      lastRss = now;
    }
    if (scriptRunning) scriptRunning = script->step(seconds(now - start), host);
    if (script && !scriptRunning) break;
    app.fly(dt);
    if (app.update()) host.dirty = true;
    // A picture the method published is drawn within a frame (the pacing below spaces the
    // frames that previews, hover and the panel want): it is what the person waits for, and
    // a running method publishes at most five a second.
    if (const uint64_t v = app.session().version(); v != publishedSeen) {
      publishedSeen = v;
      pictureWaiting = true;
    }
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(host.window, &fw, &fh);
    // Hover feedback in the panel (its tooltips) needs frames for a moment after input. Over
    // the image every input draws its own frame (it marks the window dirty) and nothing waits
    // on a hover: frames there would only take the cores from a restart's first round (on
    // llvmpipe one costs 30-50 ms of CPU at 1640x800).
    const ImGuiIO& io = ImGui::GetIO();
    const bool interacting = seconds(now - host.lastInput) < (unpaced ? 0.5 : 0.3) &&
                             (unpaced || io.WantCaptureMouse || io.WantCaptureKeyboard);
    const bool rendering = app.session().state() == RenderSession::State::Running;
    const double pacing = request.continuous || unpaced ? 1.0 / 60
                          : pictureWaiting              ? 1.0 / 30
                                           : framePacing(rendering, interacting, frameCost);
    const bool wanted =
        !host.iconified && fw > 0 && fh > 0 && (host.dirty || interacting || request.continuous);
    const double sinceFrame = seconds(now - lastFrame);
    if (wanted && sinceFrame >= pacing) {
      frameCost = drawWindowFrame(host, dt);
      lastFrame = Clock::now();
      pictureWaiting = false;
    }
    // Sleep until the next frame is due, or a while to look for a new picture and the script's
    // next step; events wake the loop early.
    const double busy = seconds(Clock::now() - now);
    if (busy > stats.longestBusy) {
      stats.longestBusy = busy;
      stats.longestBusyAt = seconds(now - opened);
    }
    double timeout = scriptRunning || rendering ? 1.0 / 30 : 0.1;
    if (wanted) timeout = std::max(0.0, pacing - seconds(Clock::now() - lastFrame));
    if (request.continuous || unpaced) timeout = std::max(0.0, 1.0 / 60 - busy);
    glfwWaitEventsTimeout(timeout);
  }
}

}  // namespace

double framePacing(bool rendering, bool interacting, double lastFrameSeconds) {
  if (!rendering) return 1.0 / 60;
  // A slow frame (the first, compiling shaders) must not hold input back for long.
  const double spaced = 3.0 * std::min(lastFrameSeconds, 0.1);
  return interacting ? std::clamp(spaced, 1.0 / 30, 0.2) : std::max(spaced, 0.25);
}

namespace {

long long statusKiB(const std::string& field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field, 0) == 0) return std::atoll(line.c_str() + field.size());
  return -1;
}

}  // namespace

long long residentKiB() { return statusKiB("VmRSS:"); }

long long peakResidentKiB() { return statusKiB("VmHWM:"); }

void runWindow(ViewOptions options, const WindowRequest& request) {
  // Freed per-pixel planes leave the resident set: cli/allocation.cpp fixes glibc's mmap and trim
  // thresholds for every command (the asset scene's soak, bench/soak.sh --asset, grew 13 % after
  // warm-up without it).
  std::optional<InputScript> script;
  if (!request.script.empty()) script = InputScript::load(request.script);
  options.background = true;  // the UI thread keeps its frame rate
  int width = request.width, height = request.height;
  if (width <= 0 || height <= 0) {
    // The image at zoom 1 right of the panel, with room for a legend below.
    width = std::max(options.scene->scene.settings.width + 360, 900);
    height = std::max(options.scene->scene.settings.height + 80, 640);
  }

  glfwSetErrorCallback([](int code, const char* text) {
    std::fprintf(stderr, "penumbra view: GLFW error %d: %s\n", code, text);
  });
  if (!glfwInit())
    throw std::runtime_error("cannot initialise GLFW (is DISPLAY set to a running X server?)");
  struct GlfwGuard {
    ~GlfwGuard() { glfwTerminate(); }
  } glfwGuard;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, request.title.c_str(), nullptr, nullptr);
  if (!window) throw std::runtime_error("cannot open an OpenGL 3.3 core window");
  glfwMakeContextCurrent(window);
  std::string gl;
  try {
    gl = loadGl(reinterpret_cast<GlProcLoader>(glfwGetProcAddress), "window");
  } catch (const GlError& e) {
    glfwDestroyWindow(window);
    throw std::runtime_error(e.what());
  }
  glfwSwapInterval(0);  // we pace frames ourselves; a blocking swap would stall input
  std::fprintf(stderr, "penumbra view: window %dx%d, %s\n", width, height, gl.c_str());

  const auto opened = Clock::now();
  WindowStats windowStats;
  Window host;
  host.window = window;
  host.opened = opened;
  host.stats = &windowStats;
  ViewerApp app(std::move(options));
  host.app = &app;
  // A new picture wakes the loop (which otherwise looks every 1/30 s while rendering).
  app.session().setOnPublish([] { glfwPostEmptyEvent(); });
  app.setRecordFrameTimes(false);
  glfwSetWindowUserPointer(window, &host);
  installCallbacks(window);
  int status = 0;
  std::string failure;
  bool imguiPlatform = false;
  try {
    app.initGl(true);
    // Installed after ours, ImGui's callbacks chain to them.
    imguiPlatform = ImGui_ImplGlfw_InitForOpenGL(window, true);
    frameLoop(host, script, request, opened, windowStats);
    windowStats.peakKiB = peakResidentKiB();
  } catch (const std::exception& e) {
    failure = e.what();
    status = 1;
  }
  if (imguiPlatform) ImGui_ImplGlfw_Shutdown();
  app.releaseGl();
  glfwDestroyWindow(window);
  if (request.closed)
    request.closed(app, std::chrono::duration<double>(Clock::now() - opened).count(), windowStats);
  const FrameStats& stats = app.frameStats();
  std::fprintf(stderr, "penumbra view: %llu frames, mean %.1f ms, p95 %.1f ms, %d restarts\n",
               (unsigned long long)stats.frames,
               stats.frames ? stats.totalSeconds / double(stats.frames) * 1e3 : 0.0,
               stats.percentile(0.95) * 1e3, app.restarts());
  if (status) throw std::runtime_error(failure);
}

}  // namespace penumbra
