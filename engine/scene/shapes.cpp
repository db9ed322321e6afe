// Tessellation of the built-in shapes and the mesh transform / area helpers.
// Curved surfaces are built as (u, v) grids whose seam column is duplicated so
// uvs can run all the way from 0 to 1 without wrapping back inside a triangle.
#include "scene/shapes.h"

#include "core/constants.h"

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra {
namespace {

// Above this many vertices a shape is almost certainly a typo (and would also
// overflow 32-bit indices long before memory runs out).
constexpr long long kMaxShapeVertices = 1LL << 26;

[[noreturn]] void fail(const char* shape, const std::string& message) {
  throw std::invalid_argument(std::string(shape) + ": " + message);
}

void requirePositive(const char* shape, const char* what, float value) {
  if (!(value > 0.0f) || !std::isfinite(value)) {
    std::ostringstream text;
    text << what << " must be a positive finite number (got " << value << ")";
    fail(shape, text.str());
  }
}

void requireCount(const char* shape, const char* what, int value, int minimum) {
  if (value < minimum) {
    fail(shape, std::string(what) + " must be at least " + std::to_string(minimum) + " (got " +
                    std::to_string(value) + ")");
  }
}

void requireGridSize(const char* shape, int columns, int rows) {
  if ((long long)(columns + 1LL) * (rows + 1LL) > kMaxShapeVertices) {
    fail(shape,
         "tessellation " + std::to_string(columns) + " x " + std::to_string(rows) + " is too fine");
  }
}

Mesh emptyMesh(const char* name) {
  Mesh mesh;
  mesh.name = name;
  mesh.timeSteps = 1;
  return mesh;
}

void addVertex(Mesh& mesh, vec3 position, vec3 normal, vec2 uv) {
  mesh.positions.push_back(position);
  mesh.normals.push_back(normal);
  mesh.uvs.push_back(uv);
  ++mesh.vertexCount;
}

void addTriangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
  mesh.materialIds.push_back(0);
}

struct SurfacePoint {
  vec3 position;
  vec3 normal;
};

// A (columns+1) x (rows+1) vertex grid over (u, v) in [0,1]². `surface` must be
// parametrised so that d/du x d/dv points outward; then the triangles below are
// counter-clockwise seen from outside. Rows that collapse to a point (sphere poles)
// are flagged so their zero-area triangles are left out.
void addGrid(Mesh& mesh, int columns, int rows, bool bottomRowIsPoint, bool topRowIsPoint,
             const std::function<SurfacePoint(float u, float v)>& surface) {
  const uint32_t first = mesh.vertexCount;
  for (int row = 0; row <= rows; ++row) {
    const float v = float(row) / float(rows);
    for (int column = 0; column <= columns; ++column) {
      const float u = float(column) / float(columns);
      const SurfacePoint point = surface(u, v);
      addVertex(mesh, point.position, point.normal, vec2(u, v));
    }
  }
  const auto at = [&](int column, int row) {
    return first + uint32_t(row * (columns + 1) + column);
  };
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      const uint32_t a = at(column, row), b = at(column + 1, row);
      const uint32_t c = at(column + 1, row + 1), d = at(column, row + 1);
      if (!(bottomRowIsPoint && row == 0)) addTriangle(mesh, a, b, c);
      if (!(topRowIsPoint && row == rows - 1)) addTriangle(mesh, a, c, d);
    }
  }
}

// Fan around a centre vertex at height y; facing +y, or -y when `facingDown`.
// uv is the planar map of the bounding square, mirrored for the downward face so
// a texture is not seen mirror-imaged from below.
void addDisk(Mesh& mesh, float radius, int segments, float y, bool facingDown) {
  const vec3 normal(0.0f, facingDown ? -1.0f : 1.0f, 0.0f);
  const uint32_t centre = mesh.vertexCount;
  addVertex(mesh, vec3(0.0f, y, 0.0f), normal, vec2(0.5f));
  for (int k = 0; k < segments; ++k) {
    const float phi = kTwoPi * float(k) / float(segments);
    const float c = std::cos(phi), s = std::sin(phi);
    // Angle increases counter-clockwise seen from +y: x = cos, z = -sin.
    const vec2 uv(0.5f + 0.5f * c, facingDown ? 0.5f - 0.5f * s : 0.5f + 0.5f * s);
    addVertex(mesh, vec3(radius * c, y, -radius * s), normal, uv);
  }
  for (int k = 0; k < segments; ++k) {
    const uint32_t here = centre + 1 + uint32_t(k);
    const uint32_t next = centre + 1 + uint32_t((k + 1) % segments);
    if (facingDown) {
      addTriangle(mesh, centre, next, here);
    } else {
      addTriangle(mesh, centre, here, next);
    }
  }
}

