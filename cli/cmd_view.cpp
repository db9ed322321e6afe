// `penumbra view`: the progressive viewer. With a display it opens a GLFW window (OpenGL 3.3
// core); with --headless, or where there is no display, it renders N rounds and writes a
// screenshot through an EGL or OSMesa context, drawing with the same code and shaders.
#include "cli/commands.h"
#include "cli/json_file.h"
#include "cli/method_options.h"
#include "cli/run_options.h"
#include "cli/scene_options.h"
#include "core/image_io.h"
#include "viewer/app/gl/context.h"
#include "viewer/app/headless.h"
#include "viewer/app/view_app.h"
#include "viewer/app/window.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

namespace penumbra {

namespace {

struct ViewFlags {
  SceneOptions scene;
  MethodOptions method;
  RunOptions run;
  int threads = 0;
  std::string referencePath, overlay = "none", tone = "srgb";
  float exposure = 0.0f, blend = 0.7f;
  bool raw = false;
  bool headless = false, withUi = false;
  int rounds = 4;
  std::string screenshot, backend = "auto", windowSize, inspect, region;
  std::string script, report;
  bool continuous = false;
};

bool haveDisplay() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wayland && *wayland);
}

std::pair<int, int> parseSize(const std::string& text, const char* flag) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 ||
      h < 1 || w > 16384 || h > 16384)
    throw CommandError(std::string(flag) + ": expected WxH with sizes in 1..16384, got '" + text +
                       "'");
  return {w, h};
}

// Open-ended rounds of 1 spp, refining until stopped, with the run flags given (--spp is where
// they stop).
RunShape viewShape(const RunOptions& run) {
  RunShape shape = RunShape::progressive(1);
  run.apply(shape);
  return shape;
}

ViewOptions makeOptions(const ViewFlags& f) {
  ViewOptions o;
  Scene scene = loadSceneWithOptions(f.scene);
  o.scene = prepareScene(std::move(scene));
  o.scenePath = f.scene.scenePath;
  if (!f.region.empty()) {
    const auto [x, y, w, h] =
        parseRegion(f.region, o.scene->scene.settings.width, o.scene->scene.settings.height);
    o.region = RenderRegion{x, y, w, h};
  }
  o.loadScene = [flags = f.scene](const std::string& path) {
    SceneOptions withPath = flags;
    withPath.scenePath = path;
    return loadSceneWithOptions(withPath);
  };
  o.shape = viewShape(f.run);
  o.methods = f.method.registry;
  o.method = &f.method.descriptor();
  f.method.requireRead({o.method});
  // Every method gets the flags given (and the preset, where it has it), so that the panel's
  // switch keeps them.
  o.configs.clear();
  for (const MethodDescriptor* m : o.methods->methods())
    o.configs.push_back(f.method.config(*m, f.method.preset));
  if (const std::string problem = validate(o.spec()); !problem.empty()) throw CommandError(problem);
  requireNoiseThresholdHonoured(*o.method, o.config(), o.shape.noiseThreshold > 0,
                                o.shape.timeLimit > 0);
  o.threads = f.threads;
  const auto overlay = overlayByName(f.overlay, *o.methods);
  if (!overlay)
    throw CommandError("--overlay: unknown overlay '" + f.overlay +
                       "' (expected one of: " + overlayNames(*o.methods) + ")");
  o.overlay = *overlay;
  o.blend = f.blend;
  o.display.exposure = f.exposure;
  o.display.curve = f.tone == "filmic" ? ToneCurve::Filmic : ToneCurve::Srgb;
  o.showRaw = f.raw;
  if (!f.referencePath.empty()) {
    auto reference = std::make_shared<Image>(readImage(f.referencePath));
    const Scene& s = o.scene->scene;
    if (reference->width != s.settings.width || reference->height != s.settings.height)
      throw CommandError(
          "--reference: " + f.referencePath + " is " + std::to_string(reference->width) + "x" +
          std::to_string(reference->height) + ", the render " + std::to_string(s.settings.width) +
          "x" + std::to_string(s.settings.height));
    o.reference = reference;
    o.referencePath = f.referencePath;
  }
  return o;
}

std::string defaultScreenshot(const ViewFlags& f) {
  const std::string stem = std::filesystem::path(f.scene.scenePath).stem().string();
  std::filesystem::create_directories("out");
  return "out/" + stem + "_view.png";
}

