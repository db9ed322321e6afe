// The progressive viewer, independent of where it draws: it runs a RenderSession on the
// scene, turns each new snapshot into textures (image, overlay, slices, legend), draws them
// and the Dear ImGui panel into the bound framebuffer, and reacts to input (keys, mouse,
// scroll, resize) given in framebuffer pixels. The GLFW window (cmd_view.cpp) and the
// headless backends drive the same object, so a screenshot shows what a person sees.
#pragma once

#include "methods/factory.h"
#include "methods/session.h"
#include "present/overlays.h"
#include "trace/integrator.h"

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

class DisplayRenderer;
class ImGuiRenderer;

struct ViewOptions {
  std::shared_ptr<const PreparedScene> scene;  // as loaded; camera moves make views of it
  MethodKind method = MethodKind::Bp;
  // Every method's configuration, in MethodKind's order: what the panel edits, kept when
  // the panel switches to another method and back.
  std::vector<MethodConfig> configs = defaultConfigs();
  // Open-ended: the seed, the kept samples per pixel a round adds, and the target spp at
  // which rendering stops (maxSpp; 0 = refine until stopped).
  RunShape shape = RunShape::progressive(1);
  int threads = 0;          // render threads (0 = all cores)
  bool preview = true;      // a block preview before each (re)start (the window; not headless)
  int rounds = -1;          // pause after this many rounds of each (re)start (-1: run on)
  bool background = false;  // render at a lower priority than the UI thread (the window)
  std::shared_ptr<const Image> reference;
  std::string referencePath;
  MapId overlay = MapId::None;  // the map shown over the image
  float blend = 0.7f;
  DisplaySettings display;
  bool showRaw = false;  // the raw estimate instead of the reconstruction
  std::string saveDirectory = ".";

  MethodSpec spec() const { return {shape, configs[size_t(method)]}; }
  // The filter scales BP's maps are labelled with.
  const std::vector<float>& alphas() const {
    return std::get<BpConfig>(configs[size_t(MethodKind::Bp)]).filter.alphas;
  }
};

// Frame timing of the UI thread, for the panel and the window test's report.
struct FrameStats {
  uint64_t frames = 0;
  double totalSeconds = 0, maxSeconds = 0, lastSeconds = 0;
  std::vector<float> recent;  // the last frame times (seconds), for a percentile
  void add(double seconds);
  double percentile(double q) const;
};

class ViewerApp {
 public:
  explicit ViewerApp(ViewOptions options);  // starts rendering; needs no GL
  ~ViewerApp();
  ViewerApp(const ViewerApp&) = delete;
  ViewerApp& operator=(const ViewerApp&) = delete;

  // GL resources: after a context is current, before the first draw; withUi creates the
  // ImGui context and renderer too. Throws GlError on a shader problem.
  void initGl(bool withUi);
  void releaseGl();  // before the context goes away

  // Takes the newest snapshot and inspection, if any; true when the picture changed.
  bool update();
  // Draws a frame of width x height framebuffer pixels (no-op when either is 0). With the
  // UI, ImGui's platform side must have set io (window) or drawFrame sets it (headless).
  void drawFrame(int width, int height, bool ui, double deltaSeconds);

  // Input, in framebuffer pixels (y down). Keys and buttons use GLFW's codes.
  void keyEvent(int key, bool down, int mods);
  void mouseButton(int button, bool down, double x, double y, int mods);
  void mouseMoved(double x, double y);
  void scrolled(double dy, double x, double y, int mods);
  void resized(int width, int height);
  // Moves the camera for held fly keys (WASD, Q/E) over dt seconds; restarts if it moved.
  void fly(double dt);

