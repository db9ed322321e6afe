// Scripted input for the window, so that a test (or a bug report) can drive the viewer
// through the same input path a person uses. One command per line, '#' starts a comment:
//   wait SECONDS                 do nothing for a while
//   key NAME                     press and release a key (a-z, 0-9, space, tab, escape,
//                                minus, equal, lbracket, rbracket, grave, f1)
//   hold NAME SECONDS            hold a key down (WASD fly)
//   click X Y                    left click at framebuffer pixel (X, Y): inspects a pixel
//   drag BUTTON X0 Y0 X1 Y1      drag with left, right or middle over ten frames
//   scroll DY [X Y] [ctrl]       scroll (ctrl: dolly the camera)
//   resize W H                   resize the window (0 0 is allowed)
//   iconify | restore            minimise the window and bring it back
//   wait-round [SECONDS]         wait until a round of the current view has landed (at most
//                                SECONDS, default 60): makes a script independent of speed
//   screenshot PATH              write the next frame to PATH
//   region X Y W H               render only that window of the image (image pixels), as a
//                                ctrl + left drag does; region 0 0 0 0 renders everything
//   touch PATH                   set PATH's modification time to now, as an editor saving it
//                                does (live reload picks it up within half a second)
//   mark NAME                    note the time under NAME in the window's --report (e.g.
//                                where a soak test's warm-up ends)
//   save PATH                    write the shown image (linear .exr/.pfm, or .png) to PATH, as
//                                the panel's save does: for measuring the picture over time
//   quit                         close the viewer
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {

// A script that cannot be read or parsed; the message names "file:line".
struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a script acts on; the window implements it.
class ScriptHost {
 public:
  virtual ~ScriptHost() = default;
  virtual void key(int glfwKey, bool down, int mods) = 0;
  virtual void mouseButton(int button, bool down, double x, double y, int mods) = 0;
  virtual void mouseMove(double x, double y) = 0;
  virtual void scroll(double dy, double x, double y, int mods) = 0;
  virtual void resize(int width, int height) = 0;
  virtual void iconify(bool minimise) = 0;
  virtual void screenshot(const std::string& path) = 0;
  virtual void saveImage(const std::string& path) = 0;
  virtual void region(int x, int y, int width, int height) = 0;  // 0 x 0: the whole image
  virtual void mark(const std::string& name) = 0;
  virtual bool roundShown() = 0;  // a round of the current view is on screen
  virtual void quit() = 0;
};

struct ScriptCommand {
  std::string verb;
  std::vector<double> numbers;
  std::string text;  // key name, button, path or "ctrl"
  int line = 0;
};

class InputScript {
 public:
  // Parses a script; throws ScriptError naming "file:line" on an unknown command or a bad
  // argument.
  static InputScript load(const std::string& path);
  static InputScript parse(const std::string& text, const std::string& name);

  // Runs what is due at `now` (seconds since the script started); false once all is done.
  bool step(double now, ScriptHost& host);
  size_t size() const { return commands_.size(); }

 private:
  std::vector<ScriptCommand> commands_;
  size_t next_ = 0;
  double busyUntil_ = 0;       // a wait, hold or drag in progress
  double roundDeadline_ = -1;  // a wait-round in progress: give up at this time
  int dragFrame_ = -1;         // frame of the drag in progress, -1: none
};

// GLFW key code of a script key name, or -1.
int scriptKeyCode(const std::string& name);

}  // namespace penumbra
