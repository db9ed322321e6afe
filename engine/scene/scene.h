// Scene description in memory: meshes (already in world space, with motion baked
// into vertex time steps), materials, textures, the camera and render settings.
// Plain structs; loading lives in scene_loader.*, meshes from files in mesh_io.*,
// built-in shapes in shapes.*, ray queries in accel.*.
#pragma once

#include "core/image.h"
#include "scene/camera.h"
#include "scene/environment.h"
#include "scene/texture_image.h"

#include <glm/mat2x2.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {

using glm::mat4;
using glm::vec2;

// An error in a scene or mesh file; the message names the file and the field.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Triangle mesh. With timeSteps > 1, positions (and normals) hold one full set of
// vertices per step, step-major: vertex v of step s is at [s * vertexCount + v].
// Steps are spread evenly over scene time [0, 1] (the shutter interval).
struct Mesh {
  std::string name;
  uint32_t vertexCount = 0;
  int timeSteps = 1;
  std::vector<vec3> positions;
  std::vector<vec3> normals;  // empty: flat shading
  std::vector<vec2> uvs;      // empty: (0,0); never per step
  std::vector<vec3> colors;   // empty: white; multiply the base colour; never per step
  // Per vertex, the tangent frame a normal map is read in (scene/tangents.h): xyz along +u, w
  // = ±1 the side of the bitangent w·cross(n, xyz), which runs along +v. A vertex with w = 0
  // has none, and its triangles take their own frame. Empty: none at all. Only for a mesh of
  // one time step.
  std::vector<glm::vec4> tangents;
  std::vector<uint32_t> indices;      // 3 per triangle, counter-clockwise = front
  std::vector<uint32_t> materialIds;  // one per triangle, index into Scene::materials

  size_t triangleCount() const { return indices.size() / 3; }
};

// Texture: a tagged struct rather than a hierarchy; evaluated in textures.cpp.
struct Texture {
  enum class Kind { Constant, Image, Checker, Stripes };
  Kind kind = Kind::Constant;
  vec3 color0 = vec3(0.8f);  // constant colour, or first checker/stripe colour
  vec3 color1 = vec3(0.2f);  // second checker/stripe colour
  vec2 scale = vec2(1.0f);   // uv repetitions (checker cells / stripes per unit uv)
  int imageIndex = -1;       // Kind::Image: index into Scene::images
  vec3 factor = vec3(1.0f);  // Kind::Image: multiplies the texels at lookup (glTF's factors)
  // Kind::Image, with hasOffset: added after the factor, offset + factor x texel (a glossiness
  // map read as roughness, 1 - glossiness x texel).
  bool hasOffset = false;
  vec3 offset = vec3(0.0f);
  // Kind::Image: how uv outside [0, 1) reaches the image (glTF's sampler), and an affine map
  // of the surface's uv before the lookup, uv' = uvLinear uv + uvOffset (glTF's
  // KHR_texture_transform, in this engine's uv, whose v runs up the image).
  TextureWrapModes wrap;
  bool uvTransformed = false;
  glm::mat2 uvLinear = glm::mat2(1.0f);
  vec2 uvOffset = vec2(0.0f);
};

