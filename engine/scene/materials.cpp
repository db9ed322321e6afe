#include "scene/materials.h"

#include "core/constants.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra {

namespace {

// Cosine-weighted hemisphere direction about +z.
vec3 cosineHemisphere(glm::vec2 u) {
  const glm::vec2 d = sampleUnitDisk(u.x, u.y);
  return vec3(d.x, d.y, std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y)));
}

float ggxD(vec3 h, float alpha) {
  const float cos2 = h.z * h.z;
  if (cos2 <= 0) return 0;
  const float a2 = alpha * alpha;
  const float d = cos2 * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Smith Lambda for GGX.
float ggxLambda(vec3 w, float alpha) {
  const float cos2 = w.z * w.z;
  if (cos2 >= 1.0f) return 0;
  const float tan2 = (1.0f - cos2) / std::max(cos2, 1e-12f);
  return 0.5f * (-1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

float ggxG(vec3 wo, vec3 wi, float alpha) {
  return 1.0f / (1.0f + ggxLambda(wo, alpha) + ggxLambda(wi, alpha));
}

// Smith Lambda for anisotropic GGX: the squared tangent of w scaled along each axis.
float anisotropicGgxLambda(vec3 w, float alphaX, float alphaY) {
  const float cos2 = w.z * w.z;
  const float scaled = alphaX * alphaX * w.x * w.x + alphaY * alphaY * w.y * w.y;
  if (!(scaled > 0)) return 0;
  return 0.5f * (-1.0f + std::sqrt(1.0f + scaled / std::max(cos2, 1e-12f)));
}

// The specular lobes' (conductor, and the dielectric base's layer) D and G, isotropic or not.
float specularD(const SurfaceBsdf& b, vec3 h) {
  return b.anisotropic ? anisotropicGgxD(h, b.alpha, b.alphaY) : ggxD(h, b.alpha);
}

float specularG(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  if (!b.anisotropic) return ggxG(wo, wi, b.alpha);
  return 1.0f / (1.0f + anisotropicGgxLambda(wo, b.alpha, b.alphaY) +
                 anisotropicGgxLambda(wi, b.alpha, b.alphaY));
}

// Schlick's weight of the grazing reflectance, (1 - cos)^5.
float schlickWeight(float cosTheta) {
  const float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f);
  return (m * m) * (m * m) * m;
}

vec3 schlick(vec3 f0, float cosTheta) { return f0 + (vec3(1.0f) - f0) * schlickWeight(cosTheta); }

// A Fresnel reflectance of reflectance f0 at normal incidence with the iridescent film's share
// of it replaced by the film's over f0 (glTF's KHR_materials_iridescence).
vec3 withIridescence(const SurfaceBsdf& b, vec3 fresnel, float cosTheta, vec3 f0) {
  if (!(b.iridescence > 0)) return fresnel;
  return glm::mix(fresnel,
                  iridescentFresnel(b.iridescenceIor, b.iridescenceThickness, cosTheta, f0),
                  b.iridescence);
}

vec3 conductorEval(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  const vec3 h = glm::normalize(wo + wi);
  const float d = specularD(b, h), g = specularG(b, wo, wi), cosTheta = glm::dot(wi, h);
  return withIridescence(b, schlick(b.color, cosTheta), cosTheta, b.color) *
         (d * g / (4.0f * wo.z));
}

float conductorPdf(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  const vec3 h = glm::normalize(wo + wi);
  return specularD(b, h) * h.z / (4.0f * std::abs(glm::dot(wo, h)));
}

// glTF's dielectric base of a Pbr material (the specification's fresnel_mix): the diffuse
// colour under an untinted GGX specular layer of the same roughness, mixed per channel by the
// layer's Fresnel reflectance at the half vector, F = f0 + (f90 - f0)(1 - |wo.h|)^5, where
// f0 = min(((ior - 1)/(ior + 1))^2 specularColor, 1) specular and f90 = specular
// (KHR_materials_specular; 0.04 and 1 without it, at ior 1.5):
// f = (1 - F) color / pi + F D G / (4 |wo.n| |wi.n|). Times cos(wi).
vec3 baseFresnel(const SurfaceBsdf& b, float cosTheta) {
  const float r = (b.ior - 1.0f) / (b.ior + 1.0f);
  const vec3 f0 = glm::min(vec3(r * r) * b.specularColor, vec3(1.0f)) * b.specular;
  return withIridescence(b, f0 + (vec3(b.specular) - f0) * schlickWeight(cosTheta), cosTheta, f0);
}

vec3 baseEval(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  const vec3 h = glm::normalize(wo + wi);
  const vec3 f = baseFresnel(b, glm::dot(wo, h));
  const float specular = specularD(b, h) * specularG(b, wo, wi) / (4.0f * wo.z);
  return (vec3(1.0f) - f) * b.color * (kInvPi * wi.z) + f * specular;
}

// The chance that sampling the base draws its specular layer: its largest Fresnel weight seen
// from wo, at least a quarter so that glossy reflections of the environment are found often.
float baseSpecularChance(const SurfaceBsdf& b, vec3 wo) {
  const vec3 f = baseFresnel(b, wo.z);
  return std::clamp(std::max(f.x, std::max(f.y, f.z)), 0.25f, 0.9f);
}

// glTF's clear coat (fresnel_coat): the material below it weighs 1 - coat Fc and the coat's
// untinted GGX lobe coat Fc, Fc = 0.04 + 0.96 (1 - |wo.h|)^5 (ior 1.5).
float coatFresnel(float cosTheta) { return schlick(vec3(0.04f), cosTheta).x; }

// The chance that sampling draws the coat: its Fresnel weight seen from wo, at least a fifth of
// its weight; 0 without a coat.
float coatChance(const SurfaceBsdf& b, vec3 wo) {
  if (!(b.coat > 0)) return 0.0f;
  return std::clamp(b.coat * coatFresnel(wo.z), 0.2f * b.coat, 0.9f);
}

float coatLobe(const SurfaceBsdf& b, vec3 wo, vec3 wi, vec3 h) {
  return ggxD(h, b.coatAlpha) * ggxG(wo, wi, b.coatAlpha) / (4.0f * wo.z);
}

float coatPdf(const SurfaceBsdf& b, vec3 wo, vec3 h) {
  return ggxD(h, b.coatAlpha) * h.z / (4.0f * std::abs(glm::dot(wo, h)));
}

// wo and wi in the coat's own frame (SurfaceBsdf::coatFrame), for a coat that has one.
struct CoatView {
  vec3 wo, wi;
};

// The coat's lobe, f cos, and its pdf, in its own frame: nothing unless wo and wi lie on one
// side of it (both mirrored to the upper side when below, as evalLocal does).
float coatLobeIn(const SurfaceBsdf& b, CoatView v) {
  if (v.wo.z * v.wi.z <= 0) return 0.0f;
  if (v.wo.z < 0) v.wo.z = -v.wo.z, v.wi.z = -v.wi.z;
  return coatLobe(b, v.wo, v.wi, glm::normalize(v.wo + v.wi));
}

float coatPdfIn(const SurfaceBsdf& b, CoatView v) {
  if (v.wo.z * v.wi.z <= 0) return 0.0f;
  if (v.wo.z < 0) v.wo.z = -v.wo.z, v.wi.z = -v.wi.z;
  return coatPdf(b, v.wo, glm::normalize(v.wo + v.wi));
}

// wo and wi (world) in the coat's own frame, into `view`, when the coat has one; else null (the
// coat lies in the base's frame).
const CoatView* coatViewOf(const SurfaceBsdf& b, vec3 wo, vec3 wi, CoatView& view) {
  if (!b.coatHasOwnFrame) return nullptr;
  view = {b.coatFrame.toLocal(wo), b.coatFrame.toLocal(wi)};
  return &view;
}

float basePdf(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  const float s = baseSpecularChance(b, wo);
  return (1.0f - s) * wi.z * kInvPi + s * conductorPdf(b, wo, wi);
}

float maxOf(vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

// What the sheen layer leaves of the material below it for the directions wo and wi.
float sheenScaling(const SurfaceBsdf& b, float cosO, float cosI) {
  const float m = maxOf(b.sheen);
  const float scaling = std::min(1.0f - m * sheenAlbedo(cosO, b.sheenAlpha),
                                 1.0f - m * sheenAlbedo(cosI, b.sheenAlpha));
  return std::clamp(scaling, 0.0f, 1.0f);
}

// The chance that sampling draws the sheen layer (cosine-weighted): its albedo seen from wo,
// between a twentieth and a half; 0 without one.
float sheenChance(const SurfaceBsdf& b, vec3 wo) {
  if (!b.hasSheen()) return 0.0f;
  return std::clamp(maxOf(b.sheen) * sheenAlbedo(wo.z, b.sheenAlpha), 0.05f, 0.5f);
}

// Local-space (n = +z) helpers. Diffuse and conductor are two-sided: wo below the
// surface is handled by mirroring both directions to the upper side.
vec3 evalLocal(const SurfaceBsdf& b, vec3 wo, vec3 wi, const CoatView* coatView = nullptr) {
  if (wo.z * wi.z <= 0) return vec3(0.0f);  // transmission is never non-specular here
  if (wo.z < 0) {
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  switch (b.type) {
    case Material::Type::Diffuse:
      return b.color * (kInvPi * wi.z);
    case Material::Type::Conductor:
      return conductorEval(b, wo, wi);
    case Material::Type::Pbr: {
      vec3 f(0.0f);
      if (b.diffuseWeight > 0) f += b.diffuseWeight * baseEval(b, wo, wi);
      if (b.conductorWeight > 0) f += b.conductorWeight * conductorEval(b, wo, wi);
      if (b.hasSheen())
        f = f * sheenScaling(b, wo.z, wi.z) + b.sheen * (sheenLobe(wo, wi, b.sheenAlpha) * wi.z);
      if (b.coat > 0) {
        const vec3 h = glm::normalize(wo + wi);
        const float c = b.coat * coatFresnel(glm::dot(wo, h));
        f = (1.0f - c) * f +
            vec3(c * (coatView ? coatLobeIn(b, *coatView) : coatLobe(b, wo, wi, h)));
      }
      return f;
    }
    default:
      return vec3(0.0f);
  }
}

float pdfLocal(const SurfaceBsdf& b, vec3 wo, vec3 wi, const CoatView* coatView = nullptr) {
  if (wo.z * wi.z <= 0) return 0;
  if (wo.z < 0) {
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  switch (b.type) {
    case Material::Type::Diffuse:
      return wi.z * kInvPi;
    case Material::Type::Conductor:
      return conductorPdf(b, wo, wi);
    case Material::Type::Pbr: {
      float pdf = 0;
      if (b.diffuseWeight > 0) pdf += b.diffuseWeight * basePdf(b, wo, wi);
      if (b.conductorWeight > 0) pdf += b.conductorWeight * conductorPdf(b, wo, wi);
      if (b.hasSheen()) {
        const float sheen = sheenChance(b, wo);
        pdf = (1.0f - sheen) * pdf + sheen * wi.z * kInvPi;
      }
      if (b.coat > 0) {
        const float c = coatChance(b, wo);
        pdf = (1.0f - c) * pdf +
              c * (coatView ? coatPdfIn(b, *coatView) : coatPdf(b, wo, glm::normalize(wo + wi)));
      }
      return pdf;
    }
    default:
      return 0;
  }
}

// A GGX half vector drawn from D(h) cos(theta_h) on the side of wo.
vec3 sampleGgxHalfVector(float alpha, glm::vec2 u, float side) {
  const float a2 = alpha * alpha;
  const float cos2 = (1.0f - u.x) / (1.0f + (a2 - 1.0f) * u.x);
  const float cosT = std::sqrt(std::max(0.0f, cos2)), sinT = std::sqrt(std::max(0.0f, 1.0f - cos2));
  const float phi = 2.0f * kPi * u.y;
  return vec3(sinT * std::cos(phi), sinT * std::sin(phi), side * cosT);
}

// A half vector of the specular lobes, drawn from D(h) cos(theta_h) on the side of wo. The
// anisotropic one by stretching: GGX's slopes for alpha 1, (-r cos phi, -r sin phi) with
// r^2 = u / (1 - u), scaled by (alphaX, alphaY), are distributed as the anisotropic D's
// (Heitz 2014, "Understanding the masking-shadowing function").
vec3 sampleSpecularHalfVector(const SurfaceBsdf& b, glm::vec2 u, float side) {
  if (!b.anisotropic) return sampleGgxHalfVector(b.alpha, u, side);
  const float r = std::sqrt(u.x / std::max(1.0f - u.x, 1e-7f));
  const float phi = 2.0f * kPi * u.y;
  const vec3 h(-r * b.alpha * std::cos(phi), -r * b.alphaY * std::sin(phi), 1.0f);
  return glm::normalize(vec3(h.x, h.y, side));
}

// Smooth dielectric: reflection with the Fresnel probability f, refraction otherwise. Under an
// iridescent film (glTF's KHR_materials_iridescence) the film's share of the reflectance
// replaces f, so the reflection carries mix(f, film, share) / f and the refraction what that
// lets through over 1 - f; under total internal reflection nothing changes.
void sampleDielectric(const SurfaceBsdf& b, vec3 wo, float uc, BsdfSample& out) {
  const float f = fresnelDielectric(wo.z, b.ior);
  const bool filmed = b.iridescence > 0 && f > 0.0f && f < 1.0f;
  vec3 film(f);
  if (filmed) {
    const float r = (b.ior - 1.0f) / (b.ior + 1.0f);
    film = withIridescence(b, vec3(f), std::abs(wo.z), vec3(r * r));
  }
  out.specular = true;
  out.pdf = 0;
  if (uc < f) {
    out.wi = b.frame.toWorld(vec3(-wo.x, -wo.y, wo.z));
    out.weight = filmed ? film / f : vec3(1.0f);
    return;
  }
  // Refraction; eta relative to the side wo is on.
  const float side = wo.z > 0 ? 1.0f : -1.0f;
  const float eta = wo.z > 0 ? 1.0f / b.ior : b.ior;  // n_from / n_to
  const float cosI = std::abs(wo.z);
  const float sin2T = eta * eta * (1.0f - cosI * cosI);
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
  const vec3 wi(-eta * wo.x, -eta * wo.y, -side * cosT);
  out.wi = glm::normalize(b.frame.toWorld(wi));
  // Radiance is compressed by (n_from/n_to)^2 when crossing into the denser medium.
  out.weight = vec3(eta * eta);
  if (filmed) out.weight *= (vec3(1.0f) - film) / (1.0f - f);
}
}  // namespace

namespace {

// sheenAlbedo's table: E at cos(theta) = i / (kCount - 1) and sqrt(alpha) = j / (kCount - 1).
struct SheenAlbedoTable {
  static constexpr int kCount = 32;
  std::array<float, kCount * kCount> e{};
};

// E(cosO, alpha) by quadrature over the half vector h drawn from D(h) cos(theta_h), uniform in
// (u, phi) with sin(theta_h) = u^(alpha / (2 alpha + 1)). A sample's weight is f cos_i over the
// pdf of wi, D cos(theta_h) / (4 wo.h): 4 V cos_i (wo.h) / cos(theta_h). u = t^2 (3 - 2 t) with
// t at the midpoints of its strata, which packs them towards both ends: near u = 1 the
// 1 / cos(theta_h) of a grazing wo (which grows as (1 - u)^(-1/2)) is integrated smoothly, and
// near u = 0 lie the steep half vectors that alone reflect a wo near the normal. phi over
// [0, pi] (wo lies in the xz plane).
float sheenAlbedoByQuadrature(float cosO, float alpha) {
  constexpr int kT = 128, kPhi = 32;
  const vec3 wo(std::sqrt(std::max(0.0f, 1.0f - cosO * cosO)), 0.0f, cosO);
  const float exponent = alpha / (2.0f * alpha + 1.0f);
  static const std::array<glm::vec2, kPhi> phis = [] {
    std::array<glm::vec2, kPhi> p;
    for (int i = 0; i < kPhi; ++i) {
      const float phi = kPi * (float(i) + 0.5f) / kPhi;
      p[size_t(i)] = {std::cos(phi), std::sin(phi)};
    }
    return p;
  }();
  double sum = 0;
  for (int it = 0; it < kT; ++it) {
    const float t = (float(it) + 0.5f) / kT;
    const float u = t * t * (3.0f - 2.0f * t), du = 6.0f * t * (1.0f - t);
    const float sinH = std::pow(u, exponent);
    const float cosH = std::sqrt(std::max(0.0f, 1.0f - sinH * sinH));
    if (!(cosH > 0)) continue;
    for (const glm::vec2 phi : phis) {
      const vec3 h(sinH * phi.x, sinH * phi.y, cosH);
      const float oh = glm::dot(wo, h);
      const float cosI = 2.0f * oh * cosH - cosO;
      if (!(oh > 0) || !(cosI > 0)) continue;
      const float v = 1.0f / (4.0f * (cosI + cosO - cosI * cosO));
      sum += du * (4.0f * v * cosI * oh / cosH);
    }
  }
  return float(sum / (kT * kPhi));
}

const SheenAlbedoTable& sheenAlbedoTable() {
  static const SheenAlbedoTable table = [] {
    SheenAlbedoTable t;
    constexpr int n = SheenAlbedoTable::kCount;
    for (int j = 0; j < n; ++j) {
      const float r = float(j) / (n - 1);
      const float alpha = std::max(r * r, kMinSheenAlpha);
      for (int i = 0; i < n; ++i)
        t.e[size_t(j * n + i)] = sheenAlbedoByQuadrature(float(i) / (n - 1), alpha);
    }
    return t;
  }();
  return table;
}

}  // namespace

float anisotropicGgxD(vec3 h, float alphaX, float alphaY) {
  if (!(h.z > 0)) return 0;
  const float x = h.x / alphaX, y = h.y / alphaY;
  const float d = x * x + y * y + h.z * h.z;
  return 1.0f / (kPi * alphaX * alphaY * d * d);
}

float sheenLobe(vec3 wo, vec3 wi, float alpha) {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0.0f;
  const vec3 h = glm::normalize(wo + wi);
  const float sin2 = std::max(0.0f, 1.0f - h.z * h.z);
  const float d = (2.0f + 1.0f / alpha) * std::pow(sin2, 0.5f / alpha) * (0.5f * kInvPi);
  const float v = 1.0f / (4.0f * (wi.z + wo.z - wi.z * wo.z));
  return d * v;
}

float sheenAlbedo(float cosTheta, float alpha) {
  constexpr int n = SheenAlbedoTable::kCount;
  const SheenAlbedoTable& t = sheenAlbedoTable();
  const float x = std::clamp(std::abs(cosTheta), 0.0f, 1.0f) * (n - 1);
  const float y = std::sqrt(std::clamp(alpha, 0.0f, 1.0f)) * (n - 1);
  const int i = std::min(int(x), n - 2), j = std::min(int(y), n - 2);
  const float fx = x - float(i), fy = y - float(j);
  const float* row0 = &t.e[size_t(j * n + i)];
  const float* row1 = row0 + n;
  return (1 - fy) * ((1 - fx) * row0[0] + fx * row0[1]) + fy * ((1 - fx) * row1[0] + fx * row1[1]);
}

ShadingFrame makeFrame(vec3 n) {
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  ShadingFrame f;
  f.n = n;
  f.s = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  f.t = vec3(b, sign + n.y * n.y * a, -n.y);
  return f;
}

vec3 ShadingFrame::toLocal(vec3 v) const {
  return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)};
}
vec3 ShadingFrame::toWorld(vec3 v) const { return v.x * s + v.y * t + v.z * n; }

namespace {
// The interference term of iridescentFresnel: the CIE 1931 colour matching functions' Fourier
// transforms at the optical path difference opd (nm), with a phase shift per channel, as
// Gaussians (Belcour and Barla 2017, supplemental), turned into linear sRGB and normalised so
// that a flat spectrum is white.
vec3 filmSensitivity(float opd, vec3 shift) {
  const double phase = 2.0 * kPiD * double(opd) * 1e-9;
  const double scale[3] = {5.4856e-13, 4.4201e-13, 5.2481e-13};
  const double position[3] = {1.6810e6, 1.7953e6, 2.2084e6};
  const double variance[3] = {4.3278e9, 9.3046e9, 6.6121e9};
  double xyz[3];
  for (int c = 0; c < 3; ++c)
    xyz[c] = scale[c] * std::sqrt(2.0 * kPiD * variance[c]) *
             std::cos(position[c] * phase + double(shift[c])) *
             std::exp(-phase * phase * variance[c]);
  // x's second lobe.
  xyz[0] += 9.7470e-14 * std::sqrt(2.0 * kPiD * 4.5282e9) *
            std::cos(2.2399e6 * phase + double(shift[0])) * std::exp(-4.5282e9 * phase * phase);
  for (double& v : xyz) v /= 1.0685e-7;
  // XYZ to linear sRGB (D65).
  return vec3(float(3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2]),
              float(-0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2]),
              float(0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2]));
}
}  // namespace

