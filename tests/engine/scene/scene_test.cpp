// Motion tests: an object's transform at time t, and motion baked into vertex time steps.
#include "scene/scene.h"
#include "scene/scene_loader.h"
#include "scene/shapes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace penumbra {
namespace {

vec3 apply(const mat4& m, vec3 p) { return vec3(m * glm::vec4(p, 1.0f)); }

TEST(Motion, TranslationMovesLinearlyOverTheShutter) {
  const mat4 base = glm::translate(mat4(1.0f), vec3(1, 2, 3));
  Motion motion;
  motion.translation = vec3(2, 0, -4);
  EXPECT_NEAR(glm::length(apply(transformAt(base, motion, 0.0f), vec3(0)) - vec3(1, 2, 3)), 0,
              1e-6);
  EXPECT_NEAR(glm::length(apply(transformAt(base, motion, 0.5f), vec3(0)) - vec3(2, 2, 1)), 0,
              1e-6);
  EXPECT_NEAR(glm::length(apply(transformAt(base, motion, 1.0f), vec3(0)) - vec3(3, 2, -1)), 0,
              1e-6);
  EXPECT_EQ(motionTimeSteps(motion), 2);
}

TEST(Motion, RotationSpinsAboutTheObjectsOwnOrigin) {
  const mat4 base = glm::translate(mat4(1.0f), vec3(5, 0, 0));
  Motion motion;
  motion.axis = vec3(0, 1, 0);
  motion.degrees = 180;
  for (float t : {0.0f, 0.3f, 1.0f})  // the centre stays put
    EXPECT_NEAR(glm::length(apply(transformAt(base, motion, t), vec3(0)) - vec3(5, 0, 0)), 0, 1e-5);
  // A point on the +x side of the object ends on the -x side after half a turn.
  EXPECT_NEAR(glm::length(apply(transformAt(base, motion, 1.0f), vec3(1, 0, 0)) - vec3(4, 0, 0)), 0,
              1e-5);
  // A quarter turn about +y takes +x to -z.
  EXPECT_NEAR(glm::length(apply(transformAt(base, motion, 0.5f), vec3(1, 0, 0)) - vec3(5, 0, -1)),
              0, 1e-5);
  EXPECT_EQ(motionTimeSteps(motion), 37);
}

TEST(Motion, PlacedMeshHoldsOneVertexSetPerTimeStep) {
  const Mesh sphere = makeSphere(1.0f, 16, 8);
  Motion motion;
  motion.translation = vec3(0, 0, 2);
  const Mesh placed = placeMesh(sphere, glm::translate(mat4(1.0f), vec3(1, 0, 0)), motion);
  ASSERT_EQ(placed.timeSteps, 2);
  ASSERT_EQ(placed.positions.size(), 2 * size_t(sphere.vertexCount));
  for (uint32_t v = 0; v < sphere.vertexCount; ++v) {
    EXPECT_NEAR(glm::length(placed.positions[v] - (sphere.positions[v] + vec3(1, 0, 0))), 0, 1e-5);
    EXPECT_NEAR(glm::length(placed.positions[sphere.vertexCount + v] -
                            (sphere.positions[v] + vec3(1, 0, 2))),
                0, 1e-5);
  }
}

TEST(Motion, MirroringTransformKeepsFrontFacesOutward) {
  const Mesh sphere = makeSphere(1.0f, 16, 8);
  const Mesh placed = placeMesh(sphere, glm::scale(mat4(1.0f), vec3(-1, 1, 1)), Motion{});
  for (size_t t = 0; t < placed.triangleCount(); ++t) {
    const vec3 a = placed.positions[placed.indices[3 * t]],
               b = placed.positions[placed.indices[3 * t + 1]],
               c = placed.positions[placed.indices[3 * t + 2]];
    const vec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) > 1e-8f) {
      EXPECT_GT(glm::dot(n, a + b + c), 0.0f);
    }
  }
}

}  // namespace
}  // namespace penumbra
