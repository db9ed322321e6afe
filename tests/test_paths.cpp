#include "tests/test_paths.h"

#include "scene/scene_loader.h"

#include <filesystem>

namespace penumbra::test {

std::string sourcePath(const std::string& relative) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/" + relative;
}

std::string outputPath(const std::string& name) {
  std::filesystem::create_directories(PENUMBRA_TEST_OUTPUT_DIR);
  return std::string(PENUMBRA_TEST_OUTPUT_DIR) + "/" + name;
}

std::unique_ptr<PreparedScene> shippedScene(const std::string& name, int size) {
  Scene scene = loadScene(sourcePath("scenes/" + name + ".json"));
  scene.settings.width = scene.settings.height = size;
  return prepareScene(std::move(scene));
}

}  // namespace penumbra::test
