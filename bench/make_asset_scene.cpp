// Writes the asset benchmark scene (issue 25, part 4): a 1280x720 JSON scene with a textured
// glTF asset of about 50k triangles on a set of over 300k triangles, lit by an environment map.
//
// Into OUT_DIR it writes, deterministically (the same bytes on every run):
//   asset.glb  "Knot": a (2,3) torus-knot tube with flutes and collars, 49,920 triangles,
//              POSITION, NORMAL, TANGENT, TEXCOORD_0; one metallic-roughness material with five
//              PNG textures embedded in the .glb: base colour (sRGB), tangent-space normal map,
//              metallic-roughness, emissive (sRGB) and occlusion, 2048x2048 unless
//              --texture-size says otherwise. The pattern is painted panels, hazard stripes,
//              brushed-metal panels, dark panels with glowing strips, seams, rivets and worn
//              paint, all from hashed noise: no image comes from outside.
//   set.glb    the set: an uneven stone floor, a curved back wall with stone courses, five
//              fluted columns with rings, a pedestal, three boulders and a chrome ball; plain
//              materials, no textures.
//   sky.hdr    a copy of the environment map (--env, default scenes/env/sky.hdr);
//   scene.json Penumbra's scene: render 1280x720, a camera on the asset, the two files as mesh
//              objects and "environment": {"file": "sky.hdr", "strength": 1, "rotation": 0}.
//
// Normal-map convention (glTF's): texel = (n * 0.5 + 0.5) * 255 for the tangent-space normal
// n = (x along dp/du, y towards the top of the image, i.e. decreasing v, z out of the surface);
// TANGENT.w is chosen so that cross(normal, tangent) * w points to decreasing v. The heights
// behind it are in metres, so bumps have their true slope on the surface.
//
// Usage: penumbra_make_asset_scene OUT_DIR [--texture-size N] [--env FILE]
#include "asset_scene_glb.h"

#include <stb/stb_image_write.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using glm::dvec3;
using json = nlohmann::json;

using namespace asset_scene;

namespace {

constexpr double kPi = 3.14159265358979323846;

// ------------------------------------------------------------------------------- noise
uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

double hash01(uint32_t a, uint32_t b, uint32_t c) {
  return (hash3(a, b, c) >> 8) * (1.0 / 16777216.0);
}

int wrap(int i, int n) { return ((i % n) + n) % n; }

// Value noise on a lattice of px by py cells over [0,1)^2, periodic in both directions.
double valueNoise(double s, double t, int px, int py, uint32_t seed) {
  const double x = s * px, y = t * py;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  double fx = x - i, fy = y - j;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  auto v = [&](int a, int b) { return hash01(uint32_t(wrap(a, px)), uint32_t(wrap(b, py)), seed); };
  const double top = v(i, j) + (v(i + 1, j) - v(i, j)) * fx;
  const double bottom = v(i, j + 1) + (v(i + 1, j + 1) - v(i, j + 1)) * fx;
  return top + (bottom - top) * fy;
}

// Fractal sum of value noise, in [0, 1], periodic over [0,1)^2.
double fbm(double s, double t, int px, int py, uint32_t seed, int octaves) {
  double sum = 0, weight = 0, amplitude = 1;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * valueNoise(s, t, px << o, py << o, seed + uint32_t(o));
    weight += amplitude;
    amplitude *= 0.5;
  }
  return sum / weight;
}

double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

dvec3 mix(dvec3 a, dvec3 b, double t) { return a + (b - a) * t; }

uint8_t byteOf(double x) { return uint8_t(std::lround(std::clamp(x, 0.0, 1.0) * 255.0)); }

