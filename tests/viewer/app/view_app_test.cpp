// The viewer's session and the run's stopping rules: a time limit set in the panel stops every
// method, the paper preset included (its rounds used to ignore it). No GL is needed.
#include "viewer/app/view_app.h"

#include "scene/scene_loader.h"
#include "viewer/app/view_panel.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace penumbra {
namespace {

ViewOptions cornellView(int size) {
  ViewOptions o;
  Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.json");
  scene.settings.width = scene.settings.height = size;
  o.scene = prepareScene(std::move(scene));
  o.threads = 1;
  o.preview = false;
  return o;
}

// Sets the run shape's `name` as the panel's widget does (the same table entry).
void setInPanel(ViewOptions& o, const std::string& name, double value) {
  for (const Param<RunShape>* p : runWidgets())
    if (p->name == name) {
      p->set(o.shape, value);
      return;
    }
  FAIL() << "the panel has no " << name << " widget";
}

// Waits (at most `seconds`) until the session stops running; true when it finished.
bool waitUntilFinished(ViewerApp& app, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    app.update();
    if (app.session().state() == RenderSession::State::Finished) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST(ViewerApp, ThePanelHasTheRunShapesWidgets) {
  std::set<std::string> names;
  for (const Param<RunShape>* p : runWidgets()) names.insert(p->name);
  for (const char* name : {"seed", "spp", "round-spp", "sampler", "time-limit", "noise-threshold"})
    EXPECT_TRUE(names.count(name)) << name;
}

// The paper preset's open-ended rounds have no end of their own: only the time limit the panel
// sets stops them, after the round in which it passed.
TEST(ViewerApp, ThePaperPresetStopsAtThePanelsTimeLimit) {
  ViewOptions o = cornellView(24);
  o.method = o.methods->find("bp", "paper");
  o.config() = o.methods->configFor("bp", "paper");
  ASSERT_EQ(o.method->algorithm(), "paper");
  ASSERT_EQ(o.shape.spp, 0);  // open-ended: never done by its budget
  setInPanel(o, "time-limit", 0.6);
  ViewerApp app(o);
  ASSERT_TRUE(waitUntilFinished(app, 30)) << toString(app.session().state());
  app.update();
  const auto snap = app.snapshot();
  ASSERT_TRUE(snap);
  EXPECT_TRUE(snap->final);
  EXPECT_GE(snap->seconds, 0.6);
  EXPECT_LT(snap->seconds, 20.0);
  EXPECT_EQ(snap->method, "bp");
  // It stays finished: no round runs past the limit.
  const int rounds = snap->round;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  app.update();
  EXPECT_EQ(app.snapshot()->round, rounds);
}

// Every method stops at the time limit, whatever its own rounds.
TEST(ViewerApp, EveryMethodStopsAtTheTimeLimit) {
  ViewOptions base = cornellView(16);
  for (const MethodDescriptor* method : base.methods->methods()) {
    ViewOptions o = base;
    o.method = method;
    setInPanel(o, "time-limit", 0.3);
    ViewerApp app(o);
    EXPECT_TRUE(waitUntilFinished(app, 30)) << method->title();
    app.update();
    ASSERT_TRUE(app.snapshot()) << method->title();
    EXPECT_GE(app.snapshot()->seconds, 0.3) << method->title();
  }
}

// Waits (at most `seconds`) until the app has shown `count` full pictures.
bool waitForFullPictures(ViewerApp& app, size_t count, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    app.update();
    if (app.firstFullPictureTimes().size() >= count) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// Each restart times its first picture (the block preview, at once) and its first full one
// (the method's first round), which the window's --report averages.
TEST(ViewerApp, EveryRestartTimesItsFirstFullPicture) {
  ViewOptions o = cornellView(32);
  o.preview = true;
  ViewerApp app(o);
  for (size_t restart = 1; restart <= 3; ++restart) {
    ASSERT_TRUE(waitForFullPictures(app, restart, 30)) << "restart " << restart;
    EXPECT_EQ(app.firstPictureTimes().size(), restart);
    EXPECT_EQ(app.snapshot()->source, SnapshotSource::Method);
    EXPECT_GE(app.firstFullPictureTimes().back(), app.firstPictureTimes().back());
    if (restart < 3) app.restart();
  }
  EXPECT_EQ(app.firstFullPictureTimes().size(), 3u);
}

// Without an overlay the session makes no maps (they cost a tenth of a second a picture at
// 1280x720); an overlay turned on after the run has ended shows once the last round is
// published again with them.
TEST(ViewerApp, AnOverlayTurnedOnLaterShowsWhenItsMapsArrive) {
  ViewOptions o = cornellView(16);
  o.shape.spp = 2;
  ViewerApp app(o);
  ASSERT_TRUE(waitUntilFinished(app, 60));
  ASSERT_NE(app.snapshot(), nullptr);
  EXPECT_FALSE(app.snapshot()->withMaps);
  const uint64_t kept = app.snapshot()->keptSamples;
  app.setOverlay(maps::SampleCount);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!app.overlayImage().available() && std::chrono::steady_clock::now() < end) {
    app.update();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(app.overlayImage().available()) << app.overlayImage().unavailable;
  EXPECT_TRUE(app.snapshot()->withMaps);
  EXPECT_EQ(app.snapshot()->keptSamples, kept);  // the same round
}

// The panel's environment: a map lights the scene and stays when only the strength changes; a
// map that cannot be read leaves everything as it was.
TEST(ViewerApp, ThePanelChangesTheEnvironment) {
  ViewerApp app(cornellView(16));
  EXPECT_FALSE(app.options().scene->scene.environment.present());
  const std::string sky = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/env/sky.hdr";
  app.setEnvironment({sky, 2.0f, 30.0f});
  const Environment& e = app.options().scene->scene.environment;
  ASSERT_TRUE(e.present());
  EXPECT_EQ(e.file, sky);
  EXPECT_EQ(e.strength, 2.0f);
  EXPECT_EQ(e.rotationDegrees, 30.0f);
  EXPECT_TRUE(app.options().scene->lights.environment != nullptr);
  app.setEnvironment({"", 0.5f, 0.0f});  // the strength alone keeps the map
  EXPECT_EQ(app.options().scene->scene.environment.file, sky);
  EXPECT_EQ(app.options().scene->scene.environment.strength, 0.5f);
  app.setEnvironment({"/nowhere/sky.hdr", 1.0f, 0.0f});
  EXPECT_NE(app.lastMessage().find("nowhere"), std::string::npos) << app.lastMessage();
  EXPECT_EQ(app.options().scene->scene.environment.file, sky);
  app.setEnvironment({"none", 1.0f, 0.0f});
  EXPECT_FALSE(app.options().scene->scene.environment.present());
}

}  // namespace
}  // namespace penumbra
