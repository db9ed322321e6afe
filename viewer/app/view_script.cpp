#include "viewer/app/view_script.h"

#include <GLFW/glfw3.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace penumbra {

namespace {

constexpr int kDragFrames = 10;

int buttonCode(const std::string& name) {
  if (name == "left") return GLFW_MOUSE_BUTTON_LEFT;
  if (name == "right") return GLFW_MOUSE_BUTTON_RIGHT;
  if (name == "middle") return GLFW_MOUSE_BUTTON_MIDDLE;
  return -1;
}

}  // namespace

int scriptKeyCode(const std::string& name) {
  if (name.size() == 1) {
    const char c = name[0];
    if (c >= 'a' && c <= 'z') return GLFW_KEY_A + (c - 'a');
    if (c >= '0' && c <= '9') return GLFW_KEY_0 + (c - '0');
  }
  static const std::map<std::string, int> named = {{"space", GLFW_KEY_SPACE},
                                                   {"tab", GLFW_KEY_TAB},
                                                   {"escape", GLFW_KEY_ESCAPE},
                                                   {"minus", GLFW_KEY_MINUS},
                                                   {"equal", GLFW_KEY_EQUAL},
                                                   {"lbracket", GLFW_KEY_LEFT_BRACKET},
                                                   {"rbracket", GLFW_KEY_RIGHT_BRACKET},
                                                   {"grave", GLFW_KEY_GRAVE_ACCENT},
                                                   {"f1", GLFW_KEY_F1}};
  const auto it = named.find(name);
  return it == named.end() ? -1 : it->second;
}

InputScript InputScript::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScriptError(path + ": cannot read the input script");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path);
}

InputScript InputScript::parse(const std::string& text, const std::string& name) {
  InputScript script;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    ScriptCommand c;
    c.line = number;
    if (!(words >> c.verb)) continue;
    auto fail = [&](const std::string& why) {
      throw ScriptError(name + ":" + std::to_string(number) + ": " + c.verb + ": " + why);
    };
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);
    auto numbers = [&](size_t from, size_t count) {
      if (args.size() < from + count) fail("expected " + std::to_string(count) + " numbers");
      for (size_t i = from; i < from + count; ++i) {
        try {
          size_t used = 0;
          c.numbers.push_back(std::stod(args[i], &used));
          if (used != args[i].size()) throw std::invalid_argument(args[i]);
        } catch (const std::exception&) {
          fail("'" + args[i] + "' is not a number");
        }
      }
    };
    if (c.verb == "wait") {
      numbers(0, 1);
    } else if (c.verb == "key") {
      if (args.size() != 1 || scriptKeyCode(args[0]) < 0) fail("expected one key name");
      c.text = args[0];
    } else if (c.verb == "hold") {
      if (args.empty() || scriptKeyCode(args[0]) < 0) fail("expected a key name and seconds");
      c.text = args[0];
      numbers(1, 1);
    } else if (c.verb == "click") {
      numbers(0, 2);
    } else if (c.verb == "drag") {
      if (args.empty() || buttonCode(args[0]) < 0) fail("expected left, right or middle");
      c.text = args[0];
      numbers(1, 4);
    } else if (c.verb == "scroll") {
      if (!args.empty() && args.back() == "ctrl") {
        c.text = "ctrl";
        args.pop_back();
      }
      numbers(0, args.size() >= 3 ? 3 : 1);
    } else if (c.verb == "resize") {
      numbers(0, 2);
      if (c.numbers[0] < 0 || c.numbers[1] < 0) fail("sizes must be >= 0");
    } else if (c.verb == "region") {
      numbers(0, 4);
      if (c.numbers[2] < 0 || c.numbers[3] < 0) fail("sizes must be >= 0");
    } else if (c.verb == "wait-round") {
      if (args.empty())
        c.numbers.push_back(60.0);
      else
        numbers(0, 1);
    } else if (c.verb == "mark") {
      if (args.size() != 1) fail("expected a name");
      c.text = args[0];
    } else if (c.verb == "touch") {
      if (args.size() != 1) fail("expected a path");
      if (!std::filesystem::is_regular_file(args[0])) fail("'" + args[0] + "' is not a file");
      c.text = args[0];
    } else if (c.verb == "screenshot" || c.verb == "save") {
      if (args.size() != 1) fail("expected a path");
      c.text = args[0];
    } else if (c.verb != "iconify" && c.verb != "restore" && c.verb != "quit") {
      fail("unknown command");
    }
    script.commands_.push_back(std::move(c));
  }
  return script;
}

