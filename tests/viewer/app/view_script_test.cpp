// The window's scripted input: parsing with errors that name file and line, and the order
// and timing in which commands reach the host.
#include "viewer/app/view_script.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

namespace penumbra {
namespace {

struct Recorder final : ScriptHost {
  std::vector<std::string> events;
  void key(int k, bool down, int) override {
    events.push_back("key " + std::to_string(k) + (down ? " down" : " up"));
  }
  void mouseButton(int b, bool down, double x, double y, int) override {
    events.push_back("button " + std::to_string(b) + (down ? " down " : " up ") +
                     std::to_string(int(x)) + "," + std::to_string(int(y)));
  }
  void mouseMove(double x, double y) override {
    events.push_back("move " + std::to_string(int(x)) + "," + std::to_string(int(y)));
  }
  void scroll(double dy, double, double, int mods) override {
    events.push_back("scroll " + std::to_string(int(dy)) + (mods ? " ctrl" : ""));
  }
  void resize(int w, int h) override {
    events.push_back("resize " + std::to_string(w) + "x" + std::to_string(h));
  }
  void iconify(bool m) override { events.push_back(m ? "iconify" : "restore"); }
  void screenshot(const std::string& p) override { events.push_back("screenshot " + p); }
  void saveImage(const std::string& p) override { events.push_back("save " + p); }
  void mark(const std::string& name) override { events.push_back("mark " + name); }
  void region(int x, int y, int w, int h) override {
    events.push_back("region " + std::to_string(x) + " " + std::to_string(y) + " " +
                     std::to_string(w) + " " + std::to_string(h));
  }
  void quit() override { events.push_back("quit"); }
  bool roundShown() override { return rounds > 0; }
  int rounds = 0;
};

TEST(ViewScript, RunsCommandsInOrderAndWaits) {
  InputScript s = InputScript::parse(
      "# a comment\nkey 1\nwait 0.5\nscroll 2 10 20 ctrl\nhold w 0.2\nresize 0 0\nquit\n", "t");
  EXPECT_EQ(s.size(), 6u);
  Recorder r;
  EXPECT_TRUE(s.step(0.0, r));  // key, then the wait starts
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0], "key " + std::to_string(GLFW_KEY_1) + " down");
  EXPECT_TRUE(s.step(0.3, r));  // still waiting
  EXPECT_EQ(r.events.size(), 2u);
  EXPECT_TRUE(s.step(0.6, r));  // scroll, then the hold presses W
  EXPECT_EQ(r.events[2], "scroll 2 ctrl");
  EXPECT_EQ(r.events[3], "key " + std::to_string(GLFW_KEY_W) + " down");
  EXPECT_TRUE(s.step(0.9, r));  // W released, resize (which waits for the window system)
  EXPECT_EQ(r.events[4], "key " + std::to_string(GLFW_KEY_W) + " up");
  EXPECT_EQ(r.events[5], "resize 0x0");
  EXPECT_FALSE(s.step(1.1, r));
  EXPECT_EQ(r.events.back(), "quit");
}

TEST(ViewScript, SavesTheShownImageAndTakesScreenshots) {
  InputScript s = InputScript::parse("save t1.exr\nscreenshot s.png\n", "t");
  Recorder r;
  EXPECT_FALSE(s.step(0.0, r));
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0], "save t1.exr");
  EXPECT_EQ(r.events[1], "screenshot s.png");
  EXPECT_THROW(InputScript::parse("save\n", "t"), ScriptError);
}

TEST(ViewScript, SetsAndClearsTheRenderRegion) {
  InputScript s = InputScript::parse("region 10 20 30 40\nregion 0 0 0 0\nmark warm\n", "t");
  Recorder r;
  EXPECT_FALSE(s.step(0.0, r));
  ASSERT_EQ(r.events.size(), 3u);
  EXPECT_EQ(r.events[0], "region 10 20 30 40");
  EXPECT_EQ(r.events[1], "region 0 0 0 0");
  EXPECT_EQ(r.events[2], "mark warm");
  EXPECT_THROW(InputScript::parse("mark\n", "t"), ScriptError);
  EXPECT_THROW(InputScript::parse("region 1 2 3\n", "t"), ScriptError);
  EXPECT_THROW(InputScript::parse("region 1 2 -3 4\n", "t"), ScriptError);
  EXPECT_THROW(InputScript::parse("region 1 2 x 4\n", "t"), ScriptError);
}

TEST(ViewScript, TouchSetsAFilesModificationTimeToNow) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "penumbra_view_script_touch.txt";
  std::ofstream(file) << "x";
  const auto old = std::filesystem::file_time_type::clock::now() - std::chrono::hours(1);
  std::filesystem::last_write_time(file, old);
  InputScript s = InputScript::parse("touch " + file.string() + "\n", "t");
  Recorder r;
  EXPECT_FALSE(s.step(0.0, r));
  EXPECT_GT(std::filesystem::last_write_time(file), old + std::chrono::minutes(30));
  std::filesystem::remove(file);
  EXPECT_THROW(InputScript::parse("touch\n", "t"), ScriptError);
  EXPECT_THROW(InputScript::parse("touch /no/such/file.json\n", "t"), ScriptError);
}

TEST(ViewScript, WaitRoundWaitsForARoundOrItsTimeout) {
  InputScript s = InputScript::parse("wait-round 5\nkey 2\nwait-round\nkey 3\n", "t");
  Recorder r;
  EXPECT_TRUE(s.step(0.0, r));
  EXPECT_TRUE(s.step(1.0, r));
  EXPECT_TRUE(r.events.empty());  // no round yet
  r.rounds = 1;
  EXPECT_FALSE(s.step(1.1, r));  // the round came: key 2, the next wait-round passes, key 3
  EXPECT_EQ(r.events.size(), 4u);
  InputScript timeout = InputScript::parse("wait-round 2\nquit\n", "t");
  Recorder none;
  EXPECT_TRUE(timeout.step(0.0, none));
  EXPECT_TRUE(timeout.step(1.9, none));
  EXPECT_FALSE(timeout.step(2.1, none));  // gave up waiting, then quit
  EXPECT_EQ(none.events.back(), "quit");
}

TEST(ViewScript, DragsOverTenFrames) {
  InputScript s = InputScript::parse("drag right 0 0 100 50\n", "t");
  Recorder r;
  int frames = 0;
  while (s.step(frames * 0.016, r)) ++frames;
  EXPECT_EQ(frames, 10);
  EXPECT_EQ(r.events.front(), "move 0,0");
  EXPECT_EQ(r.events[1], "button " + std::to_string(GLFW_MOUSE_BUTTON_RIGHT) + " down 0,0");
  EXPECT_EQ(r.events.back(), "button " + std::to_string(GLFW_MOUSE_BUTTON_RIGHT) + " up 100,50");
}

TEST(ViewScript, ErrorsNameTheFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      InputScript::parse(text, "input.txt");
    } catch (const ScriptError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("wait 1\nteleport 3\n"), "input.txt:2: teleport: unknown command");
  EXPECT_EQ(message("key hyperspace"), "input.txt:1: key: expected one key name");
  EXPECT_EQ(message("wait soon"), "input.txt:1: wait: 'soon' is not a number");
  EXPECT_EQ(message("resize -1 4"), "input.txt:1: resize: sizes must be >= 0");
  EXPECT_EQ(message("drag sideways 1 2 3 4"), "input.txt:1: drag: expected left, right or middle");
  EXPECT_THROW(InputScript::load("/nonexistent/script.txt"), ScriptError);
}

}  // namespace
}  // namespace penumbra
