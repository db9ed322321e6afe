// Tests for the built-in shapes: areas against the analytic surfaces, outward
// normals and winding, uv conventions, argument checks, and transformMesh.
#include "scene/shapes.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace penumbra {
namespace {

constexpr double kPi = 3.14159265358979323846;

vec3 geometricNormal(const Mesh& mesh, size_t triangle) {
  const vec3 p0 = mesh.positions[mesh.indices[3 * triangle]];
  const vec3 p1 = mesh.positions[mesh.indices[3 * triangle + 1]];
  const vec3 p2 = mesh.positions[mesh.indices[3 * triangle + 2]];
  return glm::cross(p1 - p0, p2 - p0);
}

vec3 centroid(const Mesh& mesh, size_t triangle) {
  return (mesh.positions[mesh.indices[3 * triangle]] +
          mesh.positions[mesh.indices[3 * triangle + 1]] +
          mesh.positions[mesh.indices[3 * triangle + 2]]) /
         3.0f;
}

// Basic consistency every shape must have.
void expectWellFormed(const Mesh& mesh) {
  ASSERT_EQ(mesh.timeSteps, 1);
  ASSERT_EQ(mesh.positions.size(), mesh.vertexCount);
  ASSERT_EQ(mesh.normals.size(), mesh.vertexCount);
  ASSERT_EQ(mesh.uvs.size(), mesh.vertexCount);
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  ASSERT_EQ(mesh.materialIds.size(), mesh.triangleCount());
  for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertexCount);
  for (const vec3& n : mesh.normals) {
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  }
  for (const vec2& uv : mesh.uvs) {
    ASSERT_GE(uv.x, 0.0f);
    ASSERT_LE(uv.x, 1.0f);
    ASSERT_GE(uv.y, 0.0f);
    ASSERT_LE(uv.y, 1.0f);
  }
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    ASSERT_GT(glm::length(geometricNormal(mesh, t)), 0.0f) << "degenerate triangle " << t;
  }
}

// `inside(p)` is a point that the surface near p faces away from (the centre of
// a convex shape, the tube centre of a torus).
void expectOutward(const Mesh& mesh, const std::function<vec3(vec3)>& inside) {
  for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
    const vec3 p = mesh.positions[v];
    ASSERT_GT(glm::dot(mesh.normals[v], p - inside(p)), 0.0f) << "vertex " << v;
  }
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const vec3 c = centroid(mesh, t);
    ASSERT_GT(glm::dot(geometricNormal(mesh, t), c - inside(c)), 0.0f) << "triangle " << t;
  }
}

vec3 origin(vec3) { return vec3(0.0f); }

TEST(Shapes, SphereAreaNormalsAndUv) {
  const float r = 2.0f;
  const Mesh sphere = makeSphere(r, 256, 128);
  expectWellFormed(sphere);
  expectOutward(sphere, origin);
  EXPECT_NEAR(meshArea(sphere), 4.0 * kPi * r * r, 1e-3 * 4.0 * kPi * r * r);
  for (uint32_t v = 0; v < sphere.vertexCount; ++v) {
    const vec3 p = sphere.positions[v];
    EXPECT_NEAR(glm::length(p), r, 1e-5f);
    EXPECT_NEAR(glm::dot(sphere.normals[v], p / r), 1.0f, 1e-5f);
    // v is latitude measured from the bottom pole.
    const float latitude = std::asin(std::clamp(p.y / r, -1.0f, 1.0f));
    EXPECT_NEAR(sphere.uvs[v].y, latitude / float(kPi) + 0.5f, 1e-3f);
  }
}

TEST(Shapes, SpherePolesAreClean) {
  const Mesh sphere = makeSphere(1.0f, 3, 2);  // the coarsest allowed: an octahedron-like solid
  expectWellFormed(sphere);
  expectOutward(sphere, origin);
  // Each pole fan has one triangle per segment, none degenerate.
  EXPECT_EQ(sphere.triangleCount(), 6u);
}