uint8_t srgbByte(double linear) {
  const double x = std::clamp(linear, 0.0, 1.0);
  return byteOf(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
}

// Runs body(row) for rows [0, n) on all cores; each row is written by exactly one thread,
// so the result does not depend on the thread count.
void parallelRows(int n, const std::function<void(int)>& body) {
  const int threads = std::max(1, int(std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      for (int row = k; row < n; row += threads) body(row);
    });
  for (std::thread& t : pool) t.join();
}

// ------------------------------------------------------------------------------ meshes

dvec3 positionOf(const Mesh& m, uint32_t i) {
  return dvec3(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
}

// A grid surface: f(u, v) over [0,1]^2 with (nu+1) x (nv+1) vertices (seam vertices doubled),
// each triangle wound counter-clockwise seen from the side `outward(u, v)` points to.
Mesh gridSurface(const std::string& name, int nu, int nv,
                 const std::function<dvec3(double, double)>& f,
                 const std::function<dvec3(double, double)>& outward) {
  Mesh m;
  m.name = name;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const dvec3 p = f(double(i) / nu, double(j) / nv);
      m.positions.insert(m.positions.end(), {float(p.x), float(p.y), float(p.z)});
    }
  auto id = [&](int i, int j) { return uint32_t(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      const dvec3 hint = outward((i + 0.5) / nu, (j + 0.5) / nv);
      const dvec3 face =
          glm::cross(positionOf(m, b) - positionOf(m, a), positionOf(m, c) - positionOf(m, a));
      if (glm::dot(face, hint) >= 0)
        m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
      else
        m.indices.insert(m.indices.end(), {a, c, b, a, d, c});
    }
  return m;
}

// Smooth vertex normals: area-weighted face normals, summed over vertices at the same position
// (so seams and poles are smooth too).
void computeNormals(Mesh& m) {
  const size_t n = m.vertexCount();
  std::vector<dvec3> sum(n, dvec3(0.0));
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    const dvec3 face =
        glm::cross(positionOf(m, b) - positionOf(m, a), positionOf(m, c) - positionOf(m, a));
    sum[a] += face;
    sum[b] += face;
    sum[c] += face;
  }
  std::map<std::array<float, 3>, dvec3> welded;
  for (size_t i = 0; i < n; ++i)
    welded[{m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]}] += sum[i];
  m.normals.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    dvec3 v = welded[{m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]}];
    v = glm::length(v) > 0 ? glm::normalize(v) : dvec3(0, 1, 0);
    m.normals[3 * i] = float(v.x);
    m.normals[3 * i + 1] = float(v.y);
    m.normals[3 * i + 2] = float(v.z);
  }
}

void append(Mesh& to, const Mesh& from) {
  const uint32_t base = uint32_t(to.vertexCount());
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  for (uint32_t i : from.indices) to.indices.push_back(base + i);
}

// Signed volume (divergence theorem): positive when a closed mesh's faces point outward.
double signedVolume(const Mesh& m) {
  double v = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3)
    v += glm::dot(positionOf(m, m.indices[t]),
                  glm::cross(positionOf(m, m.indices[t + 1]), positionOf(m, m.indices[t + 2])));
  return v / 6;
}

// ---------------------------------------------------------------------- the asset: a knot
constexpr int kKnotAlong = 520, kKnotAround = 48;  // 2 * 520 * 48 = 49,920 triangles
constexpr int kTextureRepeats = 6;                 // the texture repeats 6 times along the knot
constexpr int kPanelsS = 8, kPanelsT = 3;          // panels per texture, along and around
constexpr double kKnotScale = 0.48, kMajor = 1.0, kMinor = 0.45, kTube = 0.19;

dvec3 knotCentre(double phi) {  // the (2,3) torus knot in the xy plane, facing +z
  const double r = kMajor + kMinor * std::cos(3 * phi);
  return kKnotScale *
         dvec3(r * std::cos(2 * phi), r * std::sin(2 * phi), kMinor * std::sin(3 * phi));
}

// Tube radius: six flutes around, a raised collar at every texture repeat along.
double knotRadius(double u, double v) {
  const double along = u * kTextureRepeats;
  const double fromCollar = std::abs(along - std::round(along));  // in repeats
  const double collar = 0.14 * smoothstep(0.035, 0.012, fromCollar);
  return kKnotScale * kTube * (1 + 0.035 * std::cos(2 * kPi * 6 * v) + collar);
}

struct Extent {  // metres of surface per unit of texture coordinate
  double s = 1, t = 1;
};