struct Material {
  // Pbr is glTF's metallic-roughness model: a GGX conductor of weight `metallic` tinted by
  // the base colour over a dielectric base that is glass with weight `transmission` and
  // diffuse otherwise; a path picks one part by weight (docs/scene-format.md).
  enum class Type { Diffuse, Conductor, Mirror, Dielectric, Pbr };
  Type type = Type::Diffuse;
  std::string name;
  int albedoTexture = -1;      // Diffuse: index into Scene::textures; -1 uses `albedo`
  vec3 albedo = vec3(0.8f);    // Diffuse reflectance, or Conductor/Mirror tint (F0)
  float roughness = 0.2f;      // Conductor: GGX alpha = roughness^2
  float ior = 1.5f;            // Dielectric index of refraction
  vec3 emission = vec3(0.0f);  // radiance emitted on the front side (CCW normal)
  float metallic = 0.0f;       // Pbr: weight of the conductor
  float transmission = 0.0f;   // Pbr: share of glass in the non-metallic part
  // Pbr: glTF's KHR_materials_specular on the dielectric base's specular layer: its reflectance
  // at normal incidence is min(f0(ior) x specularColor, 1) x specular, at grazing specular.
  float specular = 1.0f;
  vec3 specularColor = vec3(1.0f);
  int specularTexture = -1;       // multiplies `specular` (its first channel, linear)
  int specularColorTexture = -1;  // multiplies `specularColor`
  // Pbr: glTF's KHR_materials_clearcoat: a clear GGX layer (ior 1.5, untinted) of this weight
  // and roughness over the whole material.
  float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
  int clearcoatTexture = -1;           // weight x red (linear data)
  int clearcoatRoughnessTexture = -1;  // roughness x green (linear data)
  // The coat's own tangent-space normal map (as normalTexture, with its scale); without it the
  // coat takes the interpolated normal, whatever maps the base (glTF's clearcoatNormalTexture).
  int clearcoatNormalTexture = -1;
  float clearcoatNormalScale = 1.0f;
  // Pbr: glTF's KHR_materials_sheen: a layer of fibres over the whole material (under the coat)
  // that reflects sheenColor by the Charlie distribution of alpha sheenRoughness^2, and takes
  // from the material below what it reflects (glTF's albedo scaling). Black: none.
  vec3 sheenColor = vec3(0.0f);
  float sheenRoughness = 0.0f;
  int sheenColorTexture = -1;      // multiplies `sheenColor` (sRGB)
  int sheenRoughnessTexture = -1;  // multiplies `sheenRoughness` (its alpha channel)
  int transmissionTexture = -1;    // multiplies `transmission` (its red channel, linear)
  // Pbr: glTF's KHR_materials_anisotropy: the specular lobes' alpha along the anisotropy's
  // direction is mix(roughness^2, 1, strength^2), across it roughness^2. The direction is the
  // tangent frame's +u (the normal map's), turned by `anisotropyRotation` radians towards +v;
  // the texture's red and green (as 2 x - 1) give it per texel before the turn, its blue scales
  // the strength (linear data).
  float anisotropyStrength = 0.0f;
  float anisotropyRotation = 0.0f;
  int anisotropyTexture = -1;
  // Pbr: glTF's KHR_materials_iridescence: a thin film over the base's specular layer and the
  // conductor, whose Fresnel reflectance replaces theirs in the share `iridescence` (times the
  // texture's red). Its index of refraction, and its thickness in nanometres: the maximum, or
  // mix(minimum, maximum, green) of the thickness texture (linear data).
  float iridescence = 0.0f;
  int iridescenceTexture = -1;
  float iridescenceIor = 1.3f;
  float iridescenceThicknessMin = 100.0f, iridescenceThicknessMax = 400.0f;
  int iridescenceThicknessTexture = -1;
  // Pbr and Dielectric: glTF's KHR_materials_volume: light travelling inside the (closed) object
  // keeps attenuationColor^(distance / attenuationDistance) of itself; an infinite distance
  // absorbs nothing.
  vec3 attenuationColor = vec3(1.0f);
  float attenuationDistance = std::numeric_limits<float>::infinity();
  int metallicRoughnessTexture = -1;  // Pbr: roughness x green, metallic x blue (linear data)
  int emissionTexture = -1;           // multiplies `emission`; -1: uniform
  int normalTexture = -1;             // tangent-space normal map (linear, +y along +v); -1: none
  float normalScale = 1.0f;           // scales the map's x and y
  int alphaTexture = -1;              // cut-out: coverage in the texture's first channel; -1: none
  float alpha = 1.0f;                 // coverage factor (times the texture's)
  float alphaCutoff = -1.0f;          // coverage below it is a hole; negative: opaque
  // glTF's KHR_materials_unlit: every ray that meets it sees its base colour (times its
  // texture and vertex colour), and it reflects nothing; it lights nothing by next-event
  // estimation either.
  bool unlit = false;
  // Blended (glTF's BLEND): the coverage is the chance that a ray stops at the surface, decided
  // per ray (stochastic transparency), instead of a cutoff.
  bool alphaBlend = false;
  // Whether its hits need their tangent frame: a normal map (the base's or the coat's) or
  // anisotropy.
  bool needsTangents() const {
    return normalTexture >= 0 || anisotropyStrength > 0 || clearcoatNormalTexture >= 0;
  }
  // Whether its coat has a normal of its own, apart from the shading normal: a coat over a
  // normal-mapped base, or with its own map.
  bool coatHasOwnNormal() const {
    return clearcoat > 0 && (normalTexture >= 0 || clearcoatNormalTexture >= 0);
  }
  bool isEmissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
  bool hasCutouts() const { return alphaCutoff >= 0.0f || alphaBlend; }
  bool absorbs() const {
    return attenuationDistance > 0 &&
           attenuationDistance < std::numeric_limits<float>::infinity() &&
           attenuationColor != vec3(1.0f);
  }
  // Every texture id of the material (-1 where it has none).
  std::array<int*, 16> textureIds() {
    return {&albedoTexture,
            &metallicRoughnessTexture,
            &emissionTexture,
            &normalTexture,
            &alphaTexture,
            &specularTexture,
            &specularColorTexture,
            &clearcoatTexture,
            &clearcoatRoughnessTexture,
            &sheenColorTexture,
            &sheenRoughnessTexture,
            &transmissionTexture,
            &anisotropyTexture,
            &clearcoatNormalTexture,
            &iridescenceTexture,
            &iridescenceThicknessTexture};
  }
  // Whether its surface reads a texture when shaded (cut-outs are Embree's): its hits need
  // their uv footprint.
  bool textured() const {
    return albedoTexture >= 0 || metallicRoughnessTexture >= 0 || emissionTexture >= 0 ||
           normalTexture >= 0 || specularTexture >= 0 || specularColorTexture >= 0 ||
           clearcoatTexture >= 0 || clearcoatRoughnessTexture >= 0 || sheenColorTexture >= 0 ||
           sheenRoughnessTexture >= 0 || transmissionTexture >= 0 || anisotropyTexture >= 0 ||
           clearcoatNormalTexture >= 0 || iridescenceTexture >= 0 ||
           iridescenceThicknessTexture >= 0;
  }
};