bool InputScript::step(double now, ScriptHost& host) {
  // A drag moves one step per frame.
  if (dragFrame_ >= 0) {
    const ScriptCommand& c = commands_[next_ - 1];
    const int button = buttonCode(c.text);
    const double t = double(++dragFrame_) / kDragFrames;
    const double x = c.numbers[0] + (c.numbers[2] - c.numbers[0]) * t;
    const double y = c.numbers[1] + (c.numbers[3] - c.numbers[1]) * t;
    host.mouseMove(x, y);
    if (dragFrame_ < kDragFrames) return true;
    host.mouseButton(button, false, x, y, 0);
    dragFrame_ = -1;
  }
  if (now < busyUntil_) return true;
  if (roundDeadline_ >= 0) {
    if (!host.roundShown() && now < roundDeadline_) return true;
    roundDeadline_ = -1;
  }
  // A hold in progress ends with its release.
  if (next_ > 0 && commands_[next_ - 1].verb == "hold" && busyUntil_ > 0) {
    host.key(scriptKeyCode(commands_[next_ - 1].text), false, 0);
    busyUntil_ = 0;
  }
  while (next_ < commands_.size()) {
    const ScriptCommand& c = commands_[next_++];
    if (c.verb == "wait") {
      busyUntil_ = now + c.numbers[0];
      return true;
    }
    if (c.verb == "key") {
      host.key(scriptKeyCode(c.text), true, 0);
      host.key(scriptKeyCode(c.text), false, 0);
    } else if (c.verb == "hold") {
      host.key(scriptKeyCode(c.text), true, 0);
      busyUntil_ = now + c.numbers[0];
      return true;
    } else if (c.verb == "click") {
      host.mouseMove(c.numbers[0], c.numbers[1]);
      host.mouseButton(GLFW_MOUSE_BUTTON_LEFT, true, c.numbers[0], c.numbers[1], 0);
      host.mouseButton(GLFW_MOUSE_BUTTON_LEFT, false, c.numbers[0], c.numbers[1], 0);
    } else if (c.verb == "drag") {
      host.mouseMove(c.numbers[0], c.numbers[1]);
      host.mouseButton(buttonCode(c.text), true, c.numbers[0], c.numbers[1], 0);
      dragFrame_ = 0;
      return true;
    } else if (c.verb == "scroll") {
      const double x = c.numbers.size() >= 3 ? c.numbers[1] : 0.0;
      const double y = c.numbers.size() >= 3 ? c.numbers[2] : 0.0;
      host.scroll(c.numbers[0], x, y, c.text == "ctrl" ? GLFW_MOD_CONTROL : 0);
    } else if (c.verb == "resize") {
      host.resize(int(c.numbers[0]), int(c.numbers[1]));
      busyUntil_ = now + 0.1;  // let the window system answer
      return true;
    } else if (c.verb == "iconify" || c.verb == "restore") {
      host.iconify(c.verb == "iconify");
      busyUntil_ = now + 0.1;
      return true;
    } else if (c.verb == "wait-round") {
      if (!host.roundShown()) {
        roundDeadline_ = now + c.numbers[0];
        return true;
      }
    } else if (c.verb == "screenshot") {
      host.screenshot(c.text);
    } else if (c.verb == "save") {
      host.saveImage(c.text);
    } else if (c.verb == "touch") {
      std::error_code ec;
      std::filesystem::last_write_time(c.text, std::filesystem::file_time_type::clock::now(), ec);
      if (ec)
        std::fprintf(stderr, "penumbra view: touch %s: %s\n", c.text.c_str(), ec.message().c_str());
    } else if (c.verb == "mark") {
      host.mark(c.text);
    } else if (c.verb == "region") {
      host.region(int(c.numbers[0]), int(c.numbers[1]), int(c.numbers[2]), int(c.numbers[3]));
    } else if (c.verb == "quit") {
      host.quit();
      return false;
    }
  }
  return false;
}

}  // namespace penumbra
