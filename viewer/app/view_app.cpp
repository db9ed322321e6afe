// ViewerApp's session and snapshot plumbing: it starts the RenderSession (with a block
// preview drawn on the UI thread), takes each new snapshot and inspection, keeps the MSE
// against the reference, and saves the shown image. Input is in view_input.cpp, textures and
// drawing in view_draw.cpp.
#include "viewer/app/view_app.h"

#include "core/image_io.h"
#include "core/stats.h"
#include "eval/metrics.h"
#include "scene/scene_loader.h"
#include "trace/preview.h"
// Complete types for the GL members the constructor and destructor own.
#include "viewer/app/gl/display_renderer.h"
#include "viewer/app/gl/imgui_renderer.h"

#include <algorithm>
#include <filesystem>

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

// Block size of the first preview after a restart: about 64 blocks across.
int previewBlock(int width) { return std::clamp(width / 64, 2, 16); }

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
  view_.camera = options_.scene->scene.camera;
  session_ = std::make_unique<RenderSession>(options_.threads, options_.background);
  watchSceneFiles();
  view_.region = options_.region;
  syncEnvironmentFields();
  // The method's maps only while an overlay shows one (they cost about 0.1 s a picture at
  // 1280x720).
  session_->setMapsWanted(!options_.overlay.none());
  restart();
}

namespace {
// The scene lit as the panel says, sharing base's geometry.
std::unique_ptr<PreparedScene> relight(const PreparedScene& base, const EnvironmentEdit& edit) {
  Scene scene = base.scene;
  if (!edit.file.empty()) replaceEnvironment(scene, edit.file);
  Environment& e = scene.environment;
  if (e.present()) {
    e.strength = edit.strength;
    e.rotationDegrees = edit.rotationDegrees;
  }
  return prepareLighting(base, std::move(scene));
}
}  // namespace

void ViewerApp::syncEnvironmentFields() {
  const Environment& e = options_.scene->scene.environment;
  view_.environmentStrength = e.strength;
  view_.environmentRotation = e.rotationDegrees;
}

void ViewerApp::setEnvironment(EnvironmentEdit edit) {
  discardReload();  // it lit the scene the old way: read again with this edit
  std::shared_ptr<const PreparedScene> relit;
  const size_t warningsBefore = options_.scene->scene.warnings.size();
  try {
    relit = relight(*options_.scene, edit);  // an empty file keeps the map: no read
  } catch (const std::exception& e) {
    message_ = std::string("environment not changed: ") + e.what();
    return;
  }
  // A strength or rotation alone keeps the map an earlier edit chose, which a reload reads again.
  if (edit.file.empty() && environmentEdit_) edit.file = environmentEdit_->file;
  environmentEdit_ = edit;
  options_.scene = std::move(relit);
  watchSceneFiles();
  const Environment& e = options_.scene->scene.environment;
  message_ = !e.present() ? "no environment"
                          : "environment " + (e.builtin ? std::string("(built-in)") : e.file);
  // What reading the map repaired (texels below zero or not finite, read as 0).
  if (options_.scene->scene.warnings.size() > warningsBefore)
    message_ += " (" + options_.scene->scene.warnings.back() + ")";
  restart();
}

void ViewerApp::watchSceneFiles() {
  watched_ = options_.loadScene && !options_.scenePath.empty() ? options_.scene->scene.sourceFiles
                                                               : std::vector<std::string>{};
  stamps_ = stampFiles();
  lastFileCheck_ = Clock::now();
}

std::vector<ViewerApp::FileStamp> ViewerApp::stampFiles() const {
  std::vector<FileStamp> stamps;
  for (const std::string& file : watched_) {
    std::error_code ec;
    const auto time = std::filesystem::last_write_time(file, ec);
    const auto size = ec ? std::uintmax_t(0) : std::filesystem::file_size(file, ec);
    stamps.push_back(ec ? FileStamp{-1, -1}
                        : FileStamp{(long long)time.time_since_epoch().count(), (long long)size});
  }
  return stamps;
}

bool ViewerApp::checkSceneFiles() {
  if (!reload_.valid() && !startReload()) return false;
  reload_.wait();
  return finishReload();
}

bool ViewerApp::startReload() {
  lastFileCheck_ = Clock::now();
  if (watched_.empty() || reload_.valid()) return false;
  std::vector<FileStamp> now = stampFiles();
  if (now == stamps_) return false;
  stamps_ = std::move(now);  // a file that fails stays failed until it changes again
  // Read on a thread of its own: a large scene takes seconds (its meshes, textures and BVH),
  // and the window keeps drawing and taking input meanwhile (the last good scene renders on).
  reload_ = std::async(std::launch::async, [load = options_.loadScene, path = options_.scenePath,
                                            edit = environmentEdit_] {
    std::shared_ptr<const PreparedScene> prepared = prepareScene(load(path));
    if (edit) prepared = relight(*prepared, *edit);
    return prepared;
  });
  return true;
}