Mesh makeKnot(Extent& extent) {
  const int nu = kKnotAlong, nv = kKnotAround;
  // Centreline and a rotation-minimising frame, its twist after one loop spread evenly along
  // the loop so that the frame (and so the texture's v) closes up.
  std::vector<dvec3> c(nu), T(nu), N(nu), B(nu);
  for (int i = 0; i < nu; ++i) {
    const double phi = 2 * kPi * i / nu, h = 1e-5;
    c[i] = knotCentre(phi);
    T[i] = glm::normalize(knotCentre(phi + h) - knotCentre(phi - h));
  }
  N[0] = glm::normalize(glm::cross(T[0], dvec3(0, 0, 1)));
  for (int i = 1; i <= nu; ++i) {
    const dvec3 t = T[i % nu], n = N[i - 1] - glm::dot(N[i - 1], t) * t;
    if (i < nu)
      N[i] = glm::normalize(n);
    else {
      const dvec3 end = glm::normalize(n);
      const double twist = std::atan2(glm::dot(glm::cross(N[0], end), T[0]), glm::dot(N[0], end));
      for (int k = 0; k < nu; ++k) {  // rotate N[k] about T[k] by -twist * k / nu
        const double a = -twist * k / nu;
        const dvec3 b = glm::cross(T[k], N[k]);
        N[k] = glm::normalize(std::cos(a) * N[k] + std::sin(a) * b);
      }
    }
  }
  for (int i = 0; i < nu; ++i) B[i] = glm::cross(T[i], N[i]);
  // Strands must not touch: the centreline keeps away from itself by more than two radii.
  double nearest = 1e9;
  for (int i = 0; i < nu; ++i)
    for (int k = i + nu / 12; k < i + nu - nu / 12; ++k)
      nearest = std::min(nearest, glm::length(c[i] - c[k % nu]));
  if (nearest < 2.6 * kKnotScale * kTube) throw std::runtime_error("knot strands intersect");

  auto point = [&](int i, int j) {  // i, j on the periodic grid
    const int ii = wrap(i, nu), jj = wrap(j, nv);
    const double v = double(jj) / nv, a = 2 * kPi * v;
    return c[ii] + knotRadius(double(ii) / nu, v) * (std::cos(a) * N[ii] + std::sin(a) * B[ii]);
  };
  Mesh m;
  m.name = "Knot";
  double lengthS = 0, lengthT = 0;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const dvec3 p = point(i, j);
      const dvec3 du = point(i + 1, j) - point(i - 1, j), dv = point(i, j + 1) - point(i, j - 1);
      const dvec3 n = glm::normalize(glm::cross(dv, du));  // outward (checked below)
      const dvec3 t = glm::normalize(du - glm::dot(du, n) * n);
      // glTF: cross(n, t) * w points to decreasing v (the top of the image).
      const double w = glm::dot(glm::cross(n, t), -dv) >= 0 ? 1.0 : -1.0;
      m.positions.insert(m.positions.end(), {float(p.x), float(p.y), float(p.z)});
      m.normals.insert(m.normals.end(), {float(n.x), float(n.y), float(n.z)});
      m.tangents.insert(m.tangents.end(), {float(t.x), float(t.y), float(t.z), float(w)});
      m.uvs.insert(m.uvs.end(), {float(double(i) / nu * kTextureRepeats), float(double(j) / nv)});
      if (j < nv && i < nu) {
        lengthS += glm::length(point(i + 1, j) - p);
        lengthT += glm::length(point(i, j + 1) - p);
      }
    }
  auto id = [&](int i, int j) { return uint32_t(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)  // cross(du, dv) points inward, so wind the other way round
      m.indices.insert(m.indices.end(), {id(i, j), id(i + 1, j + 1), id(i + 1, j), id(i, j),
                                         id(i, j + 1), id(i + 1, j + 1)});
  if (!(signedVolume(m) > 0)) throw std::runtime_error("knot faces point inward");
  extent.s = lengthS / nv / kTextureRepeats;  // mean metres per unit of texture s
  extent.t = lengthT / nu;
  return m;
}

// ----------------------------------------------------------------- the asset's textures
struct Surface {
  dvec3 base{0.5};
  double height = 0;  // metres, along the normal
  double metallic = 0, roughness = 0.5, occlusion = 1;
  dvec3 emission{0.0};
};

