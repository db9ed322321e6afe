#include "scene/tangents.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
// The angle of a triangle's corner between the edges to its two other corners.
float cornerAngle(glm::vec3 toB, glm::vec3 toC) {
  const float lengths = glm::length(toB) * glm::length(toC);
  if (!(lengths > 0.0f)) return 0.0f;
  return std::acos(std::clamp(glm::dot(toB, toC) / lengths, -1.0f, 1.0f));
}
}  // namespace

void generateTangents(Mesh& mesh, const std::vector<Material>& materials) {
  if (mesh.timeSteps != 1 || mesh.uvs.empty()) return;
  const size_t triangles = mesh.triangleCount();
  const auto needsTangents = [&](size_t tri) {
    const uint32_t id = mesh.materialIds[tri];
    return id < materials.size() && materials[id].needsTangents();
  };
  size_t first = 0;
  while (first < triangles && !needsTangents(first)) ++first;
  if (first == triangles) return;
  if (mesh.tangents.empty()) mesh.tangents.assign(mesh.vertexCount, glm::vec4(0.0f));

  // Per vertex and handedness (0: w = +1, 1: w = -1), the angle-weighted sum of the unit
  // tangents its triangles give it, and the angle summed.
  std::vector<glm::vec3> sum(2 * size_t(mesh.vertexCount), glm::vec3(0.0f));
  std::vector<float> weight(2 * size_t(mesh.vertexCount), 0.0f);
  for (size_t tri = first; tri < triangles; ++tri) {
    if (!needsTangents(tri)) continue;
    const uint32_t* idx = &mesh.indices[3 * tri];
    const glm::vec3 p[3] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
    glm::vec3 dpdu, dpdv;
    if (!triangleTangents(p[1] - p[0], p[2] - p[0], mesh.uvs[idx[1]] - mesh.uvs[idx[0]],
                          mesh.uvs[idx[2]] - mesh.uvs[idx[0]], dpdu, dpdv))
      continue;
    const glm::vec3 faceNormal = glm::cross(p[1] - p[0], p[2] - p[0]);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = idx[k];
      if (mesh.tangents[v].w != 0.0f) continue;  // the file's own
      glm::vec3 n = mesh.normals.empty() ? faceNormal : mesh.normals[v];
      const float nLength = glm::length(n);
      if (!(nLength > 0.0f)) continue;
      n /= nLength;
      glm::vec3 t = dpdu - n * glm::dot(n, dpdu);
      const float tLength = glm::length(t);
      if (!(tLength > 0.0f) || !std::isfinite(tLength)) continue;
      t /= tLength;
      const size_t side = 2 * size_t(v) + (glm::dot(glm::cross(n, t), dpdv) < 0.0f ? 1 : 0);
      const float angle = cornerAngle(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
      sum[side] += angle * t;
      weight[side] += angle;
    }
  }
  for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
    const size_t side = 2 * size_t(v) + (weight[2 * size_t(v) + 1] > weight[2 * size_t(v)]);
    const float length = glm::length(sum[side]);
    // Tangents that cancel (a vertex at a pole of its uvs, say) leave it without one.
    if (!(length > 1e-3f * weight[side])) continue;
    mesh.tangents[v] = glm::vec4(sum[side] / length, side % 2 ? -1.0f : 1.0f);
  }
}

void generateTangents(Scene& scene) {
  for (Mesh& mesh : scene.meshes) generateTangents(mesh, scene.materials);
}

glm::vec4 transformTangent(const glm::mat3& linear, glm::vec4 tangent) {
  const glm::vec3 t = linear * glm::vec3(tangent);
  const float length = glm::length(t);
  if (!(length > 0.0f) || !std::isfinite(length) || !std::isfinite(tangent.w))
    return glm::vec4(0.0f);
  const float mirror = glm::determinant(linear) < 0.0f ? -1.0f : 1.0f;
  return glm::vec4(t / length, tangent.w < 0.0f ? -mirror : mirror);
}

bool vertexTangentFrame(const Mesh& mesh, const uint32_t* idx, float b0, float b1, float b2,
                        glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  if (mesh.tangents.empty() || mesh.timeSteps != 1) return false;
  const glm::vec4 &t0 = mesh.tangents[idx[0]], &t1 = mesh.tangents[idx[1]],
                  &t2 = mesh.tangents[idx[2]];
  if (t0.w == 0.0f || t0.w != t1.w || t1.w != t2.w) return false;
  t = b0 * glm::vec3(t0) + b1 * glm::vec3(t1) + b2 * glm::vec3(t2);
  t -= n * glm::dot(n, t);
  const float length = glm::length(t);
  if (!(length > 1e-6f)) return false;
  t /= length;
  b = t0.w * glm::cross(n, t);
  return true;
}

}  // namespace penumbra