// A light that is a point or a direction (glTF's KHR_lights_punctual): it cannot be hit by a
// ray, only sampled by next-event estimation. Units follow glTF: `intensity` is luminous
// intensity (candela) for point and spot lights and illuminance (lux) for directional ones,
// in the same units as emitted radiance (nits): a point light of intensity I at distance d
// gives the irradiance I / d^2.
struct PunctualLight {
  enum class Kind { Point, Spot, Directional };
  Kind kind = Kind::Point;
  std::string name;
  vec3 position = vec3(0.0f);
  vec3 direction = vec3(0.0f, 0.0f, -1.0f);   // unit; where the light shines (spot, directional)
  vec3 intensity = vec3(1.0f);                // colour times intensity
  float cosInner = 1.0f, cosOuter = 0.7071f;  // spot cone: full inside, none outside
  // Point and spot lights: the distance at which the light reaches nothing (glTF's `range`), by
  // glTF's window clamp(1 - (d / range)^4, 0, 1) on the inverse square; 0: none (it never ends).
  float range = 0.0f;
};

struct RenderSettings {
  int width = 256;
  int height = 256;
  int spp = 16;
  int maxDepth = 8;  // path vertices after the camera; 1 = direct light only
};

struct Scene {
  std::string sourcePath;  // for messages
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<TextureImage> images;  // the image textures' texels (textures.h: textureBytes)
  std::vector<PunctualLight> lights;
  // Light from far away (environment.h). Without one, a `background` lights the scene as a
  // constant environment; with one, the environment lights it and the background is the
  // backdrop camera rays see. `transparent` hides whatever camera rays would see beyond the
  // scene (the alpha channel of a render says where that is).
  Environment environment;
  std::optional<vec3> background;
  bool transparent = false;
  Camera camera;
  RenderSettings settings;
  // Features a file has that are not rendered (glTF's, say), one line each, "file: what".
  std::vector<std::string> warnings;
  // Every file the scene was read from: the scene file, then the meshes, MTL libraries,
  // textures and glTF buffers and images it refers to (what the viewer watches to reload).
  std::vector<std::string> sourceFiles;
};

// A per-vertex attribute (position or normal) of a mesh at scene time t in [0,1],
// interpolated linearly between time steps as Embree does.
template <typename T>
T vertexAtTime(const std::vector<T>& values, const Mesh& mesh, uint32_t vertex, float time) {
  if (mesh.timeSteps <= 1) return values[vertex];
  const float f = std::clamp(time, 0.0f, 1.0f) * float(mesh.timeSteps - 1);
  const int step = std::min(int(f), mesh.timeSteps - 2);
  const float w = f - float(step);
  const size_t base = size_t(step) * mesh.vertexCount + vertex;
  return (1 - w) * values[base] + w * values[base + mesh.vertexCount];
}

// Axis-aligned bounds of every vertex of every step.
void sceneBounds(const Scene& scene, vec3& lo, vec3& hi);

}  // namespace penumbra