TEST(Shapes, SphereLongitudeIncreasesTowardsRightSeenFromOutside) {
  const Mesh sphere = makeSphere(1.0f, 64, 32);
  for (uint32_t v = 0; v < sphere.vertexCount; ++v) {
    const vec3 p = sphere.positions[v];
    const float horizontal = std::hypot(p.x, p.z);
    if (horizontal < 1e-3f) continue;
    float u = std::atan2(-p.z, p.x) / float(2.0 * kPi);
    if (u < 0.0f) u += 1.0f;
    const float difference = std::abs(u - sphere.uvs[v].x);
    EXPECT_TRUE(difference < 1e-4f || std::abs(difference - 1.0f) < 1e-4f) << "vertex " << v;
  }
}

TEST(Shapes, RectangleIsExactAndFacesUp) {
  const Mesh rect = makeRectangle(vec2(3.0f, 2.0f));
  expectWellFormed(rect);
  EXPECT_EQ(rect.triangleCount(), 2u);
  EXPECT_DOUBLE_EQ(meshArea(rect), 6.0);
  for (size_t t = 0; t < rect.triangleCount(); ++t) {
    const vec3 n = glm::normalize(geometricNormal(rect, t));
    EXPECT_NEAR(n.y, 1.0f, 1e-6f);
  }
  for (uint32_t v = 0; v < rect.vertexCount; ++v) {
    EXPECT_EQ(rect.positions[v].y, 0.0f);
    EXPECT_EQ(rect.normals[v], vec3(0, 1, 0));
    EXPECT_NEAR(rect.uvs[v].x, rect.positions[v].x / 3.0f + 0.5f, 1e-6f);   // u along +x
    EXPECT_NEAR(rect.uvs[v].y, -rect.positions[v].z / 2.0f + 0.5f, 1e-6f);  // v along -z
  }
}

TEST(Shapes, DiskIsExactAndFacesUp) {
  const float r = 1.5f;
  const int n = 40;
  const Mesh disk = makeDisk(r, n);
  expectWellFormed(disk);
  EXPECT_EQ(disk.triangleCount(), size_t(n));
  EXPECT_NEAR(meshArea(disk), 0.5 * n * r * r * std::sin(2.0 * kPi / n), 1e-5);
  for (size_t t = 0; t < disk.triangleCount(); ++t) {
    EXPECT_GT(geometricNormal(disk, t).y, 0.0f);
  }
  for (uint32_t v = 0; v < disk.vertexCount; ++v) {
    EXPECT_NEAR(disk.uvs[v].x, disk.positions[v].x / (2 * r) + 0.5f, 1e-6f);
    EXPECT_NEAR(disk.uvs[v].y, -disk.positions[v].z / (2 * r) + 0.5f, 1e-6f);
  }
}

TEST(Shapes, BoxIsExactWithFlatFaces) {
  const vec3 size(1.0f, 2.0f, 3.0f);
  const Mesh box = makeBox(size);
  expectWellFormed(box);
  expectOutward(box, origin);
  EXPECT_EQ(box.vertexCount, 24u);
  EXPECT_EQ(box.triangleCount(), 12u);
  EXPECT_DOUBLE_EQ(meshArea(box), 2.0 * (1 * 2 + 2 * 3 + 3 * 1));
  for (size_t t = 0; t < box.triangleCount(); ++t) {
    const vec3 flat = glm::normalize(geometricNormal(box, t));
    for (int corner = 0; corner < 3; ++corner) {
      EXPECT_NEAR(glm::dot(box.normals[box.indices[3 * t + corner]], flat), 1.0f, 1e-6f);
    }
  }
  for (const vec3& p : box.positions) {
    EXPECT_EQ(std::abs(p.x), 0.5f);
    EXPECT_EQ(std::abs(p.y), 1.0f);
    EXPECT_EQ(std::abs(p.z), 1.5f);
  }
}

