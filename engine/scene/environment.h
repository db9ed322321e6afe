// Light from infinitely far away: an equirectangular (latitude-longitude) radiance map, or a
// constant, with its importance sampler.
//
// The map's convention (Blender's world texture, carried into our y-up world, where glTF's and
// Blender's exporters put Blender's +z):
//  - rows: the top row is straight up (+y), the middle row is the horizon, the bottom row is
//    straight down; the polar angle from +y is theta = pi * t, t running 0..1 down the image;
//  - columns: the azimuth phi = 2 pi (u - 0.5), u running 0..1 left to right, and
//    direction = (sin theta cos phi, cos theta, sin theta sin phi).
//    So the image's centre (u = 0.5) is seen looking along +x, u = 0.75 along +z (towards a
//    default camera), u = 0.25 along -z and the left and right edges along -x: Blender's
//    layout, whose centre is its +x and whose u = 0.25 is its +y (our -z).
//  - rotation: the map turns by `rotation` degrees about +y by the right-hand rule (+x towards
//    -z), as Blender's Mapping node turns it about its +z.
//
// Sampling (pbrt-v4's and Cycles' approach): a piecewise-constant 2D distribution whose cells
// are the map's texels, each weighing its luminance times its solid angle (the integral of
// sin theta over the texel), the luminance being the texel's mean under the bilinear lookup.
// Within a texel the direction is uniform in azimuth and in cos theta, so the pdf in solid
// angle is constant on the texel: a constant map (one texel) is sampled uniformly over the
// sphere, and the pdf is proportional to the radiance wherever a texel and its neighbours
// agree. Multiple importance sampling with BSDF sampling keeps the estimate unbiased where the
// two differ.
// The row is drawn from the marginal by a binary search over its small CDF (u.y, which stays
// stratified across rows); the texel within the row from the row's alias table (Walker's
// method, u.x), one lookup instead of a binary search over a row of a large map, whose cache
// misses dominated the cost. The alias step's leftover fraction places the direction within
// the texel.
#pragma once

#include "core/image.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace penumbra {

// Map coordinates (u, t) in [0,1]^2 (t from the top row) of a unit direction, and back.
glm::vec2 directionToEquirect(vec3 direction);
// Its u alone (the azimuth), without the polar angle's arc cosine.
float equirectU(vec3 direction);
vec3 equirectToDirection(glm::vec2 ut);

// What a scene says about its environment (Scene::environment).
struct Environment {
  std::string file;                  // the map's file; empty for the built-in one
  std::shared_ptr<const Image> map;  // linear RGB radiance, latitude-longitude; null: none
  float strength = 1.0f;             // multiplies the map
  float rotationDegrees = 0.0f;      // about +y, right-hand rule
  bool builtin = false;              // the default environment of a file with no lights
  bool present() const { return map != nullptr; }
};

// Reads an environment map (.exr, .hdr, or any image readImage reads); throws SceneError
// naming the file on a missing or unreadable file or an empty image. A texel value below zero
// or not finite reads as 0: `warning`, when given, then says how many and where the first was
// (empty when there were none).
std::shared_ptr<const Image> readEnvironmentMap(const std::string& path,
                                                std::string* warning = nullptr);

// The built-in neutral environment for an asset opened with no lights: a soft studio, a bright
// upper hemisphere with a broad key light high at the front left and a dimmer floor, grey (no
// colour cast), so that a glTF or OBJ file opens lit as in other glTF viewers. Deterministic.
std::shared_ptr<const Image> builtinEnvironmentMap();

// The environment as a light: radiance in a direction, importance sampling and its pdf.
class EnvironmentLight {
 public:
  // `map` must not be null; strength scales it, rotation turns it about +y.
  EnvironmentLight(std::shared_ptr<const Image> map, float strength, float rotationDegrees);
  // A constant radiance from every direction (a one-texel map).
  static EnvironmentLight constant(vec3 radiance);

  // The radiance from a unit world direction; with `pdf`, also pdf(direction), sharing the
  // direction's map coordinates.
  vec3 radiance(vec3 direction, float* pdf = nullptr) const;
  // A direction drawn with probability proportional to luminance x solid angle; `pdf` is per
  // unit solid angle; with `radiance`, also the radiance from there. False when the map is
  // black (nothing to sample).
  bool sample(glm::vec2 u, vec3& direction, float& pdf, vec3* radiance = nullptr) const;
  float pdf(vec3 direction) const;
  // Asks the cache for what sample(u) will read (its alias entry and the map's texels there),
  // so that a caller can hide that memory latency behind other work. Changes nothing.
  void prefetch(glm::vec2 u) const;
  // The same for what radiance(direction, &pdf) will read: the texel's pdf and the map's
  // texels around it.
  void prefetchDirection(vec3 direction) const;
  // The integral of the luminance over the sphere (strength applied): the light's weight.
  double integratedLuminance() const { return integral_; }
  bool black() const { return !(integral_ > 0); }
  // One radiance from every direction (a one-texel map): nothing to look up or prefetch.
  bool constant() const { return width_ == 1 && height_ == 1; }

  // One texel: its column's entry in its row's alias table, and the pdf of the column it
  // sends the rest of its draws to. The texels' own pdfs are a separate array (pdfs_), which
  // a BSDF sample's MIS weight reads at random: a third of the entries' size, so more of it
  // stays in cache.
  struct AliasEntry {
    float keep = 1.0f;      // the chance that a draw landing on this column stays on it
    uint32_t alias = 0;     // the column it goes to otherwise
    float aliasPdf = 0.0f;  // the alias column's texel's probability over its solid angle
  };

 private:
  vec3 toMap(vec3 world) const;  // undoes the rotation
  vec3 toWorld(vec3 map) const;
  vec3 lookup(float u, float t) const;  // bilinear, map coordinates, strength applied
  float cellPdf(glm::vec2 ut) const;    // the pdf of the texel at map coordinates
  size_t cellAt(glm::vec2 ut) const;    // that texel's index, row by row

  std::shared_ptr<const Image> map_;
  float strength_ = 1.0f;
  float cosRotation_ = 1.0f, sinRotation_ = 0.0f;
  int width_ = 0, height_ = 0;
  double integral_ = 0;
  std::vector<float> cosRowEdge_;  // height + 1 values: cos theta at each row's top edge
  std::vector<float> rowCdf_;      // height + 1 values, 0 .. 1
  std::vector<int> rowGuide_;      // height + 1 values: entry k, the row of (k - 1) / height
  int rowOf(float u) const;        // the row whose cdf interval holds u
  std::vector<AliasEntry> cells_;  // per texel, row by row
  std::vector<float> pdfs_;        // per texel: its probability over its solid angle
};

}  // namespace penumbra
