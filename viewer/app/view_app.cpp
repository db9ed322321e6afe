#include "viewer/app/view_app.h"

#include "core/stats.h"

#include "core/image_io.h"
#include "eval/metrics.h"
#include "scene/camera_control.h"
#include "trace/preview.h"
#include "viewer/app/gl/context.h"
#include "viewer/app/gl/display_renderer.h"
#include "viewer/app/gl/imgui_renderer.h"

#include <glad/gl.h>
// After glad: GLFW only for its key and button codes here.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// Block size of the first preview after a restart: about 64 blocks across.
int previewBlock(int width) { return std::clamp(width / 64, 2, 16); }

// Room the panel takes on the left of the window (its width plus margins).
constexpr int kPanelWidth = 356;

}  // namespace

void FrameStats::add(double seconds) {
  ++frames;
  totalSeconds += seconds;
  maxSeconds = std::max(maxSeconds, seconds);
  lastSeconds = seconds;
  recent.push_back(float(seconds));
  if (recent.size() > 600) recent.erase(recent.begin(), recent.begin() + 300);
}

double FrameStats::percentile(double q) const { return lowerQuantile(recent, q).value_or(0.0f); }

ViewerApp::ViewerApp(ViewOptions options) : options_(std::move(options)) {
  if (!options_.scene) throw std::invalid_argument("ViewerApp: no scene");
  camera_ = options_.scene->scene.camera;
  session_ = std::make_unique<RenderSession>(options_.threads, options_.background);
  restart();
}

ViewerApp::~ViewerApp() {
  session_.reset();  // joins the worker before the views it renders go away
  releaseGl();
}

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

void ViewerApp::restart() {
  std::shared_ptr<const PreparedScene> view;
  try {
    view = prepareView(*options_.scene, camera_);
  } catch (const std::exception& e) {
    message_ = e.what();
    return;
  }
  const MethodSpec spec = options_.spec();
  configError_ = validate(spec);
  if (!configError_.empty()) {
    message_ = "not restarted: " + configError_;
    return;
  }
  // The factory owns the view, which the method refers to, for as long as the method runs,
  // and a copy of the spec: it runs on the worker thread.
  restartTime_ = Clock::now();
  generation_ =
      session_->restart([view, spec] { return makeMethod(*view, spec); }, options_.rounds);
  if (inspectX_ >= 0) session_->inspect(inspectX_, inspectY_);
  ++restarts_;
  firstPreviewSeconds_ = -1;
  mseHistory_.clear();
  if (options_.preview) {
    // Drawn here, on the UI thread, so the new view shows within a frame whatever the
    // render threads are doing; the method's first round replaces it.
    auto preview = std::make_shared<Snapshot>();
    preview->source = SnapshotSource::Preview;
    preview->method = "preview";
    preview->width = view->scene.settings.width;
    preview->height = view->scene.settings.height;
    preview->raw = renderPreview(*view, options_.shape.seed, previewBlock(preview->width));
    preview->reconstructed = preview->raw;
    snapshot_ = std::move(preview);
    overlayStale_ = texturesStale_ = true;
    firstPreviewSeconds_ = secondsBetween(restartTime_, Clock::now());
    firstPictureTimes_.push_back(firstPreviewSeconds_);
  }
}

void ViewerApp::setCamera(const Camera& camera) {
  camera_ = camera;
  restart();
}

bool ViewerApp::update() {
  bool changed = false;
  const uint64_t version = session_->version();
  uint64_t generation = 0;
  std::shared_ptr<const Snapshot> latest;
  if (version != seenVersion_) latest = session_->latest(&generation);
  // A snapshot of the method before the last restart is an old view: not shown.
  if (version != seenVersion_ && generation == generation_) {
    seenVersion_ = version;
    snapshot_ = std::move(latest);
    // The first round after a restart, when there was no preview.
    if (snapshot_ && firstPreviewSeconds_ < 0) {
      firstPreviewSeconds_ = secondsBetween(restartTime_, Clock::now());
      firstPictureTimes_.push_back(firstPreviewSeconds_);
    }
    if (snapshot_ && options_.reference && snapshot_->source != SnapshotSource::Preview) {
      const Image& shown = shownImage();
      if (shown.width == options_.reference->width && shown.height == options_.reference->height) {
        const double spp = double(snapshot_->keptSamples) /
                           std::max(1.0, double(snapshot_->width) * snapshot_->height);
        mseHistory_.push_back({spp, compareImages(shown, *options_.reference).mse});
      }
    }
    overlayStale_ = texturesStale_ = true;
    changed = true;
  }
  if (overlayStale_) {
    refreshOverlay();
    overlayStale_ = false;
    texturesStale_ = true;
  }
  const uint64_t inspections = session_->inspectionVersion();
  if (inspections != seenInspection_) {
    seenInspection_ = inspections;
    inspection_ = session_->inspection();
    changed = true;
  }
  return changed || texturesStale_;
}