// Unit vector in the xz plane at longitude `phi`, counter-clockwise seen from +y.
vec3 radial(float phi) { return vec3(std::cos(phi), 0.0f, -std::sin(phi)); }

}  // namespace

Mesh makeSphere(float radius, int segments, int rings) {
  requirePositive("makeSphere", "radius", radius);
  requireCount("makeSphere", "segments", segments, 3);
  requireCount("makeSphere", "rings", rings, 2);
  requireGridSize("makeSphere", segments, rings);

  Mesh mesh = emptyMesh("sphere");
  addGrid(mesh, segments, rings, true, true, [&](float u, float v) {
    const float latitude = kPi * (v - 0.5f);  // -π/2 at the bottom pole
    vec3 normal = std::cos(latitude) * radial(kTwoPi * u);
    normal.y = std::sin(latitude);
    // Exactly on the axis at the poles: cos(±π/2) in float is not quite zero.
    if (v == 0.0f || v == 1.0f) normal = vec3(0.0f, v == 0.0f ? -1.0f : 1.0f, 0.0f);
    return SurfacePoint{radius * normal, normal};
  });

  // Each pole triangle touches one copy of its pole vertex; centring that copy's u
  // over the triangle's longitude span keeps texture lookups from shearing there.
  const uint32_t rowLength = uint32_t(segments) + 1;
  const uint32_t topRow = uint32_t(rings) * rowLength;
  for (uint32_t column = 0; column < rowLength; ++column) {
    // (The clamp only touches the one unused copy at each pole.)
    mesh.uvs[column].x = std::min((float(column) + 0.5f) / float(segments), 1.0f);
    mesh.uvs[topRow + column].x = std::max((float(column) - 0.5f) / float(segments), 0.0f);
  }
  return mesh;
}

Mesh makeRectangle(vec2 size) {
  requirePositive("makeRectangle", "size.x", size.x);
  requirePositive("makeRectangle", "size.y", size.y);

  Mesh mesh = emptyMesh("rectangle");
  const float hx = 0.5f * size.x, hz = 0.5f * size.y;
  const vec3 up(0.0f, 1.0f, 0.0f);
  addVertex(mesh, vec3(-hx, 0.0f, hz), up, vec2(0.0f, 0.0f));
  addVertex(mesh, vec3(hx, 0.0f, hz), up, vec2(1.0f, 0.0f));
  addVertex(mesh, vec3(hx, 0.0f, -hz), up, vec2(1.0f, 1.0f));
  addVertex(mesh, vec3(-hx, 0.0f, -hz), up, vec2(0.0f, 1.0f));
  addTriangle(mesh, 0, 1, 2);
  addTriangle(mesh, 0, 2, 3);
  return mesh;
}

Mesh makeDisk(float radius, int segments) {
  requirePositive("makeDisk", "radius", radius);
  requireCount("makeDisk", "segments", segments, 3);
  requireGridSize("makeDisk", segments, 1);

  Mesh mesh = emptyMesh("disk");
  addDisk(mesh, radius, segments, 0.0f, false);
  return mesh;
}