TEST(Shapes, CylinderAreaAndOrientation) {
  const float r = 0.5f, h = 2.0f;
  const int n = 24;
  const double side = n * 2.0 * r * std::sin(kPi / n) * h;
  const double cap = 0.5 * n * r * r * std::sin(2.0 * kPi / n);

  const Mesh open = makeCylinder(r, h, n, false);
  expectWellFormed(open);
  expectOutward(open, [](vec3 p) { return vec3(0.0f, p.y, 0.0f); });
  EXPECT_NEAR(meshArea(open), side, 1e-5);

  const Mesh closed = makeCylinder(r, h, n, true);
  expectWellFormed(closed);
  expectOutward(closed, origin);
  EXPECT_NEAR(meshArea(closed), side + 2.0 * cap, 1e-5);
  for (const vec3& p : closed.positions) EXPECT_NEAR(std::abs(p.y), 0.5f * h, 1e-6f);
}

TEST(Shapes, TorusAreaOrientationAndUv) {
  const float major = 2.0f, minor = 0.5f;
  const Mesh torus = makeTorus(major, minor, 256, 128);
  expectWellFormed(torus);
  const auto tubeCentre = [&](vec3 p) {
    const vec3 flat(p.x, 0.0f, p.z);
    return major * glm::normalize(flat);
  };
  expectOutward(torus, tubeCentre);
  const double exact = 4.0 * kPi * kPi * major * minor;
  EXPECT_NEAR(meshArea(torus), exact, 1e-3 * exact);

  for (uint32_t v = 0; v < torus.vertexCount; ++v) {
    const vec3 p = torus.positions[v];
    // u: angle around the major circle (counter-clockwise seen from +y).
    float u = std::atan2(-p.z, p.x) / float(2.0 * kPi);
    if (u < 0.0f) u += 1.0f;
    float du = std::abs(u - torus.uvs[v].x);
    EXPECT_TRUE(du < 1e-4f || std::abs(du - 1.0f) < 1e-4f) << "vertex " << v;
    // v: angle around the tube, 0 on the outer equator, 1/4 on top.
    const vec3 d = p - tubeCentre(p);
    float tube = std::atan2(d.y, glm::dot(d, glm::normalize(vec3(p.x, 0, p.z))));
    float vExpected = tube / float(2.0 * kPi);
    if (vExpected < 0.0f) vExpected += 1.0f;
    float dv = std::abs(vExpected - torus.uvs[v].y);
    EXPECT_TRUE(dv < 1e-3f || std::abs(dv - 1.0f) < 1e-3f) << "vertex " << v;
  }
}

TEST(Shapes, TorusWithThickTubeIsAllowed) {
  EXPECT_NO_THROW(makeTorus(1.0f, 1.5f, 8, 8));
  EXPECT_NO_THROW(makeTorus(1.0f, 1.0f, 8, 8));
}

TEST(Shapes, RejectsNonsense) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_THROW(makeSphere(-1.0f, 8, 4), std::invalid_argument);
  EXPECT_THROW(makeSphere(0.0f, 8, 4), std::invalid_argument);
  EXPECT_THROW(makeSphere(nan, 8, 4), std::invalid_argument);
  EXPECT_THROW(makeSphere(inf, 8, 4), std::invalid_argument);
  EXPECT_THROW(makeSphere(1.0f, 2, 4), std::invalid_argument);
  EXPECT_THROW(makeSphere(1.0f, 8, 1), std::invalid_argument);
  EXPECT_THROW(makeSphere(1.0f, 1 << 20, 1 << 20), std::invalid_argument);
  EXPECT_THROW(makeRectangle(vec2(-1.0f, 1.0f)), std::invalid_argument);
  EXPECT_THROW(makeRectangle(vec2(1.0f, 0.0f)), std::invalid_argument);
  EXPECT_THROW(makeDisk(1.0f, 2), std::invalid_argument);
  EXPECT_THROW(makeDisk(-1.0f, 8), std::invalid_argument);
  EXPECT_THROW(makeBox(vec3(1.0f, 0.0f, 1.0f)), std::invalid_argument);
  EXPECT_THROW(makeCylinder(1.0f, -2.0f, 8, true), std::invalid_argument);
  EXPECT_THROW(makeCylinder(0.0f, 2.0f, 8, true), std::invalid_argument);
  EXPECT_THROW(makeCylinder(1.0f, 2.0f, 2, true), std::invalid_argument);
  EXPECT_THROW(makeTorus(1.0f, 0.0f, 8, 8), std::invalid_argument);
  EXPECT_THROW(makeTorus(-1.0f, 0.5f, 8, 8), std::invalid_argument);
  EXPECT_THROW(makeTorus(1.0f, 0.5f, 2, 8), std::invalid_argument);
  EXPECT_THROW(makeTorus(1.0f, 0.5f, 8, 2), std::invalid_argument);
  try {
    makeSphere(-1.0f, 8, 4);
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("radius"), std::string::npos) << error.what();
  }
}

