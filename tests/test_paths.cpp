#include "tests/test_paths.h"

#include "scene/scene_loader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

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

Scene sceneFrom(const std::string& json) { return parseSceneJson(json, "test.json", "."); }

RenderResult renderScene(Scene scene, int spp, SamplerKind sampler, uint64_t seed) {
  auto prepared = prepareScene(std::move(scene));
  RenderOptions options;
  options.spp = spp;
  options.sampler = sampler;
  options.seed = seed;
  return renderImage(*prepared, options);
}

std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method, int maxRounds) {
  for (int round = 0; round < maxRounds && !method.done(); ++round) method.runRound(nullptr);
  EXPECT_TRUE(method.done()) << "not done after " << maxRounds << " rounds";
  return method.snapshot();
}

std::filesystem::path freshFolder(const std::string& prefix) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    (prefix + "_" + info->test_suite_name() + "_" + info->name());
  std::filesystem::remove_all(dir);
  return dir;
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string writeOutput(const std::string& name, const std::string& contents) {
  const std::string path = outputPath(name);
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

double mse(std::span<const glm::vec3> image, std::span<const glm::vec3> clean) {
  double sum = 0.0;
  for (size_t p = 0; p < image.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double d = double(image[p][c]) - double(clean[p][c]);
      sum += d * d;
    }
  return sum / (3.0 * double(image.size()));
}

void expectNear(glm::vec3 a, glm::vec3 b, float tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

const std::vector<float>& mapOf(const Snapshot& snapshot, MapId id) {
  static const std::vector<float> none;
  const SnapshotMap* m = snapshot.map(id);
  EXPECT_NE(m, nullptr) << "no " << id.name() << " map";
  return m ? m->values : none;
}

}  // namespace penumbra::test