void writeReport(const std::string& path, const ViewerApp& app, const std::string& backend,
                 double wallSeconds, const WindowStats& window) {
  if (path.empty()) return;
  nlohmann::json j;
  j["wall_seconds"] = wallSeconds;
  j["frames_per_second"] = wallSeconds > 0 ? double(app.frameStats().frames) / wallSeconds : 0.0;
  const FrameStats& f = app.frameStats();
  j["backend"] = backend;
  j["frames"] = f.frames;
  j["mean_frame_ms"] = f.frames ? f.totalSeconds / double(f.frames) * 1e3 : 0.0;
  j["p95_frame_ms"] = f.percentile(0.95) * 1e3;
  j["max_frame_ms"] = f.maxSeconds * 1e3;
  j["restarts"] = app.restarts();
  // Restart to first picture: how soon a camera move shows something (the block preview
  // counts), and to the first full one (every pixel with a sample of its own, through the
  // method's reconstruction).
  auto timesJson = [&j](const std::vector<double>& times, const std::string& name) {
    double sum = 0, worst = 0;
    for (double t : times) {
      sum += t;
      worst = std::max(worst, t);
    }
    j[name + "s"] = times.size();
    j[name + "_ms_mean"] = times.empty() ? 0.0 : sum / double(times.size()) * 1e3;
    j[name + "_ms_max"] = worst * 1e3;
    j[name + "_ms_last"] = times.empty() ? 0.0 : times.back() * 1e3;  // after the last restart
  };
  timesJson(app.firstPictureTimes(), "first_picture");
  timesJson(app.firstFullPictureTimes(), "first_full_picture");
  const auto snap = app.snapshot();
  j["round"] = snap ? snap->round : 0;
  j["method"] = snap ? snap->method : "";
  j["kept_spp"] =
      snap ? double(snap->keptSamples) / std::max(1.0, double(snap->width) * snap->height) : 0.0;
  j["state"] = toString(const_cast<ViewerApp&>(app).session().state());
  j["message"] = app.lastMessage();
  // The method's kept spp over its own seconds at its newest snapshot shown (the last
  // restart's), to compare with a batch render's spp / time_seconds.
  j["trace_spp_per_second"] = app.traceSpeed();
  j["reloads"] = app.reloads();
  j["longest_busy_ms"] = window.longestBusy * 1e3;
  j["longest_busy_at_seconds"] = window.longestBusyAt;
  nlohmann::json rss = nlohmann::json::array();
  for (const auto& [t, kib] : window.rss) rss.push_back({t, kib});
  j["rss_kib"] = rss;  // [seconds after opening, VmRSS KiB], twice a second
  nlohmann::json marks = nlohmann::json::object(), peaks = nlohmann::json::object();
  for (const auto& mark : window.marks) {
    marks[mark.name] = mark.seconds;
    peaks[mark.name] = mark.peakKiB;
  }
  j["marks"] = marks;  // the script's marks, seconds after opening
  // The peak resident memory (VmHWM, KiB) up to each mark and when the window closed: exact,
  // where rss_kib's samples can fall either side of a short peak.
  j["peak_rss_kib_at_marks"] = peaks;
  j["peak_rss_kib"] = window.peakKiB;
  writeJson(path, j);
}

// ---- Headless ----------------------------------------------------------------------------

void runHeadless(const ViewFlags& f) {
  HeadlessRequest request;
  request.backend = f.backend == "egl"      ? HeadlessBackend::Egl
                    : f.backend == "osmesa" ? HeadlessBackend::OsMesa
                                            : HeadlessBackend::Auto;
  request.rounds = f.rounds;
  request.withUi = f.withUi;
  if (!f.windowSize.empty())
    std::tie(request.width, request.height) = parseSize(f.windowSize, "--window-size");
  if (!f.inspect.empty()) {
    char comma = 0, extra = 0;
    if (std::sscanf(f.inspect.c_str(), "%d%c%d%c", &request.inspectX, &comma, &request.inspectY,
                    &extra) != 3 ||
        comma != ',')
      throw CommandError("--inspect: expected X,Y, got '" + f.inspect + "'");
  }
  const std::string out = f.screenshot.empty() ? defaultScreenshot(f) : f.screenshot;
  if (lowercaseExtension(out) != ".png")
    throw CommandError("--screenshot: expected a .png file, got '" + out + "'");
  HeadlessFrame frame;
  try {
    frame = renderHeadless(makeOptions(f), request);
  } catch (const GlError& e) {
    throw CommandError(e.what());
  }
  std::fprintf(stderr, "penumbra view: headless, %s\n", frame.description.c_str());
  if (!frame.failure.empty()) throw CommandError("rendering failed: " + frame.failure);
  writePng8(out, frame.width, frame.height, 3, frame.rgb);
  const auto& snap = frame.snapshot;
  std::printf("%s: %dx%d, %s, %d rounds, %s, overlay %s\n", out.c_str(), frame.width, frame.height,
              snap ? snap->method.c_str() : "-", snap ? snap->round : 0, frame.backend.c_str(),
              f.overlay.c_str());
  if (!frame.overlayUnavailable.empty())
    std::fprintf(stderr, "penumbra view: overlay %s unavailable: %s\n", f.overlay.c_str(),
                 frame.overlayUnavailable.c_str());
}

