// Per-vertex tangent frames for normal maps: generated ones (the angle-weighted mean of the
// triangles' dp/du, split by handedness where mirrored uvs meet), a file's moved by a
// transform, and the frame read back at a hit.
#include "scene/tangents.h"

#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <vector>

namespace penumbra {
namespace {

using test::expectNear;

// A mesh in the z = 0 plane (normal +z) from corners and their uvs, one normal-mapped material.
Mesh planarMesh(const std::vector<vec3>& positions, const std::vector<vec2>& uvs,
                const std::vector<uint32_t>& indices) {
  Mesh mesh;
  mesh.positions = positions;
  mesh.normals.assign(positions.size(), vec3(0, 0, 1));
  mesh.uvs = uvs;
  mesh.vertexCount = uint32_t(positions.size());
  mesh.indices = indices;
  mesh.materialIds.assign(indices.size() / 3, 0);
  return mesh;
}

std::vector<Material> normalMapped() {
  std::vector<Material> materials(1);
  materials[0].normalTexture = 0;
  return materials;
}

TEST(Tangents, ASharedVertexTakesTheAngleWeightedMeanOfItsTriangles) {
  // Triangle A (0, 1, 2) has dp/du along +x; B (1, 3, 2), whose uvs are sheared, along
  // (1, -1/3). The shared corners 1 and 2 have 45 degrees in each.
  Mesh mesh = planarMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}},
                         {{0, 0}, {1, 0}, {0, 1}, {1, 1.5f}}, {0, 1, 2, 1, 3, 2});
  generateTangents(mesh, normalMapped());
  ASSERT_EQ(mesh.tangents.size(), 4u);
  const vec3 a(1, 0, 0), b = glm::normalize(vec3(1, -1.0f / 3.0f, 0));
  expectNear(vec3(mesh.tangents[0]), a);
  expectNear(vec3(mesh.tangents[3]), b);
  expectNear(vec3(mesh.tangents[1]), glm::normalize(a + b));
  expectNear(vec3(mesh.tangents[2]), glm::normalize(a + b));
  for (const glm::vec4& t : mesh.tangents) EXPECT_EQ(t.w, 1.0f);

  // The frame at a hit interpolates them: at the middle of the shared edge, from either side.
  vec3 t, bitangent;
  ASSERT_TRUE(
      vertexTangentFrame(mesh, &mesh.indices[0], 0.0f, 0.5f, 0.5f, vec3(0, 0, 1), t, bitangent));
  expectNear(t, glm::normalize(a + b));
  expectNear(bitangent, glm::cross(vec3(0, 0, 1), t));
  vec3 t2, bitangent2;
  ASSERT_TRUE(
      vertexTangentFrame(mesh, &mesh.indices[3], 0.5f, 0.0f, 0.5f, vec3(0, 0, 1), t2, bitangent2));
  expectNear(t2, t);
}

TEST(Tangents, MirroredUvsGiveTheOtherHandednessAndTheirSeamTheLargerSide) {
  // u = |x|: the right triangle (c0, r, c1) runs +u along +x, the left one (c0, c1, l) along
  // -x; +v runs along +y in both, so the left one's bitangent is -cross(n, t).
  // c0 has 135 degrees on the left and 90 on the right; c1 45 on the right, 26.6 on the left.
  Mesh mesh = planarMesh({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, -1, 0}},
                         {{0, 0}, {0, 1}, {1, 0}, {1, -1}}, {0, 2, 1, 0, 1, 3});
  generateTangents(mesh, normalMapped());
  expectNear(vec3(mesh.tangents[2]), vec3(1, 0, 0));
  EXPECT_EQ(mesh.tangents[2].w, 1.0f);
  expectNear(vec3(mesh.tangents[3]), vec3(-1, 0, 0));
  EXPECT_EQ(mesh.tangents[3].w, -1.0f);
  EXPECT_EQ(mesh.tangents[0].w, -1.0f) << "c0: most of its angle is on the left";
  EXPECT_EQ(mesh.tangents[1].w, 1.0f) << "c1: most of its angle is on the right";
  // Each triangle has corners of both sides: it keeps its own frame.
  vec3 t, b;
  EXPECT_FALSE(vertexTangentFrame(mesh, &mesh.indices[0], 0.3f, 0.3f, 0.4f, vec3(0, 0, 1), t, b));
  EXPECT_FALSE(vertexTangentFrame(mesh, &mesh.indices[3], 0.3f, 0.3f, 0.4f, vec3(0, 0, 1), t, b));
}

