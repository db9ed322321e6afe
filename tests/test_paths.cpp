#include "tests/test_paths.h"

#include <filesystem>

namespace penumbra::test {

std::string sourcePath(const std::string& relative) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/" + relative;
}

std::string outputPath(const std::string& name) {
  std::filesystem::create_directories(PENUMBRA_TEST_OUTPUT_DIR);
  return std::string(PENUMBRA_TEST_OUTPUT_DIR) + "/" + name;
}

}  // namespace penumbra::test