void ViewerApp::discardReload() {
  if (!reload_.valid()) return;
  reload_.wait();
  reload_ = {};
  stamps_.clear();  // read again, with what changed since, at the next check
}

bool ViewerApp::finishReload() {
  std::shared_ptr<const PreparedScene> prepared;
  try {
    prepared = reload_.get();  // leaves reload_ empty
  } catch (const std::exception& e) {
    message_ = std::string("reload failed, still showing the last good scene: ") + e.what();
    return false;
  }
  const Camera oldFileCamera = options_.scene->scene.camera;
  const Camera& newFileCamera = prepared->scene.camera;
  const bool cameraChanged = oldFileCamera.eye != newFileCamera.eye ||
                             oldFileCamera.lookAt != newFileCamera.lookAt ||
                             oldFileCamera.up != newFileCamera.up ||
                             oldFileCamera.vfovDegrees != newFileCamera.vfovDegrees ||
                             oldFileCamera.orthographicHeight != newFileCamera.orthographicHeight ||
                             oldFileCamera.lensRadius != newFileCamera.lensRadius ||
                             oldFileCamera.focusDistance != newFileCamera.focusDistance ||
                             oldFileCamera.shutterOpen != newFileCamera.shutterOpen ||
                             oldFileCamera.shutterClose != newFileCamera.shutterClose;
  options_.scene = std::move(prepared);
  if (cameraChanged) view_.camera = options_.scene->scene.camera;
  watchSceneFiles();  // the new scene may refer to other files
  message_ = "reloaded " + options_.scene->scene.sourcePath;
  ++reloads_;
  restart();
  return true;
}

bool ViewerApp::openScene(const std::string& path) {
  discardReload();  // of the scene being replaced
  if (!options_.loadScene) {
    message_ = "cannot open scenes here";
    return false;
  }
  std::shared_ptr<const PreparedScene> prepared;
  try {
    prepared = prepareScene(options_.loadScene(path));
  } catch (const std::exception& e) {
    message_ = std::string("cannot open it, still showing the last scene: ") + e.what();
    return false;
  }
  options_.scene = std::move(prepared);
  options_.scenePath = path;
  view_.camera = options_.scene->scene.camera;
  environmentEdit_.reset();  // the new scene's own environment
  syncEnvironmentFields();
  watchSceneFiles();
  message_ = "opened " + path;
  restart();
  fitView();
  return true;
}

ViewerApp::~ViewerApp() {
  if (reload_.valid()) reload_.wait();
  session_.reset();  // joins the worker before the views it renders go away
  releaseGl();
}

