// Live reload: the viewer watches every file its scene was read from (the scene, and the
// meshes, MTL libraries and textures it names), reloads on a change and restarts, keeps the
// user's camera unless the file's camera changed, and keeps the last good scene, with the
// error in its message, when the changed file does not load. No GL is needed.
#include "viewer/app/view_app.h"

#include "methods/ld/ld.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <string>
#include <thread>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// One folder per test: CTest runs the tests in parallel processes.
std::string folder() {
  const std::string dir =
      test::outputPath(std::string("viewer/live_reload/") +
                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Writes `text` and moves the file's time a second on from `bump` steps ago, so that the
// change shows even on file systems whose times are coarse.
void write(const std::string& path, const std::string& text, int bump) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  fs::last_write_time(path, fs::file_time_type::clock::now() + std::chrono::seconds(bump));
}

std::string sceneText(const std::string& albedo, const std::string& eye) {
  return R"({"render": {"width": 16, "height": 16, "spp": 1},
             "camera": {"eye": )" +
         eye + R"(, "look_at": [0, 0, 0]},
             "materials": {"m": {"type": "diffuse", "albedo": )" +
         albedo + R"(}},
             "objects": [{"shape": "mesh", "file": "tri.obj", "material": "m"}]})";
}

ViewOptions optionsFor(const std::string& path) {
  ViewOptions o;
  o.scene = prepareScene(loadScene(path));
  o.scenePath = path;
  o.loadScene = [](const std::string& file) { return loadScene(file); };
  o.method = &ldMethod();
  o.threads = 1;
  o.preview = false;
  o.rounds = 1;
  return o;
}

const char* const kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// Writes tri.obj and scene.json (grey, seen from +z) into dir; returns the scene's path.
std::string writeScene(const std::string& dir) {
  write(dir + "/tri.obj", kTriangle, 0);
  write(dir + "/scene.json", sceneText("[0.5, 0.5, 0.5]", "[0, 0, 3]"), 0);
  return dir + "/scene.json";
}

TEST(LiveReload, ReloadsOnAChangeOfTheSceneOrAFileItNames) {
  const std::string dir = folder();
  const std::string path = writeScene(dir);
  ViewerApp app(optionsFor(path));
  EXPECT_EQ(app.options().scene->scene.sourceFiles.size(), 2u);
  const int restarts = app.restarts();
  EXPECT_FALSE(app.checkSceneFiles()) << "nothing changed yet";

  write(path, sceneText("[0.25, 0.5, 0.75]", "[0, 0, 3]"), 2);
  EXPECT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.restarts(), restarts + 1);
  EXPECT_EQ(app.options().scene->scene.materials[0].albedo, vec3(0.25f, 0.5f, 0.75f));
  EXPECT_NE(app.lastMessage().find("reloaded"), std::string::npos) << app.lastMessage();

  // A mesh the scene names counts too.
  write(dir + "/tri.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n", 4);
  EXPECT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.options().scene->scene.meshes[0].positions[1], vec3(2, 0, 0));
}

TEST(LiveReload, UpdateReadsAChangedSceneOnAThreadOfItsOwn) {
  const std::string dir = folder();
  const std::string path = writeScene(dir);
  // The read waits at a gate: update() must return meanwhile, the last scene rendering on.
  auto gate = std::make_shared<std::promise<void>>();
  std::shared_future<void> open = gate->get_future().share();
  ViewOptions options = optionsFor(path);
  options.loadScene = [open](const std::string& file) {
    open.wait();
    return loadScene(file);
  };
  ViewerApp app(std::move(options));
  write(path, sceneText("[0.25, 0.5, 0.75]", "[0, 0, 3]"), 2);
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // update() looks twice a second
  const auto start = std::chrono::steady_clock::now();
  app.update();  // starts the read
  app.update();
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int reloadsWhileReading = app.reloads();
  gate->set_value();
  EXPECT_LT(waited, 0.5) << "update() waited for the read";
  EXPECT_EQ(reloadsWhileReading, 0);
  EXPECT_EQ(app.options().scene->scene.materials[0].albedo, vec3(0.5f));
  for (int i = 0; i < 1000 && app.reloads() == 0; ++i) {
    app.update();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(app.reloads(), 1);
  EXPECT_EQ(app.options().scene->scene.materials[0].albedo, vec3(0.25f, 0.5f, 0.75f));
}

// Reads a whole file.
std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(LiveReload, TheShippedGltfSceneReloadsOnAnEditOfItsFileOrATexture) {
  // A copy of scenes/studio: its .gltf, .bin and textures are all watched.
  const std::string dir = folder();
  fs::copy(test::sourcePath("scenes/studio"), dir, fs::copy_options::recursive);
  const std::string path = dir + "/studio.gltf";
  ViewerApp app(optionsFor(path));
  const auto& files = app.options().scene->scene.sourceFiles;
  EXPECT_EQ(files.size(), 1u + 1u + 5u) << "the .gltf, its .bin and five textures";
  const auto brass = [&] {
    for (const Material& m : app.options().scene->scene.materials)
      if (m.name == "Brass") return m;
    ADD_FAILURE() << "no Brass material";
    return Material();
  };
  EXPECT_NEAR(brass().metallic, 0.6f, 1e-6f);

  // The artist turns the brass into full metal and saves.
  std::string text = readAll(path);
  const size_t at = text.find("\"metallicFactor\": 0.6");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("\"metallicFactor\": 0.6").size(), "\"metallicFactor\": 1.0");
  write(path, text, 2);
  const int restarts = app.restarts();
  EXPECT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.restarts(), restarts + 1);
  EXPECT_NEAR(brass().metallic, 1.0f, 1e-6f);

  // A texture repainted outside the scene file reloads too; a broken one keeps the last scene.
  const std::string crate = dir + "/textures/crate.png";
  const std::string good = readAll(crate);
  write(crate, good.substr(0, good.size() / 2), 4);
  const auto before = app.options().scene;
  EXPECT_FALSE(app.checkSceneFiles());
  EXPECT_EQ(app.options().scene, before);
  EXPECT_NE(app.lastMessage().find("crate.png"), std::string::npos) << app.lastMessage();
  write(crate, good, 6);
  EXPECT_TRUE(app.checkSceneFiles());
}

