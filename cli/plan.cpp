#include "cli/plan.h"

#include "cli/commands.h"
#include "cli/json_file.h"
#include "core/image_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace penumbra {

namespace fs = std::filesystem;

std::vector<std::string>& commandArguments() {
  static std::vector<std::string> arguments;
  return arguments;
}

std::string executablePath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("penumbra") : self.string();
}

std::string shellQuote(const std::string& arg) {
  const bool plain = !arg.empty() && std::all_of(arg.begin(), arg.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           std::string("/._-+=:,@%").find(c) != std::string::npos;
  });
  if (plain) return arg;
  std::string quoted = "'";
  for (char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::vector<std::string> argumentsWithout(const std::vector<std::string>& drop,
                                          const std::vector<std::string>& dropFlags,
                                          const std::string& scenePath) {
  const std::vector<std::string>& args = commandArguments();
  std::vector<std::string> kept;
  bool sceneDone = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const size_t eq = a.find('=');
    const std::string name = a.rfind("--", 0) == 0 && eq != std::string::npos ? a.substr(0, eq) : a;
    if (std::find(drop.begin(), drop.end(), name) != drop.end()) {
      if (name == a) ++i;  // "--x v": skip the value too
      continue;
    }
    if (std::find(dropFlags.begin(), dropFlags.end(), a) != dropFlags.end()) continue;
    if (!sceneDone && a == scenePath) {
      kept.push_back(fs::absolute(a).lexically_normal().string());
      sceneDone = true;
      continue;
    }
    kept.push_back(a);
  }
  return kept;
}

void writePlan(const std::string& dir, const std::string& kind,
               const std::vector<std::string>& tasks, const std::vector<std::string>& finish) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CommandError(dir + ": cannot create the plan folder: " + ec.message());
  const auto writeLines = [&](const std::string& name, const std::vector<std::string>& lines) {
    const std::string path = (fs::path(dir) / name).string();
    writeFileAtomically(path, [&](const std::string& tmp) {
      std::ofstream out(tmp);
      for (const std::string& line : lines) out << line << "\n";
      if (!out) throw ImageIoError(path + ": cannot write");
    });
  };
  writeLines("tasks.txt", tasks);
  writeLines("finish.txt", finish);
  nlohmann::json j;
  j["kind"] = kind;
  j["tasks"] = tasks.size();
  j["planned_by"] = commandLine();
  j["tasks_file"] = "tasks.txt";
  j["finish_file"] = "finish.txt";
  writeJson((fs::path(dir) / "plan.json").string(), j);
}

}  // namespace penumbra
