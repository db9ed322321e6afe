// Triangle meshes from files: PLY (our own reader, ASCII and binary) and Wavefront
// OBJ with its MTL materials (through tinyobjloader). Meshes come back in the
// file's own coordinates with one time step; placing them is the caller's job.
#pragma once

#include "scene/scene.h"

#include <string>
#include <vector>

namespace penumbra {

// Normalises a mesh's normals; zero or non-finite ones (files do have them) become the
// normalised sum of the area-weighted face normals around the vertex. No-op without normals.
void repairNormals(Mesh& mesh);

// Reads a PLY file: positions, optional normals (nx ny nz) and uvs (u v, s t or
// texture_u texture_v), polygons fan-triangulated with their winding kept.
// materialIds are all 0. Throws SceneError naming the file and the place.
Mesh loadPly(const std::string& path);

// The MTL numbers that decide how an OBJ material is rendered. Fields hold the MTL
// defaults (as tinyobjloader reports them) when a statement is absent.
struct ObjMaterialDesc {
  std::string name;
  vec3 diffuse = vec3(0.0f);   // Kd
  vec3 specular = vec3(0.0f);  // Ks
  vec3 emission = vec3(0.0f);  // Ke
  float shininess = 1.0f;      // Ns, Phong exponent
  float ior = 1.0f;            // Ni
  float dissolve = 1.0f;       // d (1 = opaque)
  int illum = 0;
};

// Maps an MTL description to a penumbra Material (see mesh_io.cpp for the rules:
// emissive, then glass, then mirror, then glossy conductor, else diffuse).
Material materialFromMtl(const ObjMaterialDesc& desc);

struct ObjData {
  Mesh mesh;                             // materialIds index `materials`
  std::vector<Material> materials;       // albedoTexture left at -1
  std::vector<std::string> diffuseMaps;  // per material: map_Kd path, "" if none
  std::vector<std::string> files;        // the MTL libraries read
  std::vector<std::string> warnings;     // what is not as the file says (a missing library)
};

// Reads an OBJ (triangulated, corners de-indexed into unique position/uv/normal
// triples) and its MTL library. map_Kd paths are resolved relative to the OBJ's
// folder. A missing MTL file falls back to a default grey diffuse material (with a
// warning); faces
// without a material get that default too. Throws SceneError naming the file.
ObjData loadObj(const std::string& path);

}  // namespace penumbra
