#include "viewer/app/headless.h"

#include "viewer/app/gl/display_renderer.h"

#include <chrono>
#include <thread>

namespace penumbra {

HeadlessFrame renderHeadless(ViewOptions options, const HeadlessRequest& request) {
  std::unique_ptr<HeadlessContext> context = createHeadlessContext(request.backend);
  HeadlessFrame frame;
  frame.backend = context->backendName();
  frame.description = context->description();

  options.preview = false;
  options.rounds = request.rounds;
  const int imageW = options.scene->scene.settings.width;
  const int imageH = options.scene->scene.settings.height;
  ViewerApp app(std::move(options));
  if (request.inspectX >= 0) app.inspectPixel(request.inspectX, request.inspectY);
  while (!app.session().wait(3600)) {
  }
  if (app.session().state() == RenderSession::State::Failed) {
    frame.failure = app.session().error();
    return frame;
  }
  // The inspection comes with the last round; when asked for after it, it follows at once.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (request.inspectX >= 0 && app.session().inspectionVersion() == 0 &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  app.update();

  int width = request.width, height = request.height;
  if (width <= 0 || height <= 0) {
    if (request.withUi) {
      width = std::max(imageW + 360, 1024);
      height = std::max(imageH + 80, 720);
    } else {
      width = imageW;
      height = imageH + app.legendBand(imageW);  // the legend goes under the image
    }
  }
  app.initGl(request.withUi);
  {
    OffscreenTarget target(width, height);
    target.bind();
    app.resized(width, height);
    app.update();
    app.fitView();
    if (request.zoom > 0) app.setView(request.zoom, request.centerX, request.centerY);
    // ImGui lays its windows out over a frame or two; the last frame is the screenshot.
    const int frames = request.withUi ? 3 : 1;
    for (int i = 0; i < frames; ++i) {
      app.update();
      app.drawFrame(width, height, request.withUi, 1.0 / 60);
    }
    const std::vector<uint8_t> rgba = target.read();
    frame.rgb.resize(size_t(width) * height * 3);
    for (size_t i = 0; i < size_t(width) * height; ++i)
      for (int k = 0; k < 3; ++k) frame.rgb[3 * i + k] = rgba[4 * i + k];
  }
  app.releaseGl();
  frame.width = width;
  frame.height = height;
  frame.snapshot = app.snapshot();
  frame.overlayUnavailable = app.overlayImage().unavailable;
  return frame;
}

}  // namespace penumbra
