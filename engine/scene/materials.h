// BSDFs of the material kinds: Lambertian diffuse, rough conductor (GGX microfacets, Smith
// shadowing, Schlick Fresnel), ideal mirror, smooth dielectric, and Pbr: glTF's
// metallic-roughness model, a mix by weight of a conductor, glass and a dielectric base (diffuse
// under an untinted GGX layer, mixed by Fresnel), sampled by picking one part by its weight,
// under an optional sheen layer (Charlie fibres) and an optional clear coat.
// Emission is a property of any material (Material::emission). Directions are in
// world space; wo points away from the surface towards the previous vertex.
#pragma once

#include "scene/scene.h"

namespace penumbra {

struct ShadingFrame {
  vec3 n;     // shading normal
  vec3 s, t;  // tangents completing an orthonormal basis with n
  vec3 toLocal(vec3 v) const;
  vec3 toWorld(vec3 v) const;
};
ShadingFrame makeFrame(vec3 n);

// Material at one surface point with its textures already evaluated.
struct SurfaceBsdf {
  Material::Type type = Material::Type::Diffuse;
  vec3 color = vec3(0.8f);  // diffuse albedo or specular tint
  float alpha = 0.04f;      // GGX alpha (conductor; Pbr's conductor and specular layer)
  // Pbr: glTF's KHR_materials_anisotropy: `alpha` along the frame's s (the anisotropy's
  // direction), alphaY along its t. Only read when anisotropic.
  bool anisotropic = false;
  float alphaY = 0.04f;
  float ior = 1.5f;
  float specular = 1.0f;            // Pbr: the base's specular layer (Material::specular)
  vec3 specularColor = vec3(1.0f);  // and its tint at normal incidence
  float coat = 0.0f;                // Pbr: the clear coat's weight (0: none)
  float coatAlpha = 1e-3f;          // and its GGX alpha
  // Pbr: the coat's own frame (glTF's clearcoatNormalTexture, or the interpolated normal under
  // a normal-mapped base), when coatHasOwnFrame; else the coat lies in `frame`.
  bool coatHasOwnFrame = false;
  ShadingFrame coatFrame;
  vec3 sheen = vec3(0.0f);   // Pbr: the sheen layer's colour (black: none)
  float sheenAlpha = 0.25f;  // and its Charlie alpha, in [kMinSheenAlpha, 1]
  // Pbr: the iridescent film's share of the specular layer's and the conductor's Fresnel
  // reflectance (0: none), its index of refraction and its thickness in nanometres.
  float iridescence = 0.0f, iridescenceIor = 1.3f, iridescenceThickness = 400.0f;
  // Pbr: the parts' weights (sum 1): the dielectric base (diffuse under a specular layer), the
  // conductor, and glass. Evaluation and the pdf cover the base and the conductor (glass is
  // specular).
  float diffuseWeight = 0, conductorWeight = 0, dielectricWeight = 0;
  ShadingFrame frame;
  vec3 geometricNormal;  // unit, the triangle's counter-clockwise normal

  bool isSpecular() const {
    return type == Material::Type::Mirror || type == Material::Type::Dielectric ||
           (type == Material::Type::Pbr && !(diffuseWeight + conductorWeight > 0) && !(coat > 0) &&
            !hasSheen());
  }
  bool hasSheen() const { return sheen.x > 0 || sheen.y > 0 || sheen.z > 0; }
  // Whether sampling draws a number to choose a lobe (reflect or refract, or a Pbr part).
  bool choosesLobe() const {
    return type == Material::Type::Dielectric || type == Material::Type::Pbr;
  }
};

struct BsdfSample {
  vec3 wi;
  vec3 weight;    // f * |cos| / pdf
  float pdf = 0;  // solid angle; 0 for specular lobes
  bool specular = false;
};

// f(wo, wi) * |cos(n, wi)|; zero for specular materials.
vec3 evalBsdfCos(const SurfaceBsdf& bsdf, vec3 wo, vec3 wi);
float bsdfPdf(const SurfaceBsdf& bsdf, vec3 wo, vec3 wi);
// u2 picks the direction, u1 picks between reflection and refraction (and first, for Pbr,
// the part).
bool sampleBsdf(const SurfaceBsdf& bsdf, vec3 wo, glm::vec2 u2, float u1, BsdfSample& out);

// The Fresnel reflectance, in linear sRGB, of a thin film of index filmIor and `thickness`
// nanometres in air over a surface whose reflectance at normal incidence is f0, seen at
// cosTheta from the normal (glTF's KHR_materials_iridescence, after Belcour and Barla 2017, "A
// Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence"): Airy's sum
// of the waves reflected between the film's two interfaces, each interface's reflectance by
// Schlick's approximation and its phase shift pi where light meets a denser medium, integrated
// against the CIE 1931 colour matching functions in Fourier space (Gaussian fits) for the first
// two orders of interference. Far thicker films than light's coherence give the two interfaces'
// incoherent sum R12 + T12^2 R23 / (1 - R12 R23). Clamped to [0, 1].
vec3 iridescentFresnel(float filmIor, float thickness, float cosTheta, vec3 f0);

// The sheen layer (glTF's KHR_materials_sheen): fibres whose normals follow the Charlie
// distribution of Estevez and Kulla 2017, D(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi),
// with alpha = sheenRoughness^2, and the visibility term of Neubelt and Pettineo 2013,
// V = 1 / (4 (cos_i + cos_o - cos_i cos_o)); f = sheen D V. The material below keeps
// min(1 - max(sheen) E(cos_o), 1 - max(sheen) E(cos_i)) of itself, E the white layer's
// directional albedo (glTF's albedo scaling).
inline constexpr float kMinSheenAlpha = 1e-3f;
// D V for unit directions about n = +z on the same side (0 otherwise), alpha in
// [kMinSheenAlpha, 1].
float sheenLobe(vec3 wo, vec3 wi, float alpha);
// E: the directional albedo of a white sheen layer seen at cosTheta (|cos| is used), the
// integral of D V cos_i over the hemisphere; from a table computed on first use by quadrature
// over the half vector, drawn from D cos(theta_h) (sin(theta_h) = u^(alpha / (2 alpha + 1))).
float sheenAlbedo(float cosTheta, float alpha);

// The anisotropic GGX distribution of microfacet normals about n = +z, with alphaX along +x
// and alphaY along +y: D(h) = 1 / (pi ax ay (hx^2 / ax^2 + hy^2 / ay^2 + hz^2)^2).
float anisotropicGgxD(vec3 h, float alphaX, float alphaY);

// Fresnel reflectance of a dielectric interface for cosThetaI (signed: negative means
// arriving from inside) and relative index eta = n_inside / n_outside.
float fresnelDielectric(float cosThetaI, float eta);

}  // namespace penumbra
