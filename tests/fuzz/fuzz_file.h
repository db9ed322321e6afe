// Helpers for the libFuzzer targets whose parsers read files by path (the OBJ/MTL, PLY and
// image readers, as a user's scene reaches them): the input goes to a file in a folder of
// this process's own, which the target hands to the reader.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::fuzz {

// A folder for this process (so parallel fuzzing jobs do not share files), made once and
// removed at exit.
inline const std::filesystem::path& workFolder() {
  static const std::filesystem::path folder = [] {
    std::filesystem::path p =
        std::filesystem::temp_directory_path() / ("penumbra-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(p);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(workFolder(), ignored);
    });
    return p;
  }();
  return folder;
}

// Writes `size` bytes to workFolder()/name and returns the path.
inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = (workFolder() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

inline std::string writeInput(const std::string& name, const std::string& text) {
  return writeInput(name, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

}  // namespace penumbra::fuzz