// The panel pattern at texture coordinates (s, t), periodic over [0,1)^2.
Surface pattern(double s, double t, const Extent& e) {
  Surface out;
  const double ps = s * kPanelsS, pt = t * kPanelsT;
  const int ci = int(std::floor(ps)), cj = int(std::floor(pt));
  const double width = e.s / kPanelsS, height = e.t / kPanelsT;  // one panel, metres
  const double x = (ps - ci) * width, y = (pt - cj) * height;
  const double edge = std::min({x, width - x, y, height - y});
  const uint32_t kind = hash3(uint32_t(wrap(ci, kPanelsS)), uint32_t(wrap(cj, kPanelsT)), 7) % 8;

  const double grain = fbm(s, t, 48, 18, 11, 5);     // paint and dirt variation
  const double brushed = fbm(s, t, 6, 1024, 23, 3);  // streaks along s
  const double wearNoise = fbm(s, t, 96, 36, 31, 4);
  double metalExposed = 0;
  switch (kind) {
    case 0:
    case 1:
    case 2:  // red-orange paint
      out.base = dvec3(0.52, 0.10, 0.035) * (0.9 + 0.2 * grain);
      out.roughness = 0.38 + 0.15 * grain;
      break;
    case 3:
    case 4:  // off-white paint
      out.base = dvec3(0.68, 0.66, 0.60) * (0.92 + 0.16 * grain);
      out.roughness = 0.45 + 0.15 * grain;
      break;
    case 5:  // brushed metal
      out.base = dvec3(0.80, 0.78, 0.74) * (0.9 + 0.15 * brushed);
      out.metallic = 1;
      out.roughness = 0.18 + 0.12 * brushed;
      metalExposed = 1;
      break;
    case 6: {  // dark panel with a recessed glowing strip
      out.base = dvec3(0.035, 0.037, 0.04) * (0.8 + 0.4 * grain);
      out.roughness = 0.62;
      const double sx = std::abs(x - width / 2) - 0.32 * width,
                   sy = std::abs(y - height / 2) - 0.05 * height;
      const double inside = std::max(sx, sy);  // < 0 inside the strip, metres
      if (inside < 0) {
        out.emission = dvec3(0.15, 0.85, 1.0) * smoothstep(0.0, 0.004, -inside);
        out.base = dvec3(0.2, 0.3, 0.32);
        out.roughness = 0.15;
        out.height -= 0.0012;
      }
      out.occlusion *= 1 - 0.35 * smoothstep(0.004, 0.0, std::abs(inside));
      break;
    }
    default: {  // hazard stripes
      const double stripe = std::fmod((x + y) / 0.05, 1.0);
      out.base = stripe < 0.5 ? dvec3(0.80, 0.52, 0.02) : dvec3(0.025);
      out.base *= 0.9 + 0.2 * grain;
      out.roughness = 0.5 + 0.1 * grain;
      break;
    }
  }
  // Worn paint, most of it near the seams: bare metal shows, a little below the paint.
  if (metalExposed == 0) {
    const double wear = smoothstep(0.69, 0.73, wearNoise + 0.2 * std::exp(-edge / 0.012));
    if (wear > 0) {
      out.base = mix(out.base, dvec3(0.62, 0.61, 0.60) * (0.85 + 0.2 * brushed), wear);
      out.metallic = mix(dvec3(out.metallic), dvec3(1.0), wear).x;
      out.roughness = out.roughness + (0.3 - out.roughness) * wear;
      out.height -= 0.00025 * wear;
      out.emission *= 1 - wear;
    }
  }
  // Seams between panels: rounded grooves 4 mm wide each side, 2.5 mm deep, dark and rough.
  const double groove = std::max(0.0, 1 - (edge / 0.004) * (edge / 0.004));
  out.height -= 0.0025 * groove;
  out.base *= 1 - 0.75 * groove;
  out.roughness += (0.8 - out.roughness) * groove;
  out.occlusion *= 1 - 0.6 * smoothstep(0.012, 0.0, edge);
  // Rivets 18 mm in from each corner: domes of radius 6 mm, 2 mm high, bare metal.
  const double rx = std::min(x, width - x) - 0.018, ry = std::min(y, height - y) - 0.018;
  const double r = std::sqrt(rx * rx + ry * ry) / 0.006;
  if (r < 1) {
    out.height += 0.002 * std::sqrt(1 - r * r);
    out.base = dvec3(0.7, 0.68, 0.65);
    out.metallic = 1;
    out.roughness = 0.3;
    out.emission = dvec3(0.0);
  }
  out.occlusion *= 1 - 0.4 * smoothstep(1.6, 1.0, r) * (r >= 1 ? 1 : 0);
  // Dirt in the crevices.
  out.base *= 0.75 + 0.25 * out.occlusion;
  return out;
}

