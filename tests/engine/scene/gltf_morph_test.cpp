// glTF morph targets: the test quad's untransformed instance displaced by its mesh's default
// weights, by its node's, and by an animation of them (at the frame time, and blurred over the
// shutter), with clear errors for damaged targets and weights.
#include "scene/gltf_io.h"

#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>

#include <string>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

// The test quad (gltf_test_files.h) whose second mesh (the untransformed instance, vertices 4
// to 7 of the static mesh) has two morph targets: the first lifts its top edge (vertices 2 and
// 3) by 1 along z, the second moves its corner (1, 0, 0) by 1 along x. With `animated`, an
// animation turns the weights from (0, 0) at 0 s to (1, 0) at 1 s.
Json morphedQuad(bool animated) {
  std::string b = quadBuffer();
  const size_t at = b.size();
  append<float>(b, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1});  // target 0
  append<float>(b, {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0});  // target 1
  append<float>(b, {0, 1});                                // key times
  append<float>(b, {0, 0, 1, 0});                          // weights per key
  Json j = quadGltf(dataUri(b), b.size());
  const size_t views = j["bufferViews"].size(), accessors = j["accessors"].size();
  for (size_t k = 0; k < 4; ++k) {
    const size_t offset = at + (k < 2 ? 48 * k : 96 + 8 * (k - 2));
    const size_t bytes = k < 2 ? 48 : 8 * (k - 1);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  }
  for (size_t k = 0; k < 2; ++k)
    j["accessors"].push_back(
        {{"bufferView", views + k}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
  j["accessors"].push_back({{"bufferView", views + 2},
                            {"componentType", 5126},
                            {"count", 2},
                            {"type", "SCALAR"},
                            {"min", {0}},
                            {"max", {1}}});
  j["accessors"].push_back(
      {{"bufferView", views + 3}, {"componentType", 5126}, {"count", 4}, {"type", "SCALAR"}});
  j["meshes"][1]["primitives"][0]["targets"] = {{{"POSITION", accessors}},
                                                {{"POSITION", accessors + 1}}};
  j["meshes"][1]["weights"] = {0.5, 0};
  if (animated)
    j["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "weights"}}}}}},
         {"samplers",
          {{{"input", accessors + 2}, {"output", accessors + 3}, {"interpolation", "LINEAR"}}}}}};
  return j;
}

TEST(GltfMorph, TheMeshsWeightsDisplaceItAndTheNodesReplaceThem) {
  Json j = morphedQuad(false);
  const GltfData g = loadGltf(writeGltf("mesh.gltf", j));
  ASSERT_EQ(g.mesh.vertexCount, 8u);
  expectNear(g.mesh.positions[5], vec3(1, 0, 0));
  expectNear(g.mesh.positions[6], vec3(1, 1, 0.5f));
  expectNear(g.mesh.positions[7], vec3(0, 1, 0.5f));
  EXPECT_EQ(allWarnings(g).find("morph"), std::string::npos) << allWarnings(g);

  j["nodes"][2]["weights"] = {0, 1};
  const GltfData n = loadGltf(writeGltf("node.gltf", j));
  expectNear(n.mesh.positions[5], vec3(2, 0, 0));
  expectNear(n.mesh.positions[6], vec3(1, 1, 0));
}

TEST(GltfMorph, AnimatedWeightsApplyAtTheFrameTimeAndBlurOverTheShutter) {
  GltfOptions still;
  still.frameTime = 0.25;
  still.shutterSeconds = 0;
  const GltfData g = loadGltf(writeGltf("still.gltf", morphedQuad(true)), still);
  ASSERT_EQ(g.mesh.vertexCount, 8u);
  expectNear(g.mesh.positions[6], vec3(1, 1, 0.25f));

  GltfOptions open;
  open.frameTime = 0;
  open.shutterSeconds = 1;
  const GltfData m = loadGltf(writeGltf("open.gltf", morphedQuad(true)), open);
  ASSERT_EQ(m.animatedMeshes.size(), 1u);
  const Mesh& moving = m.animatedMeshes[0];
  ASSERT_EQ(moving.timeSteps, 2) << "weights that change at a constant rate need two steps";
  expectNear(moving.positions[2], vec3(1, 1, 0));
  expectNear(moving.positions[4 + 2], vec3(1, 1, 1));
}

TEST(GltfMorph, DamagedTargetsAndWeightsNameTheElement) {
  Json j = morphedQuad(false);
  j["accessors"][j["meshes"][1]["primitives"][0]["targets"][1]["POSITION"].get<size_t>()]["count"] =
      3;
  // Without a weight, target 1 is not read.
  EXPECT_EQ(loadGltf(writeGltf("unused.gltf", j)).mesh.vertexCount, 8u);
  j["nodes"][2]["weights"] = {0, 1};
  expectSceneError([&] { loadGltf(writeGltf("count.gltf", j)); },
                   {"meshes[1].primitives[0].targets[1].POSITION", "expected 4 VEC3"});
  j = morphedQuad(true);
  j["animations"][0]["samplers"][0]["output"] = j["animations"][0]["samplers"][0]["input"];
  expectSceneError([&] { loadGltf(writeGltf("weights.gltf", j)); },
                   {"animations[0].channels[0].output", "expected 4 SCALAR weights"});
}

}  // namespace
}  // namespace penumbra
