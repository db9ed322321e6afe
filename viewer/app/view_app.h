// The progressive viewer, independent of where it draws: it runs a RenderSession on the
// scene, turns each new snapshot into textures (image, overlay, slices, legend), draws them
// and the Dear ImGui panel into the bound framebuffer, and reacts to input (keys, mouse,
// scroll, resize) given in framebuffer pixels. The GLFW window (cmd_view.cpp) and the
// headless backends drive the same object, so a screenshot shows what a person sees.
// Its parts: view_state.h (the plain data), view_app.cpp (session and snapshots),
// view_input.cpp (input), view_draw.cpp (textures and drawing), view_panel.* (ImGui windows).
#pragma once

#include "methods/session.h"
#include "viewer/app/view_state.h"

#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// Seconds from a to b on the steady clock the window times itself with.
inline double secondsBetween(std::chrono::steady_clock::time_point a,
                             std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

class DisplayRenderer;
class ImGuiRenderer;

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

  // Live reload: when a file the scene was read from has changed since the last check (its
  // time or size), reads the scene again (ViewOptions::loadScene) and restarts; the camera
  // stays unless the file's own camera changed. A file that fails to load leaves the last
  // good scene rendering and its error in the panel's message. Returns true when it
  // reloaded. This waits for the read; update() instead looks at most twice a second and reads
  // on a thread of its own, taking the new scene in once it is ready, so the window never
  // stalls on a large scene.
  bool checkSceneFiles();
  // Opens another scene file (dropped on the window, or typed in the panel) with its own
  // camera; on failure the current scene stays and the error is the message. True if opened.
  bool openScene(const std::string& path);

  // Control.
  void restart();  // with the current camera and parameters
  void setOverlay(MapId overlay);
  void fitView();  // zoom 1 (or less to fit), centred
  // Zoom (screen pixels per image pixel) with image position (x, y) at the centre; x < 0
  // keeps the current centre.
  void setView(float zoom, float x, float y);
  void inspectPixel(int x, int y);
  // Renders only `region` (clamped to the image; an empty one renders everything) and
  // restarts; the picture outside keeps the last image, dimmed.
  void setRegion(RenderRegion region);
  // Changes the environment (the panel's Environment section) and restarts; the change stays
  // applied when the scene's files reload. A map that cannot be read leaves all as it was.
  void setEnvironment(EnvironmentEdit edit);
  bool quitRequested() const { return view_.quit; }
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
  // Restart to the first picture of the method itself (every pixel sampled), per restart.
  const std::vector<double>& firstFullPictureTimes() const { return firstFullPictureTimes_; }
  // The method's trace speed since the last (re)start, measured as a batch render's is: kept
  // samples per pixel over the method's own wall time, at its newest snapshot shown (so the
  // lag until a snapshot is shown is left out); 0 until one has been shown.
  double traceSpeed() const;
  int reloads() const { return reloads_; }  // live reloads that loaded (checkSceneFiles)
  const FrameStats& frameStats() const { return frameStats_; }
  // The window times whole frames (draw and swap) itself; drawFrame times only its own work.
  void recordFrame(double seconds) { frameStats_.add(seconds); }
  void setRecordFrameTimes(bool own) { recordFrameTimes_ = own; }
  const std::string& lastMessage() const { return message_; }
  const ViewState& viewState() const { return view_; }  // camera, zoom, inspected pixel

 private:
  void setCamera(const Camera& camera);
  void refreshOverlay();
  void zoomAt(float factor, double x, double y);
  int panelReserve() const;         // width the panel takes on the left, 0 without it
  const Image& shownImage() const;  // raw or reconstructed; needs a snapshot
  void drawUi(int width, int height, double deltaSeconds);  // the ImGui windows

  // Modification time and size of each watched file, (-1, -1) when missing.
  using FileStamp = std::pair<long long, long long>;
  std::vector<FileStamp> stampFiles() const;
  void watchSceneFiles();
  bool startReload();    // a watched file changed: read the scene again on a thread
  bool finishReload();   // the read is done: take it in and restart, or keep the last good one
  void discardReload();  // wait for a read in flight and drop it; the next check reads again
  std::future<std::shared_ptr<const PreparedScene>> reload_;
  // A snapshot of the region's view placed in the full image over the dimmed backdrop.
  std::shared_ptr<const Snapshot> placeInRegion(std::shared_ptr<const Snapshot> snapshot) const;
  void inspectInSession(int x, int y);  // image pixel -> the running view's pixel

  ViewOptions options_;
  std::unique_ptr<RenderSession> session_;
  std::vector<std::string> watched_;
  Image backdrop_;  // the full picture when the region was set (shown dimmed outside it)
  std::vector<FileStamp> stamps_;
  std::chrono::steady_clock::time_point lastFileCheck_;
  std::string configError_;                         // why the panel's parameters cannot start
  std::optional<EnvironmentEdit> environmentEdit_;  // the panel's, reapplied on reload
  void syncEnvironmentFields();                     // the panel's fields from the scene

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
  bool fullPictureShown_ = false;  // since the last restart
  std::vector<double> firstFullPictureTimes_;
  // The method's (seconds, kept spp) at its newest snapshot shown since the restart.
  std::pair<double, double> traceLast_{-1, 0};
  int reloads_ = 0;

  // View and input.
  ViewState view_;
  InputState input_;
  std::string screenshotPath_;
  std::string message_;
  FrameStats frameStats_;
  bool recordFrameTimes_ = true;

  std::unique_ptr<DisplayRenderer> renderer_;
  std::unique_ptr<ImGuiRenderer> imgui_;
  bool ownsImGui_ = false;
};

}  // namespace penumbra