TEST(Tangents, OnlyNormalMappedOrAnisotropicStaticMeshesWithUvsGetThem) {
  const std::vector<vec3> corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Mesh plain = planarMesh(corners, {{0, 0}, {1, 0}, {0, 1}}, {0, 1, 2});
  generateTangents(plain, std::vector<Material>(1));
  EXPECT_TRUE(plain.tangents.empty()) << "no normal map";
  // Anisotropy reads its direction in the same frame.
  std::vector<Material> anisotropic(1);
  anisotropic[0].anisotropyStrength = 0.5f;
  generateTangents(plain, anisotropic);
  ASSERT_EQ(plain.tangents.size(), 3u);
  EXPECT_EQ(plain.tangents[0], glm::vec4(1, 0, 0, 1));
  Mesh noUvs = planarMesh(corners, {}, {0, 1, 2});
  generateTangents(noUvs, normalMapped());
  EXPECT_TRUE(noUvs.tangents.empty());
  Mesh degenerate = planarMesh(corners, {{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}}, {0, 1, 2});
  generateTangents(degenerate, normalMapped());
  for (const glm::vec4& t : degenerate.tangents) EXPECT_EQ(t, glm::vec4(0.0f));
  vec3 t, b;
  EXPECT_FALSE(vertexTangentFrame(degenerate, &degenerate.indices[0], 0.3f, 0.3f, 0.4f,
                                  vec3(0, 0, 1), t, b));
  // A file's tangent is kept as it is.
  Mesh given = planarMesh(corners, {{0, 0}, {1, 0}, {0, 1}}, {0, 1, 2});
  given.tangents = {{0, 1, 0, -1}, {0, 0, 0, 0}, {0, 1, 0, -1}};
  generateTangents(given, normalMapped());
  EXPECT_EQ(given.tangents[0], glm::vec4(0, 1, 0, -1));
  EXPECT_EQ(given.tangents[1], glm::vec4(1, 0, 0, 1)) << "only the vertex without one is filled";
}

TEST(Tangents, ATransformTurnsThemAndAMirrorFlipsTheirHandedness) {
  const glm::mat3 turn =
      glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), vec3(0, 1, 0)));
  const glm::vec4 turned = transformTangent(2.0f * turn, {1, 0, 0, 1});
  expectNear(vec3(turned), vec3(0, 0, -1));
  EXPECT_EQ(turned.w, 1.0f);
  const glm::vec4 mirrored =
      transformTangent(glm::mat3(glm::scale(glm::mat4(1.0f), {-1, 1, 1})), {1, 0, 0, -1});
  expectNear(vec3(mirrored), vec3(-1, 0, 0));
  EXPECT_EQ(mirrored.w, 1.0f);
  EXPECT_EQ(transformTangent(glm::mat3(1.0f), {0, 0, 0, 1}), glm::vec4(0.0f));
  EXPECT_EQ(transformTangent(glm::mat3(1.0f), {NAN, 0, 0, 1}), glm::vec4(0.0f));

  // placeMesh moves a mesh's tangents with it, and drops them when the mesh moves in time.
  Mesh mesh = planarMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0}, {1, 0}, {0, 1}}, {0, 1, 2});
  mesh.tangents.assign(3, {1, 0, 0, 1});
  const Mesh placed = placeMesh(mesh, glm::scale(glm::mat4(1.0f), {-1, 1, 1}), Motion{});
  ASSERT_EQ(placed.tangents.size(), 3u);
  expectNear(vec3(placed.tangents[1]), vec3(-1, 0, 0));
  EXPECT_EQ(placed.tangents[1].w, -1.0f);
  Motion spin;
  spin.degrees = 30;
  spin.axis = vec3(0, 1, 0);
  EXPECT_TRUE(placeMesh(mesh, glm::mat4(1.0f), spin).tangents.empty());
}

}  // namespace
}  // namespace penumbra