// The five textures, size x size texels each; texel (i, j) (j = 0 the top row) samples
// (s, t) = ((i + 0.5) / size, (j + 0.5) / size): glTF's uv, v down the image.
std::vector<Image8> makeTextures(int size, const Extent& extent) {
  const size_t n = size_t(size) * size;
  std::vector<float> height(n);
  Image8 base{"baseColor", 3, std::vector<uint8_t>(3 * n), {}};
  Image8 normal{"normal", 3, std::vector<uint8_t>(3 * n), {}};
  Image8 mr{"metallicRoughness", 3, std::vector<uint8_t>(3 * n), {}};
  Image8 emissive{"emissive", 3, std::vector<uint8_t>(3 * n), {}};
  Image8 occlusion{"occlusion", 1, std::vector<uint8_t>(n), {}};
  parallelRows(size, [&](int j) {
    for (int i = 0; i < size; ++i) {
      const size_t k = size_t(j) * size + i;
      const Surface p = pattern((i + 0.5) / size, (j + 0.5) / size, extent);
      height[k] = float(p.height);
      for (int c = 0; c < 3; ++c) {
        base.pixels[3 * k + c] = srgbByte(p.base[c]);
        emissive.pixels[3 * k + c] = srgbByte(p.emission[c]);
      }
      mr.pixels[3 * k] = 255;  // red is unused by glTF's metallic-roughness texture
      mr.pixels[3 * k + 1] = byteOf(std::clamp(p.roughness, 0.05, 1.0));
      mr.pixels[3 * k + 2] = byteOf(p.metallic);
      occlusion.pixels[k] = byteOf(p.occlusion);
    }
  });
  // Normals from the heights: n = (-dh/dx, -dh/dy, 1) with x along s and y up the image
  // (towards decreasing t), both in metres on the surface.
  const double dx = extent.s / size, dy = extent.t / size;
  parallelRows(size, [&](int j) {
    for (int i = 0; i < size; ++i) {
      auto h = [&](int a, int b) {
        return double(height[size_t(wrap(b, size)) * size + wrap(a, size)]);
      };
      const double dhds = (h(i + 1, j) - h(i - 1, j)) / (2 * dx);
      const double dhdt = (h(i, j + 1) - h(i, j - 1)) / (2 * dy);  // per metre of increasing t
      const dvec3 n = glm::normalize(dvec3(-dhds, dhdt, 1.0));     // up the image = -t
      const size_t k = size_t(j) * size + i;
      for (int c = 0; c < 3; ++c) normal.pixels[3 * k + c] = byteOf(n[c] * 0.5 + 0.5);
    }
  });
  return {std::move(base), std::move(normal), std::move(mr), std::move(emissive),
          std::move(occlusion)};
}

void encodePngs(std::vector<Image8>& images, int size) {
  std::vector<std::thread> pool;
  for (Image8& image : images)
    pool.emplace_back([&image, size] {
      auto sink = [](void* context, void* data, int bytes) {
        auto* out = static_cast<std::vector<uint8_t>*>(context);
        out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + bytes);
      };
      if (!stbi_write_png_to_func(sink, &image.png, size, size, image.channels, image.pixels.data(),
                                  size * image.channels))
        throw std::runtime_error("PNG encoding failed: " + image.name);
    });
  for (std::thread& t : pool) t.join();
}

// ------------------------------------------------------------------------------- the set
Mesh makeFloor() {  // 12 m x 12 m of uneven stone, 256 x 256 quads
  auto f = [](double u, double v) {
    const double x = (u - 0.5) * 12, z = (v - 0.5) * 12;
    const double bump = 0.012 * (fbm(u, v, 12, 12, 101, 4) - 0.5);
    return dvec3(x, bump, z);
  };
  Mesh m = gridSurface("Floor", 256, 256, f, [](double, double) { return dvec3(0, 1, 0); });
  computeNormals(m);
  return m;
}

