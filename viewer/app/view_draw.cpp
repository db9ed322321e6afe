// ViewerApp's drawing: GL resources, the overlay and legend rebuilt from the snapshot, the
// textures uploaded when stale, the image, the ImGui windows (view_panel.h) and screenshots of
// the bound framebuffer; and the layout they share (the panel's room, fitting the image).
#include "viewer/app/view_app.h"

#include "core/image_io.h"
#include "viewer/app/gl/context.h"
#include "viewer/app/gl/display_renderer.h"
#include "viewer/app/gl/imgui_renderer.h"
#include "viewer/app/view_panel.h"

#include <glad/gl.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

// Room the panel takes on the left of the window (its width plus margins).
constexpr int kPanelWidth = 356;

}  // namespace

void ViewerApp::initGl(bool withUi) {
  renderer_ = std::make_unique<DisplayRenderer>();
  if (withUi) {
    if (!ImGui::GetCurrentContext()) {
      IMGUI_CHECKVERSION();
      ImGui::CreateContext();
      ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
      ImGui::StyleColorsDark();
      ownsImGui_ = true;
    }
    imgui_ = std::make_unique<ImGuiRenderer>();
  }
  texturesStale_ = true;
}

void ViewerApp::releaseGl() {
  imgui_.reset();
  renderer_.reset();
  if (ownsImGui_) {
    ImGui::DestroyContext();
    ownsImGui_ = false;
  }
}

void ViewerApp::refreshOverlay() {
  overlayImage_ = OverlayImage{};
  overlayImage_.overlay = options_.overlay;
  legendStrip_ = Image();
  if (!snapshot_ || options_.overlay.none()) return;
  const Image& shown = shownImage();
  overlayImage_ = buildOverlay(*snapshot_, options_.overlay, shown, options_.reference.get());
  if (overlayImage_.available())
    legendStrip_ = drawMapWithLegend({}, std::max(1, view_.width - panelReserve()), 0,
                                     overlayImage_.label, overlayImage_.legend);
}

int ViewerApp::legendBand(int width) {
  if (width != view_.width) {
    view_.width = std::max(1, width);
    overlayStale_ = true;
  }
  if (overlayStale_) update();
  return legendStrip_.empty() ? 0 : legendStrip_.height;
}

void ViewerApp::drawFrame(int width, int height, bool ui, double deltaSeconds) {
  if (width <= 0 || height <= 0 || !renderer_) return;  // minimised: nothing to draw
  const auto start = Clock::now();
  if (width != view_.width || height != view_.height) resized(width, height);
  if (overlayStale_) update();
  if (!view_.fitted && snapshot_) fitView();
  if (texturesStale_ && snapshot_) {
    const Image& shown = shownImage();
    renderer_->setImage(shown);
    // Overlay and slices are uploaded only while they can be drawn (the slices with the
    // Selected overlay): at 1920x1080 each full-size texture is tens of MB.
    renderer_->setOverlay(overlayImage_.available() ? overlayImage_.colors : Image());
    renderer_->setLegend(legendStrip_);
    if (options_.overlay == maps::Selected)
      renderer_->setSlices(*snapshot_);
    else
      renderer_->clearSlices();
    texturesStale_ = false;
  }
  DisplayView view;
  view.zoom = view_.zoom;
  view.centerX = view_.centerX;
  view.centerY = view_.centerY;
  view.display = options_.display;
  view.overlay = overlayImage_.available();
  view.blend = options_.blend;
  // The slices the method's maps of slice indices say (their kinds' SliceRole).
  view.slicesPerSide = 0;
  if (snapshot_)
    for (const SnapshotMap& map : snapshot_->maps)
      if (map.id.kind()->slices != SliceRole::None) view.slicesPerSide = map.slicesPerSide;
  view.slices = options_.overlay == maps::Selected && view_.zoom >= 8.0f && view.slicesPerSide > 0;
  view.inspectedX = view_.inspectX;
  view.inspectedY = view_.inspectY;
  if (view_.region.active()) {
    view.regionX = view_.region.x;
    view.regionY = view_.region.y;
    view.regionWidth = view_.region.width;
    view.regionHeight = view_.region.height;
  }
  view.legendHeight = legendStrip_.height;
  view.legendLeft = panelReserve();
  glClearColor(0.12f, 0.12f, 0.13f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  renderer_->draw(width, height, view);

  if (ui && imgui_) drawUi(width, height, deltaSeconds);
  if (recordFrameTimes_) frameStats_.add(secondsBetween(start, Clock::now()));
  if (!screenshotPath_.empty()) {
    const std::string path = screenshotPath_;
    screenshotPath_.clear();
    try {
      writeScreenshot(path, width, height);
      message_ = "screenshot: " + path;
    } catch (const std::exception& e) {
      message_ = e.what();
    }
  }
}

void ViewerApp::drawUi(int width, int height, double deltaSeconds) {
  ImGuiIO& io = ImGui::GetIO();
  if (!io.BackendPlatformName) {  // headless: no platform backend sets these
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DeltaTime = float(std::max(deltaSeconds, 1e-4));
  }
  ImGui::NewFrame();
  const PanelState state{options_,    view_,         *session_,   snapshot_,
                         inspection_, overlayImage_, mseHistory_, firstPreviewSeconds_,
                         frameStats_, configError_,  message_};
  const PanelActions actions{
      [this] { restart(); },
      [this](MapId overlay) { setOverlay(overlay); },
      [this] { overlayStale_ = true; },  // the reference error follows the shown image
      [this](const std::string& path) { return saveImage(path); },
      [this](const std::string& path) { requestScreenshot(path); },
      [this](int x, int y) { inspectPixel(x, y); },
      [this](const std::string& path) { openScene(path); },
      [this](RenderRegion region) { setRegion(region); },
      [this](const EnvironmentEdit& edit) { setEnvironment(edit); }};
  if (view_.showPanel) drawPanel(state, actions);
  if (view_.showInspector && view_.inspectX >= 0) drawInspector(state, actions);
  ImGui::Render();
  imgui_->render(ImGui::GetDrawData(), width, height);
}

void ViewerApp::writeScreenshot(const std::string& path, int width, int height) const {
  std::vector<uint8_t> rgba = readFramebuffer(width, height);
  std::vector<uint8_t> rgb(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = rgba[4 * i + k];
  writePng8(path, width, height, 3, rgb);
}

void ViewerApp::fitView() {
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  // The image fits above the legend band and right of the panel, when there is room.
  const int band = legendStrip_.height;
  const int panel = panelReserve();
  const float room = float(std::max(1, view_.height - band));
  const float fit = std::min(float(std::max(1, view_.width - panel)) / float(w), room / float(h));
  view_.zoom =
      fit >= 1.0f ? std::floor(fit) : fit;  // whole zoom steps keep pixels square and crisp
  view_.centerX = 0.5f * float(w) - 0.5f * float(panel) / view_.zoom;
  view_.centerY = 0.5f * float(h) + 0.5f * float(band) / view_.zoom;
  view_.fitted = true;
}

int ViewerApp::panelReserve() const {
  const int w = options_.scene->scene.settings.width;
  return imgui_ && view_.showPanel && view_.width >= w + kPanelWidth ? kPanelWidth : 0;
}

}  // namespace penumbra