TEST(Shapes, TransformMeshUsesInverseTransposeForNormals) {
  Mesh sphere = makeSphere(1.0f, 48, 24);
  const glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), vec3(5, -1, 2)), vec3(2, 1, 0.5f));
  transformMesh(sphere, m);
  expectWellFormed(sphere);
  for (uint32_t v = 0; v < sphere.vertexCount; ++v) {
    // On the ellipsoid (x/2)² + y² + (2z)² = 1 around (5,-1,2) the normal is
    // along the gradient (x/4, y, 4z).
    const vec3 q = sphere.positions[v] - vec3(5, -1, 2);
    const vec3 expected = glm::normalize(vec3(q.x / 4.0f, q.y, 4.0f * q.z));
    EXPECT_NEAR(glm::dot(sphere.normals[v], expected), 1.0f, 1e-5f) << "vertex " << v;
  }
  expectOutward(sphere, [](vec3) { return vec3(5, -1, 2); });
}

TEST(Shapes, TransformMeshKeepsFrontsOutwardUnderMirroring) {
  Mesh box = makeBox(vec3(1.0f, 2.0f, 3.0f));
  transformMesh(box, glm::scale(glm::mat4(1.0f), vec3(-1.0f, 1.0f, 1.0f)));
  expectWellFormed(box);
  expectOutward(box, origin);
}

TEST(Shapes, TransformMeshMovesEveryTimeStep) {
  Mesh rect = makeRectangle(vec2(1.0f));
  const uint32_t n = rect.vertexCount;
  rect.timeSteps = 2;
  for (uint32_t v = 0; v < n; ++v) rect.positions.push_back(rect.positions[v] + vec3(0, 1, 0));
  transformMesh(rect, glm::translate(glm::mat4(1.0f), vec3(10, 0, 0)));
  for (uint32_t v = 0; v < n; ++v) {
    EXPECT_NEAR(rect.positions[v].x, rect.positions[n + v].x, 1e-6f);
    EXPECT_GT(rect.positions[n + v].x, 9.0f);
    EXPECT_EQ(rect.positions[n + v].y, 1.0f);
  }
}

TEST(Shapes, TransformMeshRejectsSingularMatrix) {
  Mesh rect = makeRectangle(vec2(1.0f));
  EXPECT_THROW(transformMesh(rect, glm::scale(glm::mat4(1.0f), vec3(1, 0, 1))),
               std::invalid_argument);
}

TEST(Shapes, MeshAreaOfOneTriangle) {
  Mesh mesh;
  mesh.vertexCount = 3;
  mesh.positions = {vec3(0, 0, 0), vec3(3, 0, 0), vec3(0, 4, 0)};
  mesh.indices = {0, 1, 2};
  mesh.materialIds = {0};
  EXPECT_DOUBLE_EQ(meshArea(mesh), 6.0);
}

}  // namespace
}  // namespace penumbra