void ViewerApp::restart() {
  std::shared_ptr<const PreparedScene> view;
  try {
    const RenderRegion& r = view_.region;
    view = r.active() ? prepareView(*options_.scene, view_.camera, r.x, r.y, r.width, r.height)
                      : prepareView(*options_.scene, view_.camera);
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
  if (view_.inspectX >= 0) inspectInSession(view_.inspectX, view_.inspectY);
  ++restarts_;
  firstPreviewSeconds_ = -1;
  fullPictureShown_ = false;
  traceLast_ = {-1, 0};
  mseHistory_.clear();
  if (options_.preview) {
    // Drawn here, on the UI thread, so the new view shows within a frame whatever the
    // render threads are doing; the method's first round replaces it. The old view's
    // snapshot goes first (the session has released it too), not after the preview is made.
    snapshot_.reset();
    auto preview = std::make_shared<Snapshot>();
    preview->source = SnapshotSource::Preview;
    preview->method = "preview";
    preview->width = view->scene.settings.width;
    preview->height = view->scene.settings.height;
    // Stored once, as raw: with no reconstruction the shown image is the raw one.
    preview->raw = renderPreview(*view, options_.shape.seed, previewBlock(preview->width));
    snapshot_ = view_.region.active() ? placeInRegion(std::move(preview)) : std::move(preview);
    overlayStale_ = texturesStale_ = true;
    firstPreviewSeconds_ = secondsBetween(restartTime_, Clock::now());
    firstPictureTimes_.push_back(firstPreviewSeconds_);
  }
}

void ViewerApp::setCamera(const Camera& camera) {
  view_.camera = camera;
  restart();
}

bool ViewerApp::update() {
  bool changed = false;
  if (reload_.valid()) {
    if (reload_.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
      changed = finishReload();
  } else if (!watched_.empty() && secondsBetween(lastFileCheck_, Clock::now()) >= 0.5) {
    startReload();
  }
  const uint64_t version = session_->version();
  uint64_t generation = 0;
  std::shared_ptr<const Snapshot> latest;
  if (version != seenVersion_) latest = session_->latest(&generation);
  // A snapshot of the method before the last restart is an old view: not shown.
  if (version != seenVersion_ && generation == generation_) {
    seenVersion_ = version;
    if (latest && latest->source == SnapshotSource::Method) {
      const double spp = double(latest->keptSamples) /
                         std::max(1.0, double(latest->width) * double(latest->height));
      traceLast_ = {latest->seconds, spp};
    }
    snapshot_ =
        latest && view_.region.active() ? placeInRegion(std::move(latest)) : std::move(latest);
    // The first round after a restart, when there was no preview.
    if (snapshot_ && firstPreviewSeconds_ < 0) {
      firstPreviewSeconds_ = secondsBetween(restartTime_, Clock::now());
      firstPictureTimes_.push_back(firstPreviewSeconds_);
    }
    // A method's snapshot has a sample in every pixel (its first round samples them all).
    if (snapshot_ && !fullPictureShown_ && snapshot_->source == SnapshotSource::Method) {
      fullPictureShown_ = true;
      firstFullPictureTimes_.push_back(secondsBetween(restartTime_, Clock::now()));
    }
    // (The reference's error is of the whole image: not measured while a region renders.)
    if (snapshot_ && options_.reference && snapshot_->source != SnapshotSource::Preview &&
        !view_.region.active()) {
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

double ViewerApp::traceSpeed() const {
  return traceLast_.first > 0 ? traceLast_.second / traceLast_.first : 0.0;
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

const Image& ViewerApp::shownImage() const { return penumbra::shownImage(*snapshot_, options_); }

void ViewerApp::setOverlay(MapId overlay) {
  options_.overlay = overlay;
  session_->setMapsWanted(!overlay.none());
  overlayStale_ = true;
}

void ViewerApp::inspectPixel(int x, int y) {
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  if (x < 0 || y < 0 || x >= w || y >= h) {
    view_.inspectX = view_.inspectY = -1;
    session_->inspect(-1, -1);
    return;
  }
  view_.inspectX = x;
  view_.inspectY = y;
  inspectInSession(x, y);
}

void ViewerApp::inspectInSession(int x, int y) {
  const RenderRegion& r = view_.region;
  if (!r.active()) {
    session_->inspect(x, y);
  } else if (r.contains(x, y)) {
    session_->inspect(x - r.x, y - r.y);
  } else {
    session_->inspect(-1, -1);
    message_ = "the inspected pixel is outside the render region";
  }
}

void ViewerApp::setRegion(RenderRegion region) {
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  const int x0 = std::clamp(region.x, 0, w), y0 = std::clamp(region.y, 0, h);
  const int x1 = std::clamp(region.x + std::max(region.width, 0), 0, w);
  const int y1 = std::clamp(region.y + std::max(region.height, 0), 0, h);
  RenderRegion clamped{x0, y0, x1 - x0, y1 - y0};
  if (!clamped.active() || (clamped.width == w && clamped.height == h)) clamped = RenderRegion{};
  if (clamped == view_.region) return;
  // What is shown now stays, dimmed, around the region.
  if (snapshot_) {
    const Image& shown = shownImage();
    if (shown.width == w && shown.height == h) backdrop_ = shown;
  }
  view_.region = clamped;
  view_.regionField[0] = clamped.x;
  view_.regionField[1] = clamped.y;
  view_.regionField[2] = clamped.width;
  view_.regionField[3] = clamped.height;
  message_ = clamped.active()
                 ? "render region " + std::to_string(clamped.x) + "," + std::to_string(clamped.y) +
                       "," + std::to_string(clamped.width) + "," + std::to_string(clamped.height)
                 : "render region cleared";
  restart();
}

std::shared_ptr<const Snapshot> ViewerApp::placeInRegion(
    std::shared_ptr<const Snapshot> snapshot) const {
  const RenderRegion& r = view_.region;
  const int w = options_.scene->scene.settings.width, h = options_.scene->scene.settings.height;
  if (!snapshot || snapshot->width != r.width || snapshot->height != r.height) return snapshot;
  constexpr float kDim = 0.35f;
  auto full = std::make_shared<Snapshot>(*snapshot);
  full->width = w;
  full->height = h;
  Image around(w, h);
  if (backdrop_.width == w && backdrop_.height == h)
    for (size_t p = 0; p < around.pixels.size(); ++p) around.pixels[p] = kDim * backdrop_.pixels[p];
  const auto place = [&](const Image& inside) {
    Image out = around;
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        out.pixels[size_t(y + r.y) * size_t(w) + size_t(x + r.x)] =
            inside.pixels[size_t(y) * size_t(r.width) + size_t(x)];
    return out;
  };
  full->raw = place(snapshot->raw);
  if (!snapshot->reconstructed.empty()) full->reconstructed = place(snapshot->reconstructed);
  // The maps cover the region only: zero outside.
  for (SnapshotMap& map : full->maps) {
    const size_t channels = map.channels();
    std::vector<float> values(size_t(w) * size_t(h) * channels, 0.0f);
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        for (size_t c = 0; c < channels; ++c)
          values[(size_t(y + r.y) * size_t(w) + size_t(x + r.x)) * channels + c] =
              map.values[(size_t(y) * size_t(r.width) + size_t(x)) * channels + c];
    map.values = std::move(values);
  }
  return full;
}

}  // namespace penumbra
