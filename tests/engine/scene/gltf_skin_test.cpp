// glTF skins: a skinned strip posed by its two joints at the frame time (linear blend
// skinning, the mesh node's own transform ignored), blurred over the shutter when a joint is
// animated, and clear errors for damaged skins.
#include "scene/gltf_io.h"

#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <string>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

// A strip of two unit quads along +x in the z = 0 plane (x = 0, 1, 2; y = 0, 1), normals +z.
// Joint 0 sits at the origin, joint 1 at x = 1, its child, turned +90 degrees about z. The
// vertices at x = 0 follow joint 0, those at x = 2 joint 1, and those at x = 1 both, half each.
// The mesh's node is moved to x = 10, which skinning ignores. With `animated`, joint 1 turns
// from 0 to 90 degrees over the first second instead.
Json skinnedStrip(bool animated) {
  std::string b;
  for (float y : {0.0f, 1.0f})
    for (float x : {0.0f, 1.0f, 2.0f}) append<float>(b, {x, y, 0});  // 72 bytes
  for (int v = 0; v < 6; ++v) append<float>(b, {0, 0, 1});           // 72
  for (int y = 0; y < 2; ++y) {                                      // 24: JOINTS_0
    append<uint8_t>(b, {0, 0, 0, 0});
    append<uint8_t>(b, {0, 1, 0, 0});
    append<uint8_t>(b, {1, 0, 0, 0});
  }
  for (int y = 0; y < 2; ++y) {  // 96: WEIGHTS_0
    append<float>(b, {1, 0, 0, 0});
    append<float>(b, {0.5f, 0.5f, 0, 0});
    append<float>(b, {1, 0, 0, 0});
  }
  append<uint16_t>(b, {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4});           // 24
  append<float>(b, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});  // 128: inverse binds
  append<float>(b, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1});
  const float s = std::sqrt(0.5f);
  append<float>(b, {0, 1});                    // 8: key times
  append<float>(b, {0, 0, 0, 1, 0, 0, s, s});  // 32: joint 1's rotations
  Json views = Json::array();
  size_t offset = 0;
  for (size_t bytes : {72, 72, 24, 96, 24, 128, 8, 32}) {
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    offset += bytes;
  }
  Json joint1 = {{"name", "joint1"}, {"translation", {1, 0, 0}}};
  if (!animated) joint1["rotation"] = {0, 0, s, s};
  Json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 1}}}}},
      {"nodes",
       {{{"name", "strip"}, {"mesh", 0}, {"skin", 0}, {"translation", {10, 0, 0}}},
        {{"name", "joint0"}, {"children", {2}}},
        joint1}},
      {"skins", {{{"joints", {1, 2}}, {"inverseBindMatrices", 5}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"JOINTS_0", 2}, {"WEIGHTS_0", 3}}},
            {"indices", 4}}}}}}},
      {"buffers", {{{"uri", dataUri(b)}, {"byteLength", b.size()}}}},
      {"bufferViews", views},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 6},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {2, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"}},
        {{"bufferView", 2}, {"componentType", 5121}, {"count", 6}, {"type", "VEC4"}},
        {{"bufferView", 3}, {"componentType", 5126}, {"count", 6}, {"type", "VEC4"}},
        {{"bufferView", 4}, {"componentType", 5123}, {"count", 12}, {"type", "SCALAR"}},
        {{"bufferView", 5}, {"componentType", 5126}, {"count", 2}, {"type", "MAT4"}},
        {{"bufferView", 6},
         {"componentType", 5126},
         {"count", 2},
         {"type", "SCALAR"},
         {"min", {0}},
         {"max", {1}}},
        {{"bufferView", 7}, {"componentType", 5126}, {"count", 2}, {"type", "VEC4"}}}}};
  if (animated)
    j["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}}}},
         {"samplers", {{{"input", 6}, {"output", 7}, {"interpolation", "LINEAR"}}}}}};
  return j;
}

// Where joint 1's turn by `degrees` about z takes the strip's vertices (in the order above).
std::vector<vec3> posedStrip(float degrees) {
  const float c = std::cos(glm::radians(degrees)), s = std::sin(glm::radians(degrees));
  // Joint 1's matrix: about (1, 0, 0), turn by the angle.
  const auto joint1 = [&](vec3 p) {
    const vec3 d = p - vec3(1, 0, 0);
    return vec3(1 + c * d.x - s * d.y, s * d.x + c * d.y, 0);
  };
  std::vector<vec3> out;
  for (float y : {0.0f, 1.0f}) {
    out.push_back(vec3(0, y, 0));
    out.push_back(0.5f * vec3(1, y, 0) + 0.5f * joint1(vec3(1, y, 0)));
    out.push_back(joint1(vec3(2, y, 0)));
  }
  return out;
}