Mesh makeBox(vec3 size) {
  requirePositive("makeBox", "size.x", size.x);
  requirePositive("makeBox", "size.y", size.y);
  requirePositive("makeBox", "size.z", size.z);

  // Per face: outward normal, then the directions of increasing u and v, chosen
  // so that uAxis x vAxis = normal (counter-clockwise seen from outside) and v
  // points up (+y) on the side faces.
  struct Face {
    vec3 normal, uAxis, vAxis;
  };
  const Face faces[6] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
  };
  const vec3 half = 0.5f * size;

  Mesh mesh = emptyMesh("box");
  for (const Face& face : faces) {
    // The axes are unit and axis-aligned, so a dot product with the half size
    // picks the extent along each of them.
    const vec3 centre = face.normal * std::abs(glm::dot(face.normal, half));
    const vec3 du = face.uAxis * std::abs(glm::dot(face.uAxis, half));
    const vec3 dv = face.vAxis * std::abs(glm::dot(face.vAxis, half));
    const uint32_t first = mesh.vertexCount;
    addVertex(mesh, centre - du - dv, face.normal, vec2(0.0f, 0.0f));
    addVertex(mesh, centre + du - dv, face.normal, vec2(1.0f, 0.0f));
    addVertex(mesh, centre + du + dv, face.normal, vec2(1.0f, 1.0f));
    addVertex(mesh, centre - du + dv, face.normal, vec2(0.0f, 1.0f));
    addTriangle(mesh, first, first + 1, first + 2);
    addTriangle(mesh, first, first + 2, first + 3);
  }
  return mesh;
}

Mesh makeCylinder(float radius, float height, int segments, bool capped) {
  requirePositive("makeCylinder", "radius", radius);
  requirePositive("makeCylinder", "height", height);
  requireCount("makeCylinder", "segments", segments, 3);
  requireGridSize("makeCylinder", segments, 3);

  Mesh mesh = emptyMesh("cylinder");
  const float halfHeight = 0.5f * height;
  addGrid(mesh, segments, 1, false, false, [&](float u, float v) {
    const vec3 normal = radial(kTwoPi * u);
    return SurfacePoint{radius * normal + vec3(0.0f, (2.0f * v - 1.0f) * halfHeight, 0.0f), normal};
  });
  if (capped) {
    addDisk(mesh, radius, segments, halfHeight, false);
    addDisk(mesh, radius, segments, -halfHeight, true);
  }
  return mesh;
}

Mesh makeTorus(float majorRadius, float minorRadius, int majorSegments, int minorSegments) {
  requirePositive("makeTorus", "majorRadius", majorRadius);
  requirePositive("makeTorus", "minorRadius", minorRadius);
  requireCount("makeTorus", "majorSegments", majorSegments, 3);
  requireCount("makeTorus", "minorSegments", minorSegments, 3);
  requireGridSize("makeTorus", majorSegments, minorSegments);

  Mesh mesh = emptyMesh("torus");
  addGrid(mesh, majorSegments, minorSegments, false, false, [&](float u, float v) {
    const vec3 out = radial(kTwoPi * u);
    const float theta = kTwoPi * v;
    const vec3 normal = std::cos(theta) * out + vec3(0.0f, std::sin(theta), 0.0f);
    return SurfacePoint{majorRadius * out + minorRadius * normal, normal};
  });
  return mesh;
}

void transformMesh(Mesh& mesh, const glm::mat4& m) {
  const glm::mat3 linear(m);
  const float det = glm::determinant(linear);
  if (det == 0.0f || !std::isfinite(det)) {
    throw std::invalid_argument("transformMesh: the matrix is singular or not finite");
  }
  const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));

  for (vec3& p : mesh.positions) p = vec3(m * glm::vec4(p, 1.0f));
  for (vec3& n : mesh.normals) {
    const vec3 transformed = normalMatrix * n;
    const float length = glm::length(transformed);
    if (length > 0.0f) n = transformed / length;
  }
  // A mirror turns counter-clockwise into clockwise; swapping two corners puts the
  // front face back on the side the (transformed) normals point to.
  if (det < 0.0f) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    }
  }
}

double meshArea(const Mesh& mesh) {
  double area = 0.0;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::dvec3 p0(mesh.positions[mesh.indices[t]]);
    const glm::dvec3 p1(mesh.positions[mesh.indices[t + 1]]);
    const glm::dvec3 p2(mesh.positions[mesh.indices[t + 2]]);
    area += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
  }
  return area;
}

}  // namespace penumbra