Mesh makeWall() {  // a curved back wall: 150 degrees of a 5.2 m circle, 3.6 m high, stone courses
  auto f = [](double u, double v) {
    const double a = kPi * (1.0 + (u - 0.5) * 150.0 / 180.0) + kPi / 2;  // centred on -z
    const double y = v * 3.6, course = std::fmod(y / 0.4, 1.0);
    const double block = std::fmod(u * 40 + (int(y / 0.4) % 2) * 0.5, 1.0);
    const double mortar = std::max(smoothstep(0.06, 0.0, std::min(course, 1 - course)),
                                   smoothstep(0.04, 0.0, std::min(block, 1 - block)));
    const double r = 5.2 + 0.02 * mortar - 0.01 * fbm(u, v, 40, 12, 202, 3);
    return dvec3(r * std::cos(a), y, r * std::sin(a));
  };
  Mesh m = gridSurface("Wall", 320, 72, f, [](double u, double) {
    const double a = kPi * (1.0 + (u - 0.5) * 150.0 / 180.0) + kPi / 2;
    return -dvec3(std::cos(a), 0, std::sin(a));  // faces the centre
  });
  computeNormals(m);
  return m;
}

Mesh makeColumn(dvec3 at) {  // a fluted column, 2.9 m, 20 flutes, with a base and capital ring
  auto f = [at](double u, double v) {
    const double a = 2 * kPi * u, y = 0.2 + v * 2.7;
    const double r = 0.21 * (1 - 0.06 * v) - 0.012 * std::pow(std::abs(std::sin(10 * a)), 0.7);
    return at + dvec3(r * std::cos(a), y, r * std::sin(a));
  };
  auto radial = [](double u, double) {
    return dvec3(std::cos(2 * kPi * u), 0, std::sin(2 * kPi * u));
  };
  Mesh m = gridSurface("Column", 160, 96, f, radial);
  for (double y : {0.1, 2.95}) {  // rings: a torus-like roll of radius 0.1
    auto ring = [at, y](double u, double v) {
      const double a = 2 * kPi * u, b = 2 * kPi * v, r = 0.25 + 0.1 * std::cos(b);
      return at + dvec3(r * std::cos(a), y + 0.1 * std::sin(b), r * std::sin(a));
    };
    auto out = [](double u, double v) {
      const double a = 2 * kPi * u, b = 2 * kPi * v;
      return dvec3(std::cos(b) * std::cos(a), std::sin(b), std::cos(b) * std::sin(a));
    };
    append(m, gridSurface("", 96, 24, ring, out));
  }
  computeNormals(m);
  return m;
}

Mesh makePedestal(double radius, double top) {  // a cylinder with a rounded top edge
  auto f = [radius, top](double u, double v) {
    const double a = 2 * kPi * u;
    double r, y;
    if (v < 0.5) {  // the side, from the floor up to the start of the rounding
      r = radius;
      y = v / 0.5 * (top - 0.04);
    } else if (v < 0.75) {  // a quarter circle of radius 4 cm
      const double b = (v - 0.5) / 0.25 * kPi / 2;
      r = radius - 0.04 + 0.04 * std::cos(b);
      y = top - 0.04 + 0.04 * std::sin(b);
    } else {  // the flat top
      r = (radius - 0.04) * (1 - (v - 0.75) / 0.25);
      y = top;
    }
    return dvec3(r * std::cos(a), y, r * std::sin(a));
  };
  auto out = [](double u, double v) {
    return v < 0.6 ? dvec3(std::cos(2 * kPi * u), 0, std::sin(2 * kPi * u)) : dvec3(0, 1, 0);
  };
  Mesh m = gridSurface("Pedestal", 192, 48, f, out);
  computeNormals(m);
  return m;
}

