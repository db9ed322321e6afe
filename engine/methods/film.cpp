#include "methods/film.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace penumbra {

void FilmPixel::add(vec3 radiance, const PathFeatures& features) {
  // A finite radiance with broken features still counts (the image must not depend on them).
  const bool usable = isFinite(features.albedo) && isFinite(features.normal) &&
                      std::isfinite(features.depth) && isFinite(features.emission);
  const PathFeatures& f = usable ? features : PathFeatures{};
  const vec3 rest = radiance - f.emission;
  if (count % 2 == 0) {
    sumA += glm::dvec3(radiance);
    residualSumA += glm::dvec3(rest);
    ++countA;
  }
  // Welford's update, in the same operations as LD's accumulation has always used.
  ++count;
  const glm::dvec3 d = glm::dvec3(radiance) - mean;
  mean += d / double(count);
  m2 += d * (glm::dvec3(radiance) - mean);

  const float inv = 1.0f / float(count);
  const vec3 da = f.albedo - albedo;
  albedo += da * inv;
  albedoM2 += da * (f.albedo - albedo);
  const vec3 dn = f.normal - normal;
  normal += dn * inv;
  normalM2 += glm::dot(dn, f.normal - normal);
  const float dd = f.depth - depth;
  depth += dd * inv;
  depthM2 += dd * (f.depth - depth);
  const vec3 de = f.emission - emission;
  emission += de * inv;
  emissionM2 += de * (f.emission - emission);
  const vec3 dr = rest - residual;
  residual += dr * inv;
  residualM2 += dr * (rest - residual);
}

vec3 FilmPixel::variance() const { return count > 1 ? vec3(m2 / double(count - 1)) : vec3(0.0f); }

vec3 FilmPixel::varianceOfMean() const {
  return count > 1 ? vec3(m2 / (double(count - 1) * count)) : vec3(0.0f);
}

vec3 FilmPixel::meanA() const { return countA ? vec3(sumA / double(countA)) : vec3(0.0f); }

vec3 FilmPixel::meanB() const {
  const uint32_t countB = count - countA;
  return countB ? vec3((mean * double(count) - sumA) / double(countB)) : vec3(0.0f);
}

vec3 FilmPixel::halfVarianceOfMean() const {
  const uint32_t countB = count - countA;
  if (countA == 0 || countB == 0) return vec3(0.0f);
  const vec3 d = meanA() - meanB();
  return d * d * (float(countA) * float(countB) / (float(count) * float(count)));
}

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(size_t(width) * size_t(height)) {}

Image Film::meanImage() const {
  Image image(width_, height_);
  for (size_t p = 0; p < pixels_.size(); ++p) image.pixels[p] = vec3(pixels_[p].mean);
  return image;
}

Image Film::varianceOfMeanImage() const {
  Image image(width_, height_);
  for (size_t p = 0; p < pixels_.size(); ++p) image.pixels[p] = pixels_[p].varianceOfMean();
  return image;
}

FilmBuffers Film::buffers() const {
  const size_t n = pixels_.size();
  FilmBuffers b;
  b.width = width_;
  b.height = height_;
  b.mean.resize(n);
  b.variance.resize(n);
  b.halfA.resize(n);
  b.halfB.resize(n);
  b.emission.resize(n);
  b.emissionVariance.resize(n);
  b.albedo.resize(n);
  b.albedoVariance.resize(n);
  b.normal.resize(n);
  b.normalVariance.resize(n);
  b.depth.resize(n);
  b.depthVariance.resize(n);
  double depthSum = 0;
  size_t depthCount = 0;
  for (const FilmPixel& px : pixels_)
    if (px.count > 0 && px.depth > 0) {
      depthSum += px.depth;
      ++depthCount;
    }
  const float depthScale = depthCount && depthSum > 0 ? float(depthCount / depthSum) : 1.0f;
  for (size_t p = 0; p < n; ++p) {
    const FilmPixel& px = pixels_[p];
    // Variances of the means of the features: the sample variance over the count.
    const float perSample = px.meanVarianceScale();
    b.mean[p] = vec3(px.mean);
    b.variance[p] = px.residualM2 * perSample;
    const uint32_t countB = px.count - px.countA;
    const vec3 restA = px.countA ? vec3(px.residualSumA / double(px.countA)) : vec3(0.0f);
    const vec3 restB =
        countB
            ? vec3((glm::dvec3(px.residual) * double(px.count) - px.residualSumA) / double(countB))
            : vec3(0.0f);
    b.halfA[p] = restA + px.emission;
    b.halfB[p] = restB + px.emission;
    b.emission[p] = px.emission;
    b.emissionVariance[p] = px.emissionM2 * perSample;
    b.albedo[p] = px.albedo;
    b.albedoVariance[p] = px.albedoM2 * perSample;
    b.normal[p] = px.normal;
    b.normalVariance[p] = px.normalM2 * perSample;
    b.depth[p] = px.depth * depthScale;
    b.depthVariance[p] = px.depthM2 * perSample * depthScale * depthScale;
  }
  return b;
}

}  // namespace penumbra
