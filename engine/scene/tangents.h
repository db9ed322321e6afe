// Tangent frames for normal maps. A tangent-space normal map is read in the frame its baker
// used: for a glTF file, the file's TANGENT attribute where it has one, else (as glTF asks)
// MikkTSpace's per-vertex tangents, which generateTangents approximates: each vertex's tangent
// is the angle-weighted mean of its triangles' dp/du made orthogonal to its normal, so the
// frame, and with it the mapped normal, varies smoothly from triangle to triangle instead of
// jumping at every edge. A vertex where mirrored uvs meet (triangles of both handedness) takes
// the side most of its angle lies on; the triangles of the other side keep their own frames.
#pragma once

#include "scene/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace penumbra {

// dp/du and dp/dv of a triangle from two edges and their uv changes; false when its uvs are
// degenerate (no parameterisation).
inline bool triangleTangents(glm::vec3 e1, glm::vec3 e2, glm::vec2 duv1, glm::vec2 duv2,
                             glm::vec3& dpdu, glm::vec3& dpdv) {
  const float det = duv1.x * duv2.y - duv1.y * duv2.x;
  if (!(std::abs(det) > 1e-12f)) return false;
  dpdu = (duv2.y * e1 - duv1.y * e2) / det;
  dpdv = (duv1.x * e2 - duv2.x * e1) / det;
  return true;
}

// Fills the tangents of the vertices of `mesh` that have none (w = 0) and belong to a
// triangle whose material has a normal map or anisotropy (Material::needsTangents). A mesh of
// several time steps, or without uvs, is left as it is (its triangles take their own frames).
void generateTangents(Mesh& mesh, const std::vector<Material>& materials);
// generateTangents for every mesh of the scene.
void generateTangents(Scene& scene);

// A tangent of a file (glTF's TANGENT, in the file's frame) moved by the linear part of a
// transform: its direction, normalised, and its handedness, flipped by a mirroring transform
// (the normal's inverse transpose and the tangent's transform turn the cross product around).
// A tangent without a direction, or not finite, becomes (0, 0, 0, 0): none.
glm::vec4 transformTangent(const glm::mat3& linear, glm::vec4 tangent);

// The normal-map frame of a hit at barycentrics (b0, b1, b2) of triangle `idx` from the
// mesh's vertex tangents, around the unit normal `n`: the interpolated tangent made
// orthonormal to n, and the bitangent w·cross(n, t). False when a corner has no tangent or
// the corners disagree on the handedness (the caller then uses the triangle's own frame).
bool vertexTangentFrame(const Mesh& mesh, const uint32_t* idx, float b0, float b1, float b2,
                        glm::vec3 n, glm::vec3& t, glm::vec3& b);

}  // namespace penumbra