Mesh makeBoulder(const std::string& name, dvec3 at, double radius, uint32_t seed) {
  auto f = [=](double u, double v) {
    const double a = 2 * kPi * u, b = kPi * v;
    const dvec3 d(std::sin(b) * std::cos(a), std::cos(b), std::sin(b) * std::sin(a));
    const double bumps = fbm(u, v, 8, 4, seed, 5) - 0.5;
    // Poles have one value for every u: take the noise there at u = 0.
    const double r =
        radius * (1 + 0.35 * (v <= 0 || v >= 1 ? fbm(0, v, 8, 4, seed, 5) - 0.5 : bumps));
    return at + dvec3(d.x * r, d.y * r * 0.75, d.z * r);
  };
  auto out = [](double u, double v) {
    const double a = 2 * kPi * u, b = kPi * v;
    return dvec3(std::sin(b) * std::cos(a), std::cos(b), std::sin(b) * std::sin(a));
  };
  Mesh m = gridSurface(name, 128, 64, f, out);
  computeNormals(m);
  return m;
}

json pbr(const std::string& name, dvec3 color, double metallic, double roughness) {
  return {{"name", name},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {color.x, color.y, color.z, 1.0}},
            {"metallicFactor", metallic},
            {"roughnessFactor", roughness}}}};
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// The set around the asset: floor, wall, columns, pedestal (its top at pedestalTop), boulders
// and a chrome ball, written as one .glb.
struct SetInfo {
  size_t triangles = 0, meshes = 0;
};
SetInfo writeSet(const std::filesystem::path& path, double pedestalTop) {
  Glb set;
  std::vector<std::pair<Mesh, int>> parts;
  const int stone = set.material(pbr("Stone", {0.42, 0.40, 0.37}, 0, 0.85));
  const int plaster = set.material(pbr("Plaster", {0.70, 0.66, 0.58}, 0, 0.9));
  const int marble = set.material(pbr("Column", {0.74, 0.72, 0.68}, 0, 0.55));
  const int lacquer = set.material(pbr("Pedestal", {0.05, 0.05, 0.055}, 0, 0.3));
  const int rock = set.material(pbr("Rock", {0.30, 0.27, 0.23}, 0, 0.8));
  const int chrome = set.material(pbr("Chrome", {0.95, 0.93, 0.90}, 1, 0.08));
  parts.emplace_back(makeFloor(), stone);
  parts.emplace_back(makeWall(), plaster);
  for (int k = 0; k < 5; ++k) {
    const double a = kPi * (200.0 + 35.0 * k) / 180.0;
    parts.emplace_back(makeColumn(dvec3(3.4 * std::cos(a), 0, 3.4 * std::sin(a))), marble);
  }
  parts.emplace_back(makePedestal(0.62, pedestalTop), lacquer);
  parts.emplace_back(makeBoulder("BoulderA", {-2.3, 0.2, 0.9}, 0.42, 301), rock);
  parts.emplace_back(makeBoulder("BoulderB", {-1.7, 0.12, 1.7}, 0.22, 302), rock);
  parts.emplace_back(makeBoulder("BoulderC", {2.5, 0.25, 0.3}, 0.5, 303), rock);
  Mesh ball = gridSurface(
      "ChromeBall", 128, 64,
      [](double u, double v) {
        const double a = 2 * kPi * u, b = kPi * v;
        return dvec3(1.35, 0.32, 1.25) +
               0.32 * dvec3(std::sin(b) * std::cos(a), std::cos(b), std::sin(b) * std::sin(a));
      },
      [](double u, double v) {
        const double a = 2 * kPi * u, b = kPi * v;
        return dvec3(std::sin(b) * std::cos(a), std::cos(b), std::sin(b) * std::sin(a));
      });
  computeNormals(ball);
  parts.emplace_back(std::move(ball), chrome);
  size_t setTriangles = 0;
  for (const auto& [mesh, mat] : parts) {
    set.mesh(mesh, mat);
    setTriangles += mesh.triangleCount();
  }
  set.write(path);
  return {setTriangles, parts.size()};
}

