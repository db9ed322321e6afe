// The sheen layer (KHR_materials_sheen) and anisotropy (KHR_materials_anisotropy) of the Pbr
// material against answers computed independently: the Charlie lobe by hand, its directional
// albedo by a brute-force quadrature over the hemisphere (the table integrates over the half
// vector instead), sampling that draws what evaluation and the pdf say, the albedo scaling that
// keeps a white material under white sheen from reflecting more than it receives, and the
// anisotropic GGX distribution's normalisation and stretch.
#include "scene/materials.h"
#include "core/constants.h"
#include "core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

namespace penumbra {
namespace {

vec3 direction(float cosTheta, float phi) {
  const float s = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

// The integral over the hemisphere of f(wi) cos(wi) for f given as f cos, by the midpoint rule
// on an n x n grid in (cos theta_i, phi): dw = dcos dphi.
template <typename FCos>
double hemisphereIntegral(FCos&& fCos, int n = 600) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const float z = (float(i) + 0.5f) / float(n);
    for (int j = 0; j < n; ++j)
      sum += fCos(direction(z, 2.0f * kPi * (float(j) + 0.5f) / float(n)));
  }
  return sum * 2.0 * kPiD / (double(n) * n);
}

// The white sheen layer's directional albedo at cosO by brute force: D V cos_i over the
// hemisphere.
double bruteForceSheenAlbedo(float cosO, float alpha) {
  const vec3 wo = direction(cosO, 0.0f);
  return hemisphereIntegral([&](vec3 wi) { return double(sheenLobe(wo, wi, alpha)) * wi.z; }, 600);
}

// Draws directions from `b` seen from wo: every sample is non-specular, its pdf is bsdfPdf's
// and its weight f cos / pdf, and the mean weight (the albedo by sampling) matches the
// integral of f cos over the hemisphere (an n x n quadrature).
void expectSamplingMatchesEvaluation(const SurfaceBsdf& b, vec3 wo, Pcg32& rng, int n,
                                     const std::string& label) {
  const double expected = hemisphereIntegral([&](vec3 wi) { return evalBsdfCos(b, wo, wi).x; }, n);
  constexpr int kSamples = 400000;
  double sum = 0;
  for (int i = 0; i < kSamples; ++i) {
    BsdfSample s;
    const glm::vec2 u(rng.nextFloat(), rng.nextFloat());
    if (!sampleBsdf(b, wo, u, rng.nextFloat(), s)) continue;
    ASSERT_FALSE(s.specular) << label;
    const float pdf = bsdfPdf(b, wo, s.wi);
    ASSERT_NEAR(s.pdf, pdf, 1e-4f * pdf) << label;
    ASSERT_NEAR(s.weight.x, evalBsdfCos(b, wo, s.wi).x / pdf, 1e-3f * s.weight.x + 1e-6f) << label;
    sum += s.weight.x;
  }
  EXPECT_NEAR(sum / kSamples, expected, 0.01 * expected) << label;
}

// A Pbr surface facing +z: black and without a specular layer unless `base` says otherwise.
SurfaceBsdf sheenSurface(vec3 sheen, float roughness, vec3 base = vec3(0.0f)) {
  SurfaceBsdf b;
  b.type = Material::Type::Pbr;
  b.color = base;
  b.specular = base == vec3(0.0f) ? 0.0f : 1.0f;
  b.alpha = 0.25f;
  b.diffuseWeight = 1.0f;
  b.sheen = sheen;
  b.sheenAlpha = std::max(roughness * roughness, kMinSheenAlpha);
  b.frame = makeFrame(vec3(0, 0, 1));
  b.geometricNormal = vec3(0, 0, 1);
  return b;
}

TEST(Sheen, LobeIsTheCharlieDistributionTimesNeubeltsVisibility) {
  // wo = wi at 60 degrees from the normal: h = wo, sin^2(theta_h) = 3/4. With alpha = 1/4,
  // D = (2 + 4) (3/4)^2 / (2 pi) = 0.537148 and V = 1 / (4 (1/2 + 1/2 - 1/4)) = 1/3.
  const vec3 w = direction(0.5f, 0.3f);
  EXPECT_NEAR(sheenLobe(w, w, 0.25f), 6.0 * 0.5625 / (2.0 * kPiD) / 3.0, 1e-5);
  // Fibres lying flat reflect nothing straight back along the normal: D(n) = 0.
  EXPECT_EQ(sheenLobe(vec3(0, 0, 1), vec3(0, 0, 1), 0.25f), 0.0f);
  // Nothing below the surface.
  EXPECT_EQ(sheenLobe(w, vec3(0.3f, 0.0f, -0.95f), 0.25f), 0.0f);
  // Through the material: f = sheen D V, times cos(wi).
  const SurfaceBsdf b = sheenSurface(vec3(0.5f, 0.25f, 1.0f), 0.5f);
  const vec3 f = evalBsdfCos(b, w, w);
  EXPECT_NEAR(f.z, sheenLobe(w, w, 0.25f) * 0.5f, 1e-6);
  EXPECT_NEAR(f.x, 0.5f * f.z, 1e-6);
  EXPECT_NEAR(f.y, 0.25f * f.z, 1e-6);
}

TEST(Sheen, AlbedoTableMatchesABruteForceIntegralOverTheHemisphere) {
  for (float roughness : {0.2f, 0.3f, 0.5f, 0.8f, 1.0f}) {
    const float alpha = roughness * roughness;
    for (float cosO : {0.1f, 0.3f, 0.6f, 0.9f, 1.0f}) {
      const double expected = bruteForceSheenAlbedo(cosO, alpha);
      EXPECT_NEAR(sheenAlbedo(cosO, alpha), expected, 0.01 + 0.02 * expected)
          << "roughness " << roughness << ", cos " << cosO;
    }
  }
  // A rough layer reflects a good share of the light towards grazing, little straight on.
  EXPECT_GT(sheenAlbedo(0.2f, 1.0f), 2.0f * sheenAlbedo(1.0f, 1.0f));
}

TEST(Sheen, SamplingDrawsWhatEvaluationAndThePdfSay) {
  // Over a white diffuse base, under a coat: every sample's weight is f cos / pdf with the pdf
  // bsdfPdf gives, and the mean weight (the albedo by sampling) matches the integral of f cos.
  SurfaceBsdf b = sheenSurface(vec3(0.8f, 0.6f, 0.4f), 0.6f, vec3(0.9f));
  b.coat = 0.5f;
  b.coatAlpha = 0.04f;
  Pcg32 rng;
  rng.seedWith(7, 3);
  for (float cosO : {0.15f, 0.5f, 0.95f})
    expectSamplingMatchesEvaluation(b, direction(cosO, 1.0f), rng, 600,
                                    "cos " + std::to_string(cosO));
}

TEST(Sheen, AWhiteMaterialUnderWhiteSheenReflectsNoMoreThanItReceives) {
  // The base keeps min(1 - E(wo), 1 - E(wi)) of itself, so the two together stay within 1
  // (glTF's albedo scaling); without the scaling a white diffuse base under white sheen would
  // reflect 1 + E. The base is Lambertian, without its specular layer: glTF's fresnel_mix of
  // the two reflects up to 7 % more than it receives towards grazing by itself.
  for (float roughness : {0.3f, 0.7f, 1.0f}) {
    SurfaceBsdf b = sheenSurface(vec3(1.0f), roughness, vec3(1.0f));
    b.specular = 0.0f;
    for (float cosO : {0.2f, 0.6f, 1.0f}) {
      const vec3 wo = direction(cosO, 0.0f);
      const double albedo = hemisphereIntegral([&](vec3 wi) { return evalBsdfCos(b, wo, wi).x; });
      EXPECT_LT(albedo, 1.0 + 0.01) << "roughness " << roughness << ", cos " << cosO;
      EXPECT_GT(albedo, 0.8) << "roughness " << roughness << ", cos " << cosO;
    }
  }
}

TEST(Sheen, GlassUnderSheenLetsThroughWhatTheFibresDoNotReflect) {
  // A clear glass part under white sheen: a sample that refracts carries 1 - E(wo) of what it
  // would carry without the layer (times eta^2), and one that draws the sheen is weighted by
  // the mix's f / pdf.
  SurfaceBsdf b = sheenSurface(vec3(1.0f), 0.5f, vec3(1.0f));
  b.diffuseWeight = 0.0f;
  b.dielectricWeight = 1.0f;
  EXPECT_FALSE(b.isSpecular());
  const vec3 wo = direction(0.9f, 0.0f);
  const float e = sheenAlbedo(0.9f, 0.25f);
  Pcg32 rng;
  rng.seedWith(11, 1);
  int refracted = 0;
  for (int i = 0; i < 2000; ++i) {
    BsdfSample s;
    if (!sampleBsdf(b, wo, glm::vec2(rng.nextFloat(), rng.nextFloat()), rng.nextFloat(), s))
      continue;
    if (!s.specular || s.wi.z > 0) continue;
    ++refracted;
    const float chance = std::clamp(e, 0.05f, 0.5f);
    EXPECT_NEAR(s.weight.x, (1.0f - e) / (1.0f - chance) / (1.5f * 1.5f), 1e-4f);
  }
  EXPECT_GT(refracted, 1000);
}

TEST(Anisotropy, TheDistributionProjectsToTheUnitDisk) {
  // The integral of D(h) cos(theta_h) over the hemisphere is 1 for any pair of alphas, and at
  // the normal D is 1 / (pi ax ay).
  for (const auto& [ax, ay] :
       {std::pair{0.3f, 0.3f}, std::pair{0.2f, 0.6f}, std::pair{0.9f, 0.4f}}) {
    const double projected =
        hemisphereIntegral([&](vec3 h) { return double(anisotropicGgxD(h, ax, ay)) * h.z; }, 1500);
    EXPECT_NEAR(projected, 1.0, 0.01) << ax << " x " << ay;
    EXPECT_NEAR(anisotropicGgxD(vec3(0, 0, 1), ax, ay), 1.0 / (kPiD * ax * ay), 1e-4);
  }
}

// A Pbr surface facing +z whose specular lobes have alpha ax along +x and ay along +y.
SurfaceBsdf anisotropicSurface(float ax, float ay, float metallic) {
  SurfaceBsdf b = sheenSurface(vec3(0.0f), 0.5f, vec3(0.9f, 0.7f, 0.5f));
  b.sheen = vec3(0.0f);
  b.conductorWeight = metallic;
  b.diffuseWeight = 1.0f - metallic;
  b.anisotropic = true;
  b.alpha = ax;
  b.alphaY = ay;
  return b;
}

TEST(Anisotropy, SamplingDrawsWhatEvaluationAndThePdfSay) {
  Pcg32 rng;
  rng.seedWith(5, 9);
  for (float metallic : {1.0f, 0.0f}) {
    const SurfaceBsdf b = anisotropicSurface(0.25f, 0.6f, metallic);
    for (float cosO : {0.3f, 0.8f})
      expectSamplingMatchesEvaluation(
          b, direction(cosO, 0.7f), rng, 1000,
          "metallic " + std::to_string(metallic) + ", cos " + std::to_string(cosO));
  }
}

TEST(Anisotropy, TheLobeIsWiderAlongTheRougherAxis) {
  // Seen straight on, a metal rough along x (0.5) and smooth along y (0.1) reflects more light
  // tilted 20 degrees towards x than towards y; turned by 90 degrees, the other way round; with
  // equal alphas, alike.
  const vec3 wo(0, 0, 1);
  const float t = 20.0f * float(kPiD) / 180.0f;
  const vec3 towardsX(std::sin(t), 0, std::cos(t)), towardsY(0, std::sin(t), std::cos(t));
  const SurfaceBsdf alongX = anisotropicSurface(0.5f, 0.1f, 1.0f);
  EXPECT_GT(evalBsdfCos(alongX, wo, towardsX).x, 10 * evalBsdfCos(alongX, wo, towardsY).x);
  const SurfaceBsdf alongY = anisotropicSurface(0.1f, 0.5f, 1.0f);
  EXPECT_GT(evalBsdfCos(alongY, wo, towardsY).x, 10 * evalBsdfCos(alongY, wo, towardsX).x);
  const SurfaceBsdf even = anisotropicSurface(0.3f, 0.3f, 1.0f);
  EXPECT_NEAR(evalBsdfCos(even, wo, towardsX).x, evalBsdfCos(even, wo, towardsY).x, 1e-5f);
}

// A black Pbr surface facing +z without a specular layer, under a smooth coat whose own normal
// is tilted 10 degrees towards +x.
SurfaceBsdf tiltedCoat() {
  SurfaceBsdf b = sheenSurface(vec3(0.0f), 0.5f);
  b.sheen = vec3(0.0f);
  b.coat = 1.0f;
  b.coatAlpha = 0.05f;
  b.coatHasOwnFrame = true;
  b.coatFrame = makeFrame(direction(std::cos(0.1745329f), 0.0f));
  return b;
}

TEST(Coat, ACoatWithItsOwnNormalReflectsAboutIt) {
  // Seen straight on, the coat's mirror direction is 20 degrees towards +x, not the normal.
  const SurfaceBsdf b = tiltedCoat();
  const vec3 wo(0, 0, 1), mirror = direction(std::cos(0.3490659f), 0.0f);
  EXPECT_GT(evalBsdfCos(b, wo, mirror).x, 100 * evalBsdfCos(b, wo, direction(0.999f, 0.0f)).x);
  SurfaceBsdf flat = b;
  flat.coatHasOwnFrame = false;
  EXPECT_LT(evalBsdfCos(flat, wo, mirror).x, 1e-2f * evalBsdfCos(b, wo, mirror).x);
}

TEST(Coat, SamplingInTheCoatsOwnFrameDrawsWhatEvaluationAndThePdfSay) {
  SurfaceBsdf b = tiltedCoat();
  b.color = vec3(0.6f);
  b.specular = 1.0f;
  b.coatAlpha = 0.2f;
  Pcg32 rng;
  rng.seedWith(3, 5);
  for (float cosO : {0.4f, 0.9f})
    expectSamplingMatchesEvaluation(b, direction(cosO, 2.0f), rng, 1000,
                                    "cos " + std::to_string(cosO));
}

// A film far thicker than light's coherence length: the interference terms vanish and the two
// interfaces add incoherently. Straight on, a film of index 1.3 over glass (f0 0.04, index 1.5):
// R12 = (0.3 / 2.3)^2, R23 = (0.2 / 2.8)^2, R = R12 + (1 - R12)^2 R23 / (1 - R12 R23).
TEST(Iridescence, AThickFilmReflectsItsInterfacesIncoherentSum) {
  const double r12 = (0.3 / 2.3) * (0.3 / 2.3), r23 = (0.2 / 2.8) * (0.2 / 2.8);
  const double expected = r12 + (1 - r12) * (1 - r12) * r23 / (1 - r12 * r23);
  const vec3 f = iridescentFresnel(1.3f, 50000.0f, 1.0f, vec3(0.04f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], expected, 1e-5) << c;
  EXPECT_NEAR(expected, 0.02194, 1e-5);
}

// A film of no thickness is no film: straight on, glass reflects its 4 % (the model's Schlick
// interfaces and Gaussian colour matching functions give it within 0.005). A quarter-wave film
// of index sqrt(1.5) is an anti-reflection coating for its wave: at 112.7 nm green (550 nm) is
// cancelled, and what is left is at the ends of the spectrum, more at the blue end (Airy:
// 0.48 % at 450 nm against 0.23 % at 650 nm), far below the bare glass's 4 %. At a grazing
// angle the coating reflects much more again.
TEST(Iridescence, NoFilmIsTheBareSurfaceAndAQuarterWaveFilmCancelsGreen) {
  const float n = std::sqrt(1.5f), quarter = 550.0f / (4.0f * n);
  const vec3 none = iridescentFresnel(n, 0.0f, 1.0f, vec3(0.04f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(none[c], 0.04f, 0.005f) << c;
  const vec3 f = iridescentFresnel(n, quarter, 1.0f, vec3(0.04f));
  EXPECT_LT(f.x + f.y + f.z, 0.25f * 3 * 0.04f) << f.x << " " << f.y << " " << f.z;
  EXPECT_LT(f.y, 0.002f);
  EXPECT_GT(f.z, 2.0f * f.y);
  EXPECT_GT(f.z, f.x);
  const vec3 grazing = iridescentFresnel(n, quarter, 0.1f, vec3(0.04f));
  EXPECT_GT(grazing.x + grazing.y + grazing.z, 10.0f * (f.x + f.y + f.z));
}

// Glass of index 1.5 under a 50 um film of index 1.3 (the incoherent sum above): straight on,
// the reflection carries 2.194 % on average instead of the glass's 4 %, and the refraction the
// rest, compressed by 1 / 1.5^2.
TEST(Iridescence, GlassUnderAFilmReflectsTheFilmsShare) {
  SurfaceBsdf b = sheenSurface(vec3(0.0f), 0.5f, vec3(1.0f));
  b.diffuseWeight = 0.0f;
  b.dielectricWeight = 1.0f;
  b.iridescence = 1.0f;
  b.iridescenceThickness = 50000.0f;
  const double film = 0.021943;
  double reflected = 0, refracted = 0;
  constexpr int kSamples = 100000;
  for (int i = 0; i < kSamples; ++i) {
    BsdfSample s;
    ASSERT_TRUE(sampleBsdf(b, vec3(0, 0, 1), glm::vec2(0.5f), (i + 0.5f) / kSamples, s));
    (s.wi.z > 0 ? reflected : refracted) += s.weight.y;
  }
  EXPECT_NEAR(reflected / kSamples, film, 1e-4);
  EXPECT_NEAR(refracted / kSamples, (1 - film) / 2.25, 1e-4);
  b.iridescence = 0.0f;
  reflected = 0;
  for (int i = 0; i < kSamples; ++i) {
    BsdfSample s;
    ASSERT_TRUE(sampleBsdf(b, vec3(0, 0, 1), glm::vec2(0.5f), (i + 0.5f) / kSamples, s));
    if (s.wi.z > 0) reflected += s.weight.y;
  }
  EXPECT_NEAR(reflected / kSamples, 0.04, 1e-4);
}

// With a film, the Pbr base and the conductor are still sampled as they are evaluated.
TEST(Iridescence, SamplingDrawsWhatEvaluationAndThePdfSay) {
  Pcg32 rng;
  rng.seedWith(7, 3);
  for (float metallic : {1.0f, 0.0f}) {
    SurfaceBsdf b = sheenSurface(vec3(0.0f), 0.5f, vec3(0.9f, 0.7f, 0.5f));
    b.conductorWeight = metallic;
    b.diffuseWeight = 1.0f - metallic;
    b.iridescence = 0.8f;
    b.iridescenceIor = 1.4f;
    b.iridescenceThickness = 300.0f;
    SurfaceBsdf plain = b;
    plain.iridescence = 0.0f;
    EXPECT_NE(evalBsdfCos(b, direction(0.8f, 0.0f), direction(0.8f, 3.14159f)),
              evalBsdfCos(plain, direction(0.8f, 0.0f), direction(0.8f, 3.14159f)));
    expectSamplingMatchesEvaluation(b, direction(0.6f, 0.7f), rng, 1000,
                                    "metallic " + std::to_string(metallic));
  }
}

}  // namespace
}  // namespace penumbra