// ---- Window ------------------------------------------------------------------------------

void openWindow(const ViewFlags& f) {
  WindowRequest request;
  if (!f.windowSize.empty())
    std::tie(request.width, request.height) = parseSize(f.windowSize, "--window-size");
  request.title = "Penumbra - " + f.scene.scenePath;
  request.script = f.script;
  request.continuous = f.continuous;
  request.closed = [&f](const ViewerApp& app, double seconds, const WindowStats& window) {
    writeReport(f.report, app, "glfw", seconds, window);
  };
  runWindow(makeOptions(f), request);
}

void run(const ViewFlags& f) {
  if (f.headless || !haveDisplay()) {
    if (!f.headless && f.script.empty())
      std::fprintf(stderr,
                   "penumbra view: no display (DISPLAY is not set): writing a headless "
                   "screenshot instead\n");
    if (!f.script.empty() && !f.headless) throw CommandError("--script needs a display");
    runHeadless(f);
    return;
  }
  openWindow(f);
}

}  // namespace

void registerViewCommand(CLI::App& app) {
  auto flags = std::make_shared<ViewFlags>();
  // An artist opening a scene gets the adaptive method in its measured-best configuration (bp's
  // defaults); --preset paper and --method ld are one flag away.
  flags->method.method = "bp";
  CLI::App* c = app.add_subcommand(
      "view", "Open the progressive viewer (a window; headless screenshots with --headless)");
  addSceneOptions(*c, flags->scene);
  addRunOptions(*c, flags->run, kViewCommand, viewShape({}), {{"spp", "0: refine until stopped"}});
  c->add_option("--threads", flags->threads, "Render threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--reference", flags->referencePath,
                "Reference image (.exr): the error overlay and the MSE plot compare with it");
  c->add_option("--overlay", flags->overlay, "Overlay at start: " + overlayNames())
      ->capture_default_str();
  c->add_option("--blend", flags->blend, "Overlay strength in [0, 1]")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
  c->add_option("--exposure", flags->exposure, "Display exposure in stops")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--tone", flags->tone, "Display tone curve: srgb or filmic")
      ->check(CLI::IsMember({"srgb", "filmic"}))
      ->capture_default_str();
  c->add_flag("--raw", flags->raw, "Show the raw estimate instead of the reconstruction");
  const char* headless = "Headless";
  c->add_flag("--headless", flags->headless,
              "Render --rounds rounds without a window and write --screenshot (also the "
              "behaviour when no display is set)")
      ->group(headless);
  c->add_option("--rounds", flags->rounds, "Headless: rounds to render before the screenshot")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str()
      ->group(headless);
  c->add_option("--screenshot", flags->screenshot,
                "Headless: PNG to write (default out/<scene>_view.png)")
      ->group(headless);
  c->add_option("--backend", flags->backend,
                "Headless GL: auto (EGL, then OSMesa), egl (GPU device or Mesa surfaceless) or "
                "osmesa")
      ->check(CLI::IsMember({"auto", "egl", "osmesa"}))
      ->capture_default_str()
      ->group(headless);
  c->add_flag("--with-ui", flags->withUi, "Headless: draw the panel (and inspector) too")
      ->group(headless);
  c->add_option("--region", flags->region,
                "Render only the window x,y,w,h of the image (pixels); the rest shows dimmed. "
                "In the window: ctrl + left drag draws one, ctrl + click clears it");
  c->add_option("--inspect", flags->inspect, "Inspect pixel X,Y (headless: before the screenshot)")
      ->group(headless);
  c->add_option("--window-size", flags->windowSize,
                "Window or screenshot size WxH (default: fits the image, and the panel in a "
                "window)");
  c->add_option("--script", flags->script,
                "Window: drive the viewer with scripted input (see viewer/app/view_script.h), then "
                "close");
  c->add_option(
      "--report", flags->report,
      "Window: write frame times, frames per second, restarts and the final round as JSON on exit");
  c->add_flag("--continuous", flags->continuous,
              "Window: redraw every frame even when nothing changed (to measure frame rate)");
  addMethodOptions(*c, flags->method, {"rounds"});
  c->callback([flags] { run(*flags); });
}

}  // namespace penumbra
