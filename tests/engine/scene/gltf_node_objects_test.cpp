// What a glTF node holds besides its mesh: here, EXT_mesh_gpu_instancing's instances of it,
// each placed by its own translation, rotation and scale before the node's transform. (Lights
// and cameras are gltf_io_test.cpp's.)
#include "scene/gltf_io.h"

#include "tests/engine/scene/expect_scene_error.h"
#include "tests/engine/scene/gltf_test_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace penumbra {
namespace {

using namespace gltf_test;
using test::expectSceneError;

// The test quad (gltf_test_files.h) whose untransformed node ("plain", mesh 1) is moved to
// x = 10 and holds two instances: one moved by (0, 0, 1); one turned +90 degrees about z,
// scaled by 2 and moved by (0, 5, 0).
Json instancedQuad() {
  std::string b = quadBuffer();
  const size_t at = b.size();
  const float s = std::sqrt(0.5f);
  append<float>(b, {0, 0, 1, 0, 5, 0});        // TRANSLATION
  append<float>(b, {0, 0, 0, 1, 0, 0, s, s});  // ROTATION
  append<float>(b, {1, 1, 1, 2, 2, 2});        // SCALE
  Json j = quadGltf(dataUri(b), b.size());
  const size_t views = j["bufferViews"].size(), accessors = j["accessors"].size();
  size_t offset = at;
  for (size_t bytes : {24, 32, 24}) {
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    offset += bytes;
  }
  for (size_t k = 0; k < 3; ++k)
    j["accessors"].push_back({{"bufferView", views + k},
                              {"componentType", 5126},
                              {"count", 2},
                              {"type", k == 1 ? "VEC4" : "VEC3"}});
  j["nodes"][2]["translation"] = {10, 0, 0};
  j["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {
      {"TRANSLATION", accessors}, {"ROTATION", accessors + 1}, {"SCALE", accessors + 2}};
  j["extensionsUsed"].push_back("EXT_mesh_gpu_instancing");
  j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  return j;
}

TEST(GltfInstancing, EachInstanceIsPlacedBeforeTheNodesTransform) {
  const GltfData g = loadGltf(writeGltf("instances.gltf", instancedQuad()));
  // The child's four vertices, then two instances of the plain quad's four.
  ASSERT_EQ(g.mesh.vertexCount, 12u);
  // Corner (1, 1, 0) of the first instance: moved by (0, 0, 1), then by the node's (10, 0, 0).
  expectNear(g.mesh.positions[4 + 2], vec3(11, 1, 1));
  // Of the second: scaled to (2, 2, 0), turned to (-2, 2, 0), moved to (-2, 7, 0), then (8, 7, 0).
  expectNear(g.mesh.positions[8 + 2], vec3(8, 7, 0));
  expectNear(g.mesh.positions[8 + 1], vec3(10, 7, 0));  // corner (1, 0, 0)
  EXPECT_EQ(allWarnings(g).find("EXT_mesh_gpu_instancing"), std::string::npos) << allWarnings(g);
}

TEST(GltfInstancing, DamagedInstancesNameTheElement) {
  Json j = instancedQuad();
  auto& attributes = j["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
  j["accessors"][attributes["SCALE"].get<size_t>()]["count"] = 1;
  expectSceneError(
      [&] { loadGltf(writeGltf("count.gltf", j)); },
      {"nodes[2].extensions.EXT_mesh_gpu_instancing.attributes", "as many instances each"});
  j = instancedQuad();
  j["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] =
      j["nodes"][2]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"];
  expectSceneError([&] { loadGltf(writeGltf("rotation.gltf", j)); },
                   {"EXT_mesh_gpu_instancing.attributes.ROTATION", "must be VEC4"});
}

}  // namespace
}  // namespace penumbra