TEST(GltfSkin, JointsPoseTheMeshAndTheNodesTransformIsIgnored) {
  const GltfData g = loadGltf(writeGltf("strip.gltf", skinnedStrip(false)));
  ASSERT_EQ(g.mesh.vertexCount, 6u);
  const std::vector<vec3> expected = posedStrip(90);
  for (size_t v = 0; v < 6; ++v) expectNear(g.mesh.positions[v], expected[v]);
  expectNear(g.mesh.positions[2], vec3(1, 1, 0));  // the tip, turned up
  expectNear(g.mesh.positions[4], vec3(0.5f, 0.5f, 0));
  // Turned about z, every normal stays +z (normalised once interpolated).
  for (const vec3& n : g.mesh.normals) expectNear(glm::normalize(n), vec3(0, 0, 1));
  EXPECT_EQ(allWarnings(g).find("skin"), std::string::npos) << allWarnings(g);
}

TEST(GltfSkin, AnAnimatedJointPosesAtTheFrameTimeAndBlursOverTheShutter) {
  // At the frame time of 1 s, no shutter: posed as the still strip.
  GltfOptions still;
  still.frameTime = 1.0;
  still.shutterSeconds = 0;
  const GltfData end = loadGltf(writeGltf("end.gltf", skinnedStrip(true)), still);
  ASSERT_TRUE(end.animatedMeshes.empty());
  const std::vector<vec3> at90 = posedStrip(90);
  for (size_t v = 0; v < 6; ++v) expectNear(end.mesh.positions[v], at90[v], 1e-4f);

  // Over the first second: a moving mesh whose steps follow the turn.
  GltfOptions open;
  open.frameTime = 0.0;
  open.shutterSeconds = 1.0;
  const GltfData g = loadGltf(writeGltf("turn.gltf", skinnedStrip(true)), open);
  EXPECT_EQ(g.mesh.vertexCount, 0u);
  ASSERT_EQ(g.animatedMeshes.size(), 1u);
  const Mesh& moving = g.animatedMeshes[0];
  ASSERT_GE(moving.timeSteps, 3);
  const int last = moving.timeSteps - 1;
  for (int step : {0, last / 2, last}) {
    const std::vector<vec3> expected = posedStrip(90.0f * float(step) / float(last));
    for (size_t v = 0; v < 6; ++v)
      expectNear(moving.positions[size_t(step) * 6 + v], expected[v], 1e-3f);
  }
}

TEST(GltfSkin, DamagedSkinsNameTheElement) {
  Json j = skinnedStrip(false);
  j["nodes"][0]["skin"] = 3;
  expectSceneError([&] { loadGltf(writeGltf("noskin.gltf", j)); },
                   {"noskin.gltf", "nodes[0].skin", "skin 3 does not exist"});
  j = skinnedStrip(false);
  j["skins"][0]["joints"] = {1};  // vertex 1 names joint 1 with weight 0.5
  expectSceneError(
      [&] { loadGltf(writeGltf("joint.gltf", j)); },
      {"meshes[0].primitives[0].JOINTS_0", "joint 1 of vertex 1", "not below the skin's 1 joints"});
  j = skinnedStrip(false);
  j["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  expectSceneError([&] { loadGltf(writeGltf("weights.gltf", j)); },
                   {"meshes[0].primitives[0]", "needs both JOINTS_0 and WEIGHTS_0"});
  j = skinnedStrip(false);
  j["skins"][0]["inverseBindMatrices"] = 3;  // the weights: VEC4
  expectSceneError([&] { loadGltf(writeGltf("bind.gltf", j)); },
                   {"skins[0].inverseBindMatrices", "expected 2 MAT4 values"});
  j = skinnedStrip(false);
  j["skins"][0]["joints"] = {1, 9};
  expectSceneError([&] { loadGltf(writeGltf("node.gltf", j)); },
                   {"skins[0].joints[1]", "node 9 does not exist"});
}

}  // namespace
}  // namespace penumbra
