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

}  // namespace

void runWindow(ViewOptions options, const WindowRequest& request) {
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
  Window host;
  host.window = window;
  ViewerApp app(std::move(options));
  host.app = &app;
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
    const auto start = Clock::now();
    auto last = start;
    bool scriptRunning = script.has_value();
    while (!glfwWindowShouldClose(window) && !app.quitRequested()) {
      const auto now = Clock::now();
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      if (scriptRunning)
        scriptRunning = script->step(std::chrono::duration<double>(now - start).count(), host);
      if (script && !scriptRunning) break;
      app.fly(dt);
      if (app.update()) host.dirty = true;
      int fw = 0, fh = 0;
      glfwGetFramebufferSize(window, &fw, &fh);
      // Hover feedback in the panel needs frames for a moment after input.
      const bool recentInput = std::chrono::duration<double>(now - host.lastInput).count() < 0.5;
      if (!host.iconified && fw > 0 && fh > 0 &&
          (host.dirty || recentInput || request.continuous)) {
        const auto frameStart = Clock::now();
        ImGui_ImplGlfw_NewFrame();
        app.drawFrame(fw, fh, true, dt);
        const auto drawn = Clock::now();
        if (std::getenv("PENUMBRA_DEBUG_FRAMES")) glFinish();
        const auto finished = Clock::now();
        glfwSwapBuffers(window);
        if (std::getenv("PENUMBRA_DEBUG_FRAMES"))
          std::fprintf(stderr, "draw %.1f finish %.1f swap %.1f ms\n",
                       std::chrono::duration<double>(drawn - frameStart).count() * 1e3,
                       std::chrono::duration<double>(finished - drawn).count() * 1e3,
                       std::chrono::duration<double>(Clock::now() - finished).count() * 1e3);
        app.recordFrame(std::chrono::duration<double>(Clock::now() - frameStart).count());
        host.dirty = false;
      }
      // At most 60 frames per second; events wake the loop early.
      const double spent = std::chrono::duration<double>(Clock::now() - now).count();
      glfwWaitEventsTimeout(std::max(0.0, 1.0 / 60 - spent));
    }
  } catch (const std::exception& e) {
    failure = e.what();
    status = 1;
  }
  if (imguiPlatform) ImGui_ImplGlfw_Shutdown();
  app.releaseGl();
  glfwDestroyWindow(window);
  if (request.closed)
    request.closed(app, std::chrono::duration<double>(Clock::now() - opened).count());
  const FrameStats& stats = app.frameStats();
  std::fprintf(stderr, "penumbra view: %llu frames, mean %.1f ms, p95 %.1f ms, %d restarts\n",
               (unsigned long long)stats.frames,
               stats.frames ? stats.totalSeconds / double(stats.frames) * 1e3 : 0.0,
               stats.percentile(0.95) * 1e3, app.restarts());
  if (status) throw std::runtime_error(failure);
}

}  // namespace penumbra
