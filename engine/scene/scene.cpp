#include "scene/scene.h"

#include "scene/scene_loader.h"
#include "scene/shapes.h"
#include "scene/tangents.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra {

void sceneBounds(const Scene& scene, vec3& lo, vec3& hi) {
  lo = vec3(std::numeric_limits<float>::max());
  hi = vec3(-std::numeric_limits<float>::max());
  for (const Mesh& mesh : scene.meshes)
    for (const vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
}

bool Motion::moving() const { return translation != vec3(0.0f) || degrees != 0.0f; }

mat4 transformAt(const mat4& base, const Motion& motion, float t) {
  const vec3 origin = vec3(base[3]);
  mat4 m = glm::translate(mat4(1.0f), origin + t * motion.translation);
  if (motion.degrees != 0.0f)
    m = glm::rotate(m, glm::radians(t * motion.degrees), glm::normalize(motion.axis));
  return glm::translate(m, -origin) * base;
}

int motionTimeSteps(const Motion& motion) {
  if (motion.timeSteps > 0) return std::clamp(motion.timeSteps, 2, 129);
  if (!motion.moving()) return 1;
  // Embree interpolates vertices linearly between steps: 5 degrees per step keeps a
  // spinning sphere's chord error below 0.1% of its radius.
  const int rotationSteps = int(std::ceil(std::abs(motion.degrees) / 5.0f)) + 1;
  return std::clamp(rotationSteps, 2, 129);
}

Mesh placeMesh(const Mesh& objectSpace, const mat4& base, const Motion& motion) {
  const int steps = motionTimeSteps(motion);
  Mesh out = objectSpace;
  out.timeSteps = steps;
  out.positions.clear();
  out.normals.clear();
  const uint32_t n = objectSpace.vertexCount;
  for (int s = 0; s < steps; ++s) {
    const float t = steps == 1 ? 0.0f : float(s) / float(steps - 1);
    Mesh step;
    step.vertexCount = n;
    step.positions.assign(objectSpace.positions.begin(), objectSpace.positions.begin() + n);
    if (!objectSpace.normals.empty())
      step.normals.assign(objectSpace.normals.begin(), objectSpace.normals.begin() + n);
    transformMesh(step, transformAt(base, motion, t));
    out.positions.insert(out.positions.end(), step.positions.begin(), step.positions.end());
    out.normals.insert(out.normals.end(), step.normals.begin(), step.normals.end());
  }
  // The file's tangents (glTF's) turn with the mesh; they are not kept per time step.
  if (steps > 1) out.tangents.clear();
  for (glm::vec4& t : out.tangents) t = transformTangent(glm::mat3(base), t);
  // A mirroring transform turns counter-clockwise into clockwise: restore the front side.
  if (glm::determinant(glm::mat3(base)) < 0)
    for (size_t i = 0; i + 2 < out.indices.size(); i += 3)
      std::swap(out.indices[i + 1], out.indices[i + 2]);
  return out;
}

}  // namespace penumbra