  // Control.
  void restart();  // with the current camera and parameters
  void setOverlay(MapId overlay);
  void fitView();  // zoom 1 (or less to fit), centred
  // Zoom (screen pixels per image pixel) with image position (x, y) at the centre; x < 0
  // keeps the current centre.
  void setView(float zoom, float x, float y);
  void inspectPixel(int x, int y);
  bool quitRequested() const { return quit_; }
  // Writes the shown image (linear .exr/.pfm or .png with the exposure); returns a message.
  std::string saveImage(const std::string& path) const;
  // Asks for a screenshot of the next drawn frame (written after it is drawn).
  void requestScreenshot(const std::string& path) { screenshotPath_ = path; }
  // Writes the frame just drawn (the bound framebuffer); throws ImageIoError.
  void writeScreenshot(const std::string& path, int width, int height) const;

  RenderSession& session() { return *session_; }
  const ViewOptions& options() const { return options_; }
  std::shared_ptr<const Snapshot> snapshot() const { return snapshot_; }
  const OverlayImage& overlayImage() const { return overlayImage_; }
  // Height of the legend band under the image for a framebuffer `width` wide (0 without an
  // overlay); a headless screenshot adds it to the image height.
  int legendBand(int width);
  int restarts() const { return restarts_; }
  // A round of the current view (not the preview) is the shown snapshot.
  bool roundShown() const {
    return snapshot_ && snapshot_->source == SnapshotSource::Method && snapshot_->round > 0;
  }
  // Seconds from each (re)start to its first picture.
  const std::vector<double>& firstPictureTimes() const { return firstPictureTimes_; }
  const FrameStats& frameStats() const { return frameStats_; }
  // The window times whole frames (draw and swap) itself; drawFrame times only its own work.
  void recordFrame(double seconds) { frameStats_.add(seconds); }
  void setRecordFrameTimes(bool own) { recordFrameTimes_ = own; }
  const std::string& lastMessage() const { return message_; }

 private:
  friend void drawPanel(ViewerApp& app);  // view_panel.cpp
  friend void drawInspector(ViewerApp& app);

  void setCamera(const Camera& camera);
  void refreshOverlay();
  void toScreen(double x, double y, float& imageX, float& imageY) const;
  void zoomAt(float factor, double x, double y);
  int panelReserve() const;         // width the panel takes on the left, 0 without it
  const Image& shownImage() const;  // raw or reconstructed; needs a snapshot

  ViewOptions options_;
  std::unique_ptr<RenderSession> session_;
  Camera camera_;
  std::string configError_;  // why the panel's parameters cannot start

  // What is shown.
  std::shared_ptr<const Snapshot> snapshot_;
  std::shared_ptr<const PixelInspection> inspection_;
  uint64_t seenVersion_ = 0, seenInspection_ = 0;
  uint64_t generation_ = 0;  // the session's generation of the last restart
  OverlayImage overlayImage_;
  Image legendStrip_;
  bool overlayStale_ = true;                           // overlay and legend to rebuild on the CPU
  bool texturesStale_ = true;                          // textures to upload
  std::vector<std::pair<double, double>> mseHistory_;  // (kept spp, MSE) against the reference
  int restarts_ = 0;
  std::chrono::steady_clock::time_point restartTime_;
  double firstPreviewSeconds_ = -1;  // restart to first snapshot, the last restart
  std::vector<double> firstPictureTimes_;

  // View and input.
  int width_ = 1, height_ = 1;  // framebuffer
  float zoom_ = 1.0f, centerX_ = 0.0f, centerY_ = 0.0f;
  bool fitted_ = false;
  int inspectX_ = -1, inspectY_ = -1;
  bool dragging_[3] = {false, false, false};
  double lastX_ = 0, lastY_ = 0, cursorX_ = -1, cursorY_ = -1, pressX_ = 0, pressY_ = 0;
  bool held_[512] = {};
  bool quit_ = false;
  bool showPanel_ = true, showInspector_ = true, showHelp_ = false;
  std::string screenshotPath_;
  std::string message_;
  char savePath_[512] = "penumbra.exr";
  char screenshotField_[512] = "screenshot.png";
  FrameStats frameStats_;
  bool recordFrameTimes_ = true;

  std::unique_ptr<DisplayRenderer> renderer_;
  std::unique_ptr<ImGuiRenderer> imgui_;
  bool ownsImGui_ = false;
};

}  // namespace penumbra