TEST(LiveReload, ABrokenFileKeepsTheLastGoodSceneAndSaysWhy) {
  const std::string dir = folder();
  const std::string path = writeScene(dir);
  ViewerApp app(optionsFor(path));
  const auto before = app.options().scene;

  write(dir + "/tri.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", 2);
  EXPECT_FALSE(app.checkSceneFiles());
  EXPECT_EQ(app.options().scene, before) << "the last good scene must stay";
  EXPECT_NE(app.lastMessage().find("reload failed"), std::string::npos) << app.lastMessage();
  EXPECT_NE(app.lastMessage().find("tri.obj:2:"), std::string::npos) << app.lastMessage();
  EXPECT_FALSE(app.checkSceneFiles()) << "a failed file is not retried until it changes";

  write(dir + "/tri.obj", kTriangle, 4);
  EXPECT_TRUE(app.checkSceneFiles()) << "mended: loads again";
  EXPECT_NE(app.options().scene, before);
}

TEST(LiveReload, TheCameraIsKeptUnlessTheFilesCameraChanged) {
  const std::string dir = folder();
  const std::string path = writeScene(dir);
  ViewerApp app(optionsFor(path));
  // The user flies the camera elsewhere (W, held for half a second).
  app.keyEvent(87 /* W */, true, 0);
  app.fly(0.5);
  app.keyEvent(87, false, 0);
  const Camera moved = app.viewState().camera;
  ASSERT_NE(moved.eye, vec3(0, 0, 3)) << "the fly key did not move the camera";

  write(path, sceneText("[0.3, 0.3, 0.3]", "[0, 0, 3]"), 2);  // materials only
  ASSERT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.viewState().camera.eye, moved.eye);

  write(path, sceneText("[0.3, 0.3, 0.3]", "[1, 2, 3]"), 4);  // the file's camera moved
  ASSERT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.viewState().camera.eye, vec3(1, 2, 3));
}

TEST(LiveReload, OpeningAnotherSceneTakesItsCameraAndWatchesItsFiles) {
  const std::string dir = folder();
  const std::string a = writeScene(dir);
  write(dir + "/b.json", sceneText("[0.1, 0.2, 0.3]", "[3, 0, 0]"), 0);
  ViewerApp app(optionsFor(a));
  EXPECT_FALSE(app.openScene(dir + "/missing.json"));
  EXPECT_NE(app.lastMessage().find("missing.json"), std::string::npos) << app.lastMessage();
  ASSERT_TRUE(app.openScene(dir + "/b.json"));
  EXPECT_EQ(app.viewState().camera.eye, vec3(3, 0, 0));
  EXPECT_EQ(app.options().scenePath, dir + "/b.json");
  write(dir + "/b.json", sceneText("[0.9, 0.9, 0.9]", "[3, 0, 0]"), 2);
  EXPECT_TRUE(app.checkSceneFiles());
  EXPECT_EQ(app.options().scene->scene.materials[0].albedo, vec3(0.9f));
}

}  // namespace
}  // namespace penumbra
