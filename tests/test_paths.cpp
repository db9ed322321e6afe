#include "tests/test_paths.h"

#include "scene/scene_loader.h"

#include <gtest/gtest.h>

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

std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method, int maxRounds) {
  for (int round = 0; round < maxRounds && !method.done(); ++round) method.runRound(nullptr);
  EXPECT_TRUE(method.done()) << "not done after " << maxRounds << " rounds";
  return method.snapshot();
}

}  // namespace penumbra::test
