// The viewer's plain data, with no GL: what it renders and shows (ViewOptions), where and how
// it looks at the image (ViewState: camera, zoom, pan, cursor, the inspected pixel, which
// windows are open), what the input handlers track between events (InputState) and the UI
// thread's frame timing (FrameStats). The panel and the input handlers edit these.
#pragma once

#include "methods/factory.h"
#include "present/overlays.h"
#include "scene/camera.h"
#include "trace/integrator.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

// A render region in image pixels (as Cycles' viewport has): rendering spends every sample
// inside it, and the rest keeps its last picture, dimmed. width 0: none.
struct RenderRegion {
  int x = 0, y = 0, width = 0, height = 0;
  bool active() const { return width > 0 && height > 0; }
  bool contains(int px, int py) const {
    return active() && px >= x && py >= y && px < x + width && py < y + height;
  }
  bool operator==(const RenderRegion&) const = default;
};

// The panel's change to the environment: a map's file ("none": no map; empty: keep the map),
// its strength and rotation. It stays applied when the scene's files reload.
struct EnvironmentEdit {
  std::string file;
  float strength = 1.0f;
  float rotationDegrees = 0.0f;
};

struct ViewOptions {
  std::shared_ptr<const PreparedScene> scene;  // as loaded; camera moves make views of it
  // Reads a scene file as the command loaded the first one (its flags applied). When set, the
  // viewer watches scene->scene.sourceFiles and reloads scenePath on a change, and can open
  // another scene (dropped on the window, or typed in the panel).
  std::function<Scene(const std::string& path)> loadScene;
  std::string scenePath;
  RenderRegion region;  // the render region to start with (--region)
  // The methods the panel offers, the chosen one, and every method's configuration in the
  // registry's order: what the panel edits, kept when the panel switches to another method and
  // back.
  const MethodRegistry* methods = &builtinMethods();
  const MethodDescriptor* method = builtinMethods().find("bp");
  std::vector<MethodConfig> configs = defaultConfigs(builtinMethods());
  // Open-ended: the seed, the kept samples per pixel a round adds, the target spp at which
  // rendering stops (0 = refine until stopped), the sampler and the stopping rules.
  RunShape shape = RunShape::progressive(1);
  int threads = 0;          // render threads (0 = all cores)
  bool preview = true;      // a block preview before each (re)start (the window; not headless)
  int rounds = -1;          // pause after this many rounds of each (re)start (-1: run on)
  bool background = false;  // render at a lower priority than the UI thread (the window)
  std::shared_ptr<const Image> reference;
  std::string referencePath;
  MapId overlay;  // the map shown over the image (none: no overlay)
  float blend = 0.7f;
  DisplaySettings display;
  bool showRaw = false;  // the raw estimate instead of the reconstruction
  std::string saveDirectory = ".";

  // The chosen method's configuration.
  MethodConfig& config() { return configs.at(methodIndex()); }
  const MethodConfig& config() const { return configs.at(methodIndex()); }
  MethodSpec spec() const { return {shape, config()}; }
  size_t methodIndex() const {
    const auto& list = methods->methods();
    return size_t(std::find(list.begin(), list.end(), method) - list.begin());
  }
  // Every method's defaults, in the registry's order.
  static std::vector<MethodConfig> defaultConfigs(const MethodRegistry& registry) {
    std::vector<MethodConfig> out;
    for (const MethodDescriptor* m : registry.methods()) out.push_back(m->defaults());
    return out;
  }
};

// The image shown of a snapshot: the raw estimate or the reconstruction.
inline const Image& shownImage(const Snapshot& snapshot, const ViewOptions& options) {
  return options.showRaw || snapshot.reconstructed.empty() ? snapshot.raw : snapshot.reconstructed;
}

// How the image is looked at, in framebuffer pixels (y down) and image pixels.
struct ViewState {
  Camera camera;                         // of the running view; moves restart the render
  int width = 1, height = 1;             // framebuffer
  float zoom = 1.0f;                     // screen pixels per image pixel
  float centerX = 0.0f, centerY = 0.0f;  // image position at the framebuffer's centre
  bool fitted = false;                   // fitView has run (or setView): refit on resize
  int inspectX = -1, inspectY = -1;      // the inspected pixel (-1: none)
  double cursorX = -1, cursorY = -1;     // the last cursor position
  bool quit = false;
  bool showPanel = true, showInspector = true, showHelp = false;
  char savePath[512] = "penumbra.exr";
  char screenshotField[512] = "screenshot.png";
  char openField[512] = "";           // the panel's scene file field
  RenderRegion region;                // the active render region
  int regionField[4] = {0, 0, 0, 0};  // the panel's x, y, w, h fields
  char environmentField[512] = "";    // the panel's environment map file
  float environmentStrength = 1.0f, environmentRotation = 0.0f;

  // The image position under framebuffer position (x, y).
  void toImage(double x, double y, float& imageX, float& imageY) const {
    imageX = centerX + float(x - 0.5 * width) / zoom;
    imageY = centerY + float(y - 0.5 * height) / zoom;
  }
};

// What the input handlers remember between events: buttons dragging, where the last move and
// the last press were, and the keys held (GLFW's codes).
struct InputState {
  bool dragging[3] = {false, false, false};
  bool regionDrag = false;  // ctrl + left drag: a render region is being drawn
  double lastX = 0, lastY = 0, pressX = 0, pressY = 0;
  bool held[512] = {};
};

// Frame timing of the UI thread, for the panel and the window test's report.
struct FrameStats {
  uint64_t frames = 0;
  double totalSeconds = 0, maxSeconds = 0, lastSeconds = 0;
  std::vector<float> recent;  // the last frame times (seconds), for a percentile
  void add(double seconds);
  double percentile(double q) const;
};

}  // namespace penumbra