int run(int argc, char** argv) {
  std::filesystem::path outDir;
  int textureSize = 2048;
  std::string env = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/env/sky.hdr";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--texture-size" && i + 1 < argc)
      textureSize = std::atoi(argv[++i]);
    else if (a == "--env" && i + 1 < argc)
      env = argv[++i];
    else if (a == "-h" || a == "--help") {
      std::printf("usage: %s OUT_DIR [--texture-size N (2048)] [--env FILE.hdr]\n", argv[0]);
      return 0;
    } else if (outDir.empty() && !a.empty() && a[0] != '-')
      outDir = a;
    else
      throw std::runtime_error("unexpected argument '" + a + "' (see --help)");
  }
  if (outDir.empty()) throw std::runtime_error("no output folder (see --help)");
  if (textureSize < 16 || textureSize > 8192)
    throw std::runtime_error("--texture-size must be in [16, 8192]");
  std::filesystem::create_directories(outDir);
  const auto start = std::chrono::steady_clock::now();

  // The asset.
  Extent extent;
  Mesh knot = makeKnot(extent);
  // Stand it on the pedestal: its lowest point touches the pedestal's top.
  constexpr double kPedestalTop = 0.5;
  float lowest = INFINITY;
  for (size_t i = 1; i < knot.positions.size(); i += 3)
    lowest = std::min(lowest, knot.positions[i]);
  for (size_t i = 1; i < knot.positions.size(); i += 3)
    knot.positions[i] += float(kPedestalTop - lowest);
  const auto texturesStart = std::chrono::steady_clock::now();
  std::vector<Image8> textures = makeTextures(textureSize, extent);
  const double patternSeconds = seconds(texturesStart);
  encodePngs(textures, textureSize);
  const double pngSeconds = seconds(texturesStart) - patternSeconds;
  Glb asset;
  asset.doc["samplers"] =
      json::array({{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}});
  std::vector<int> tex;
  size_t textureBytes = 0;
  for (const Image8& image : textures) {
    tex.push_back(asset.image(image));
    textureBytes += image.png.size();
  }
  json material = {
      {"name", "KnotPanels"},
      {"pbrMetallicRoughness",
       {{"baseColorTexture", {{"index", tex[0]}}},
        {"metallicFactor", 1.0},
        {"roughnessFactor", 1.0},
        {"metallicRoughnessTexture", {{"index", tex[2]}}}}},
      {"normalTexture", {{"index", tex[1]}, {"scale", 1.0}}},
      {"emissiveTexture", {{"index", tex[3]}}},
      {"emissiveFactor", {1.0, 1.0, 1.0}},
      {"occlusionTexture", {{"index", tex[4]}, {"strength", 1.0}}},
      {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}};
  asset.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  asset.mesh(knot, asset.material(material));
  asset.write(outDir / "asset.glb");

  const SetInfo set = writeSet(outDir / "set.glb", kPedestalTop);

  // The scene.
  json scene = {{"render", {{"width", 1280}, {"height", 720}, {"spp", 64}, {"max_depth", 8}}},
                {"camera", {{"eye", {0.3, 1.5, 4.2}}, {"look_at", {0.0, 1.08, 0.0}}, {"fov", 35}}},
                {"materials", json::object()},
                {"objects",
                 {{{"name", "set"}, {"shape", "mesh"}, {"file", "set.glb"}},
                  {{"name", "asset"}, {"shape", "mesh"}, {"file", "asset.glb"}}}}};
  std::ifstream in(env, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read the environment map " + env);
  writeText(outDir / "sky.hdr", std::string(std::istreambuf_iterator<char>(in), {}));
  scene["environment"] = {{"file", "sky.hdr"}, {"strength", 1}, {"rotation", 0}};
  writeText(outDir / "scene.json", scene.dump(2) + "\n");

  std::printf("asset.glb: %zu triangles, %zu vertices, 5 textures %dx%d (%.1f MB of PNG)\n",
              knot.triangleCount(), knot.vertexCount(), textureSize, textureSize,
              textureBytes / 1e6);
  std::printf("set.glb: %zu triangles in %zu meshes\n", set.triangles, set.meshes);
  std::printf("total: %zu triangles; texture surface %.3f m x %.3f m per repeat\n",
              knot.triangleCount() + set.triangles, extent.s, extent.t);
  std::printf("time: %.2f s (texture patterns %.2f s, PNG encoding %.2f s)\n", seconds(start),
              patternSeconds, pngSeconds);
  std::printf("wrote %s\n", (outDir / "scene.json").string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_make_asset_scene: error: %s\n", e.what());
    return 1;
  }
}
