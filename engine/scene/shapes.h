// Built-in shapes tessellated into triangle meshes in object space (one time step,
// outward-facing counter-clockwise triangles, uvs, smooth normals on curved
// surfaces), plus the mesh helpers scene loading needs: placing a mesh with a
// matrix and measuring its area.
#pragma once

#include "scene/scene.h"

#include <glm/mat4x4.hpp>

namespace penumbra {

// Sphere centred at the origin. `segments` around the y axis (>= 3), `rings` from
// pole to pole (>= 2). u = longitude / 2π, v = 0 at the bottom pole, 1 at the top.
Mesh makeSphere(float radius, int segments, int rings);

// Rectangle in the xz plane centred at the origin, normal +y. size = (x extent, z extent).
// u runs along +x, v along -z (so the texture reads upright seen from above with -z up).
Mesh makeRectangle(vec2 size);

// Disk in the xz plane centred at the origin, normal +y, uv a planar map of its
// bounding square (same orientation as makeRectangle).
Mesh makeDisk(float radius, int segments);

// Axis-aligned box centred at the origin: 6 faces with 4 vertices each, flat
// normals and a full [0,1]² uv square per face.
Mesh makeBox(vec3 size);

// Cylinder around the y axis centred at the origin. The side has smooth normals,
// u = angle / 2π and v = 0 at the bottom, 1 at the top; caps, if any, are flat disks.
Mesh makeCylinder(float radius, float height, int segments, bool capped);

// Torus lying in the xz plane around the y axis. u = angle around the major circle
// / 2π, v = angle around the tube / 2π (v = 0 on the outer equator).
Mesh makeTorus(float majorRadius, float minorRadius, int majorSegments, int minorSegments);

// Applies an affine transform to the positions of every time step, and to the
// normals with the inverse transpose (renormalised). A mirroring transform also
// reverses triangle winding, so front faces keep facing the same side of the
// surface. Throws std::invalid_argument for a singular matrix.
void transformMesh(Mesh& mesh, const glm::mat4& m);

// Total triangle area at time step 0.
double meshArea(const Mesh& mesh);

}  // namespace penumbra