void ViewerApp::refreshOverlay() {
  overlayImage_ = OverlayImage{};
  overlayImage_.overlay = options_.overlay;
  legendStrip_ = Image();
  if (!snapshot_ || options_.overlay == MapId::None) return;
  const Image& shown = shownImage();
  overlayImage_ = buildOverlay(*snapshot_, options_.overlay, shown, options_.reference.get());
  if (overlayImage_.available())
    legendStrip_ = drawMapWithLegend({}, std::max(1, width_ - panelReserve()), 0,
                                     overlayImage_.label, overlayImage_.legend);
}

int ViewerApp::legendBand(int width) {
  if (width != width_) {
    width_ = std::max(1, width);
    overlayStale_ = true;
  }
  if (overlayStale_) update();
  return legendStrip_.empty() ? 0 : legendStrip_.height;
}

void ViewerApp::drawFrame(int width, int height, bool ui, double deltaSeconds) {
  if (width <= 0 || height <= 0 || !renderer_) return;  // minimised: nothing to draw
  const auto start = Clock::now();
  if (width != width_ || height != height_) resized(width, height);
  if (overlayStale_) update();
  if (!fitted_ && snapshot_) fitView();
  if (texturesStale_ && snapshot_) {
    const Image& shown = shownImage();
    renderer_->setImage(shown);
    if (overlayImage_.available()) renderer_->setOverlay(overlayImage_.colors);
    renderer_->setLegend(legendStrip_);
    renderer_->setSlices(*snapshot_);
    texturesStale_ = false;
  }
  DisplayView view;
  view.zoom = zoom_;
  view.centerX = centerX_;
  view.centerY = centerY_;
  view.display = options_.display;
  view.overlay = overlayImage_.available();
  view.blend = options_.blend;
  view.slicesPerSide = snapshot_ ? snapshot_->slicesPerSide : 0;
  view.slices = options_.overlay == MapId::Selected && zoom_ >= 8.0f && view.slicesPerSide > 0;
  view.inspectedX = inspectX_;
  view.inspectedY = inspectY_;
  view.legendHeight = legendStrip_.height;
  view.legendLeft = panelReserve();
  glClearColor(0.12f, 0.12f, 0.13f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  renderer_->draw(width, height, view);

  if (ui && imgui_) {
    ImGuiIO& io = ImGui::GetIO();
    if (!io.BackendPlatformName) {  // headless: no platform backend sets these
      io.DisplaySize = ImVec2(float(width), float(height));
      io.DeltaTime = float(std::max(deltaSeconds, 1e-4));
    }
    ImGui::NewFrame();
    if (showPanel_) drawPanel(*this);
    if (showInspector_ && inspectX_ >= 0) drawInspector(*this);
    ImGui::Render();
    imgui_->render(ImGui::GetDrawData(), width, height);
  }
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

void ViewerApp::writeScreenshot(const std::string& path, int width, int height) const {
  std::vector<uint8_t> rgba = readFramebuffer(width, height);
  std::vector<uint8_t> rgb(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = rgba[4 * i + k];
  writePng8(path, width, height, 3, rgb);
}

std::string ViewerApp::saveImage(const std::string& path) const {
  if (!snapshot_) return "nothing rendered yet";
  const Image& shown = shownImage();
  try {
    writeImage(path, shown, options_.display.exposure);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "saved " + path;
}

void ViewerApp::resized(int width, int height) {
  if (width <= 0 || height <= 0) return;  // minimised or zero-sized: keep the last view
  const bool refit = fitted_ && width_ > 1;
  if (width != width_) overlayStale_ = true;  // the legend strip follows the width
  width_ = width;
  height_ = height;
  texturesStale_ = true;
  if (refit) fitView();
}

void ViewerApp::fitView() {
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  // The image fits above the legend band and right of the panel, when there is room.
  const int band = legendStrip_.height;
  const int panel = panelReserve();
  const float room = float(std::max(1, height_ - band));
  const float fit = std::min(float(std::max(1, width_ - panel)) / float(w), room / float(h));
  zoom_ = fit >= 1.0f ? std::floor(fit) : fit;  // whole zoom steps keep pixels square and crisp
  centerX_ = 0.5f * float(w) - 0.5f * float(panel) / zoom_;
  centerY_ = 0.5f * float(h) + 0.5f * float(band) / zoom_;
  fitted_ = true;
}

const Image& ViewerApp::shownImage() const {
  return options_.showRaw || snapshot_->reconstructed.empty() ? snapshot_->raw
                                                              : snapshot_->reconstructed;
}

int ViewerApp::panelReserve() const {
  const int w = options_.scene->scene.settings.width;
  return imgui_ && showPanel_ && width_ >= w + kPanelWidth ? kPanelWidth : 0;
}

void ViewerApp::setView(float zoom, float x, float y) {
  zoom_ = std::clamp(zoom, 0.05f, 256.0f);
  if (x >= 0 && y >= 0) {
    centerX_ = x;
    centerY_ = y;
  }
  fitted_ = true;
}

void ViewerApp::toScreen(double x, double y, float& imageX, float& imageY) const {
  imageX = centerX_ + float(x - 0.5 * width_) / zoom_;
  imageY = centerY_ + float(y - 0.5 * height_) / zoom_;
}

void ViewerApp::zoomAt(float factor, double x, double y) {
  float ix, iy;
  toScreen(x, y, ix, iy);
  zoom_ = std::clamp(zoom_ * factor, 0.05f, 256.0f);
  // Keep the image point under the cursor where it was.
  centerX_ = ix - float(x - 0.5 * width_) / zoom_;
  centerY_ = iy - float(y - 0.5 * height_) / zoom_;
}

void ViewerApp::setOverlay(MapId overlay) {
  options_.overlay = overlay;
  overlayStale_ = true;
}

void ViewerApp::inspectPixel(int x, int y) {
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  if (x < 0 || y < 0 || x >= w || y >= h) {
    inspectX_ = inspectY_ = -1;
    session_->inspect(-1, -1);
    return;
  }
  inspectX_ = x;
  inspectY_ = y;
  session_->inspect(x, y);
}

void ViewerApp::keyEvent(int key, bool down, int mods) {
  if (key >= 0 && key < 512) held_[key] = down;
  if (!down) return;
  const auto list = overlayList();
  if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + int(list.size())) {
    setOverlay(list[size_t(key - GLFW_KEY_1)].id);
    return;
  }
  switch (key) {
    case GLFW_KEY_0:
    case GLFW_KEY_GRAVE_ACCENT:
      setOverlay(MapId::None);
      break;
    case GLFW_KEY_R:
      options_.showRaw = !options_.showRaw;
      overlayStale_ = true;  // the reference error follows the shown image
      break;
    case GLFW_KEY_SPACE:
      if (session_->state() == RenderSession::State::Paused)
        session_->resume();
      else
        session_->pause();
      break;
    case GLFW_KEY_N:
      session_->step();
      break;
    case GLFW_KEY_F:
      fitView();
      break;
    case GLFW_KEY_TAB:
      showPanel_ = !showPanel_;
      break;
    case GLFW_KEY_I:
      showInspector_ = !showInspector_;
      break;
    case GLFW_KEY_F1:
    case GLFW_KEY_H:
      showHelp_ = !showHelp_;
      break;
    case GLFW_KEY_MINUS:
      options_.display.exposure -= 0.5f;
      break;
    case GLFW_KEY_EQUAL:
      options_.display.exposure += 0.5f;
      break;
    case GLFW_KEY_T:
      options_.display.curve =
          options_.display.curve == ToneCurve::Srgb ? ToneCurve::Filmic : ToneCurve::Srgb;
      break;
    case GLFW_KEY_LEFT_BRACKET:
      options_.blend = std::max(0.0f, options_.blend - 0.1f);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      options_.blend = std::min(1.0f, options_.blend + 0.1f);
      break;
    case GLFW_KEY_P:
      requestScreenshot(options_.saveDirectory + "/" + screenshotField_);
      break;
    case GLFW_KEY_S:
      if (mods & GLFW_MOD_CONTROL) message_ = saveImage(options_.saveDirectory + "/" + savePath_);
      break;
    case GLFW_KEY_ESCAPE:
      quit_ = true;
      break;
    default:
      break;
  }
}

void ViewerApp::fly(double dt) {
  float right = 0, up = 0, forward = 0;
  const auto pressed = [&](int key) { return held_[key] ? 1.0f : 0.0f; };
  forward = pressed(GLFW_KEY_W) - pressed(GLFW_KEY_S);
  right = pressed(GLFW_KEY_D) - pressed(GLFW_KEY_A);
  up = pressed(GLFW_KEY_E) - pressed(GLFW_KEY_Q);
  if (right == 0 && up == 0 && forward == 0) return;
  // Speed: a third of the distance to the look-at point per second.
  const float distance = std::max(1e-3f, glm::length(camera_.lookAt - camera_.eye));
  const float step = float(dt) * distance / 3.0f;
  setCamera(flyCamera(camera_, right * step, up * step, forward * step));
}

void ViewerApp::mouseButton(int button, bool down, double x, double y, int mods) {
  if (button < 0 || button > 2) return;
  if (down) {
    dragging_[button] = true;
    lastX_ = x;
    lastY_ = y;
    cursorX_ = x;
    cursorY_ = y;
    // Shift + left pans the image, like the middle button.
    if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)) {
      dragging_[button] = false;
      dragging_[GLFW_MOUSE_BUTTON_MIDDLE] = true;
    }
    pressX_ = x;
    pressY_ = y;
    return;
  }
  const bool wasLeft = button == GLFW_MOUSE_BUTTON_LEFT && dragging_[button];
  dragging_[button] = false;
  if (button == GLFW_MOUSE_BUTTON_LEFT) dragging_[GLFW_MOUSE_BUTTON_MIDDLE] = false;
  // A click (no drag) on the left button inspects the pixel under the cursor.
  if (wasLeft && std::abs(x - pressX_) < 3 && std::abs(y - pressY_) < 3) {
    float ix, iy;
    toScreen(x, y, ix, iy);
    inspectPixel(int(std::floor(ix)), int(std::floor(iy)));
  }
}

void ViewerApp::mouseMoved(double x, double y) {
  const double dx = x - lastX_, dy = y - lastY_;
  lastX_ = x;
  lastY_ = y;
  cursorX_ = x;
  cursorY_ = y;
  if (dx == 0 && dy == 0) return;
  if (dragging_[GLFW_MOUSE_BUTTON_MIDDLE]) {
    centerX_ -= float(dx) / zoom_;
    centerY_ -= float(dy) / zoom_;
    return;
  }
  const bool clickSized = std::abs(x - pressX_) < 3 && std::abs(y - pressY_) < 3;
  if (dragging_[GLFW_MOUSE_BUTTON_LEFT] && !clickSized) {
    setCamera(orbitCamera(camera_, float(-dx) * 0.006f, float(dy) * 0.006f));
  } else if (dragging_[GLFW_MOUSE_BUTTON_RIGHT]) {
    const float shown = float(options_.scene->scene.settings.height) * zoom_;
    setCamera(panCamera(camera_, float(dx) / shown, float(dy) / shown));
  }
}

void ViewerApp::scrolled(double dy, double x, double y, int mods) {
  if (dy == 0) return;
  if (mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT)) {
    setCamera(dollyCamera(camera_, std::pow(0.9f, float(dy))));
    return;
  }
  zoomAt(std::pow(1.25f, float(dy)), x, y);
}

}  // namespace penumbra