vec3 iridescentFresnel(float filmIor, float thickness, float cosTheta, vec3 f0) {
  const float cos1 = std::clamp(cosTheta, 0.0f, 1.0f);
  // Snell's law into the film; beyond the critical angle it reflects everything.
  const float sin2Squared = (1.0f - cos1 * cos1) / (filmIor * filmIor);
  if (sin2Squared >= 1.0f) return vec3(1.0f);
  const float cos2 = std::sqrt(1.0f - sin2Squared);
  // Air to film: reflectance R12 (= R21), transmittance T121 there and back, and the phase
  // shift of a reflection off the denser side.
  const float r0 = (filmIor - 1.0f) / (filmIor + 1.0f);
  const float r12 = schlick(vec3(r0 * r0), cos1).x;
  const float t121 = 1.0f - r12;
  const float phi21 = filmIor < 1.0f ? 0.0f : kPi;  // pi - phi12
  // Film to base, the base's index from its f0 (as if from air), per channel.
  vec3 r23, phi23;
  for (int c = 0; c < 3; ++c) {
    const float sqrtF0 = std::sqrt(std::clamp(f0[c], 0.0f, 0.9999f));
    const float baseIor = (1.0f + sqrtF0) / (1.0f - sqrtF0);
    const float r1 = (baseIor - filmIor) / (baseIor + filmIor);
    r23[c] = schlick(vec3(r1 * r1), cos2).x;
    phi23[c] = baseIor < filmIor ? kPi : 0.0f;
  }
  const float opd = 2.0f * filmIor * std::max(thickness, 0.0f) * cos2;
  const vec3 phi = vec3(phi21) + phi23;
  const vec3 r123 = glm::clamp(r12 * r23, vec3(1e-5f), vec3(0.9999f));
  const vec3 rs = t121 * t121 * r23 / (vec3(1.0f) - r123);
  vec3 reflectance = vec3(r12) + rs;  // the incoherent sum (order 0)
  vec3 cm = rs - vec3(t121);
  const vec3 amplitude = glm::sqrt(r123);
  for (int m = 1; m <= 2; ++m) {
    cm *= amplitude;
    reflectance += cm * 2.0f * filmSensitivity(float(m) * opd, float(m) * phi);
  }
  // The two orders and the colour fits overshoot a little (a metal's, seen grazing, by up to
  // 8 %): a reflectance stays within [0, 1].
  return glm::clamp(reflectance, vec3(0.0f), vec3(1.0f));
}

float fresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
  if (cosThetaI < 0) {
    eta = 1.0f / eta;
    cosThetaI = -cosThetaI;
  }
  const float sin2I = 1.0f - cosThetaI * cosThetaI;
  const float sin2T = sin2I / (eta * eta);
  if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
  const float cosT = std::sqrt(1.0f - sin2T);
  const float rPar = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
  const float rPerp = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
  return 0.5f * (rPar * rPar + rPerp * rPerp);
}

vec3 evalBsdfCos(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  // Reject light leaks: reflection must stay on one side of the geometric surface too.
  if (glm::dot(wo, b.geometricNormal) * glm::dot(wi, b.geometricNormal) <= 0) return vec3(0.0f);
  CoatView coat;
  return evalLocal(b, b.frame.toLocal(wo), b.frame.toLocal(wi), coatViewOf(b, wo, wi, coat));
}

float bsdfPdf(const SurfaceBsdf& b, vec3 wo, vec3 wi) {
  CoatView coat;
  return pdfLocal(b, b.frame.toLocal(wo), b.frame.toLocal(wi), coatViewOf(b, wo, wi, coat));
}

bool sampleBsdf(const SurfaceBsdf& b, vec3 woWorld, glm::vec2 u, float uc, BsdfSample& out) {
  const vec3 wo = b.frame.toLocal(woWorld);
  if (wo.z == 0) return false;
  const float side = wo.z > 0 ? 1.0f : -1.0f;
  vec3 wi;
  switch (b.type) {
    case Material::Type::Diffuse:
      wi = cosineHemisphere(u);
      wi.z *= side;
      break;
    case Material::Type::Conductor: {
      // Sample D(h) cos(theta_h), reflect wo about h.
      const vec3 h = sampleSpecularHalfVector(b, u, side);
      wi = 2.0f * glm::dot(wo, h) * h - wo;
      if (wi.z * wo.z <= 0) return false;
      break;
    }
    case Material::Type::Mirror:
      out.wi = b.frame.toWorld(vec3(-wo.x, -wo.y, wo.z));
      out.weight = b.color;
      out.pdf = 0;
      out.specular = true;
      return true;
    case Material::Type::Dielectric:
      sampleDielectric(b, wo, uc, out);
      return true;
    case Material::Type::Pbr: {
      // uc picks the coat or the part, then is stretched back onto [0,1) for the next choice.
      const float coat = coatChance(b, vec3(wo.x, wo.y, std::abs(wo.z)));
      if (coat > 0) {
        if (uc < coat) {
          if (b.coatHasOwnFrame) {
            // Reflected about a microfacet of the coat's own frame, then seen in the base's.
            const vec3 cwo = b.coatFrame.toLocal(woWorld);
            const vec3 h = sampleGgxHalfVector(b.coatAlpha, u, cwo.z > 0 ? 1.0f : -1.0f);
            const vec3 cwi = 2.0f * glm::dot(cwo, h) * h - cwo;
            if (cwi.z * cwo.z <= 0) return false;
            wi = b.frame.toLocal(b.coatFrame.toWorld(cwi));
            break;
          }
          const vec3 h = sampleGgxHalfVector(b.coatAlpha, u, side);
          wi = 2.0f * glm::dot(wo, h) * h - wo;
          if (wi.z * wo.z <= 0) return false;
          break;  // weighted by the mix's f / pdf below
        }
        uc = std::min((uc - coat) / (1.0f - coat), 0.99999994f);
      }
      const float sheen = sheenChance(b, vec3(wo.x, wo.y, std::abs(wo.z)));
      if (sheen > 0) {
        if (uc < sheen) {
          wi = cosineHemisphere(u);
          wi.z *= side;
          break;  // weighted by the mix's f / pdf below
        }
        uc = std::min((uc - sheen) / (1.0f - sheen), 0.99999994f);
      }
      if (uc < b.dielectricWeight) {
        sampleDielectric(b, wo, uc / b.dielectricWeight, out);
        // Transmission is tinted by the base colour (glTF's KHR_materials_transmission).
        if (glm::dot(out.wi, b.frame.n) * wo.z < 0) out.weight *= b.color;
        // Under a coat, glass gets what the coat lets through, over the chance of not drawing it.
        if (coat > 0) out.weight *= (1.0f - b.coat * coatFresnel(std::abs(wo.z))) / (1.0f - coat);
        // Under sheen, what the fibres do not reflect, over the chance of not drawing them.
        if (sheen > 0)
          out.weight *= sheenScaling(b, std::abs(wo.z), std::abs(wo.z)) / (1.0f - sheen);
        return true;
      }
      const float rest = b.diffuseWeight + b.conductorWeight;
      if (!(rest > 0)) return false;
      const float v = std::min((uc - b.dielectricWeight) / rest, 0.99999994f);
      // Within the base, v stretched again picks its specular layer or its diffuse part.
      const float conductor = b.conductorWeight / rest;
      const bool glossy =
          v < conductor || (v - conductor) / (1.0f - conductor) <
                               baseSpecularChance(b, vec3(wo.x, wo.y, std::abs(wo.z)));
      if (glossy) {
        const vec3 h = sampleSpecularHalfVector(b, u, side);
        wi = 2.0f * glm::dot(wo, h) * h - wo;
        if (wi.z * wo.z <= 0) return false;
      } else {
        wi = cosineHemisphere(u);
        wi.z *= side;
      }
      break;  // weighted by the mix's f / pdf below: one-sample MIS over the parts
    }
  }
  out.wi = b.frame.toWorld(wi);
  CoatView coat;
  const CoatView* coatView = coatViewOf(b, woWorld, out.wi, coat);
  const vec3 f = evalLocal(b, wo, wi, coatView);
  const float pdf = pdfLocal(b, wo, wi, coatView);
  if (!(pdf > 0)) return false;
  if (glm::dot(woWorld, b.geometricNormal) * glm::dot(out.wi, b.geometricNormal) <= 0) return false;
  out.weight = f / pdf;
  out.pdf = pdf;
  out.specular = false;
  return true;
}

}  // namespace penumbra
