#include "methods/film.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra {

void FilmPixel::add(vec3 radiance, const PathFeatures& features) {
  // A finite radiance with broken features still counts (the image must not depend on them).
  const bool usable = isFinite(features.albedo) && isFinite(features.normal) &&
                      std::isfinite(features.depth) && isFinite(features.emission);
  const PathFeatures& f = usable ? features : PathFeatures{};
  const vec3 rest = radiance - f.emission;
  if (count % 2 == 0) {
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

vec3 FilmPixel::meanA() const {
  return countA ? vec3(residualSumA / double(countA)) + emission : vec3(0.0f);
}

vec3 FilmPixel::meanB() const {
  const uint32_t countB = count - countA;
  return countB ? vec3((glm::dvec3(residual) * double(count) - residualSumA) / double(countB)) +
                      emission
                : vec3(0.0f);
}

vec3 FilmPixel::halfVarianceOfMean() const {
  const uint32_t countB = count - countA;
  if (countA == 0 || countB == 0) return vec3(0.0f);
  const vec3 d = meanA() - meanB();
  return d * d * (float(countA) * float(countB) / (float(count) * float(count)));
}

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(size_t(width) * size_t(height)) {}

void Film::enableSlices(int perSide) {
  slicesPerSide_ = std::max(1, perSide);
  slices_.assign(pixels_.size() * size_t(slicesPerPixel()), FilmSlice{});
}

void Film::add(size_t p, vec3 radiance, const PathFeatures& features, int slice) {
  pixels_[p].add(radiance, features);
  if (slice < 0 || slicesPerSide_ == 0) return;
  FilmSlice& s = slices_[p * size_t(slicesPerPixel()) + size_t(slice)];
  const glm::dvec3 L(radiance);
  if (s.count % 2 == 0) {
    s.sumA += L;
    ++s.countA;
  }
  ++s.count;
  const glm::dvec3 d = L - s.mean;
  s.mean += d / double(s.count);
  s.m2 += vec3(d * (L - s.mean));
}

bool Film::stratified(size_t p) const {
  if (slicesPerSide_ == 0) return false;
  const FilmSlice* s = &slices_[p * size_t(slicesPerPixel())];
  for (int k = 0; k < slicesPerPixel(); ++k)
    if (s[k].count == 0) return false;
  return true;
}

glm::dvec3 Film::estimate(size_t p) const {
  if (!stratified(p)) return pixels_[p].mean;
  const FilmSlice* s = &slices_[p * size_t(slicesPerPixel())];
  glm::dvec3 sum(0.0);
  for (int k = 0; k < slicesPerPixel(); ++k) sum += s[k].mean;
  return sum / double(slicesPerPixel());
}

vec3 Film::estimateVarianceOfMean(size_t p) const {
  const FilmPixel& px = pixels_[p];
  if (!stratified(p)) return px.varianceOfMean();
  // A slice of one sample has no variance of its own: the pixel's pooled per-sample variance
  // stands in for it.
  const vec3 pooled = px.variance();
  const FilmSlice* s = &slices_[p * size_t(slicesPerPixel())];
  vec3 sum(0.0f);
  for (int k = 0; k < slicesPerPixel(); ++k) {
    const vec3 perSample = s[k].count > 1 ? s[k].m2 / float(s[k].count - 1) : pooled;
    sum += perSample / float(s[k].count);
  }
  const float area = 1.0f / float(slicesPerPixel());
  return sum * (area * area);
}

Image Film::meanImage() const {
  Image image(width_, height_);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels_.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t p = r.begin(); p < r.end(); ++p)
                        image.pixels[p] = vec3(estimate(p));
                    });
  return image;
}

Image Film::varianceOfMeanImage() const {
  Image image(width_, height_);
  for (size_t p = 0; p < pixels_.size(); ++p) image.pixels[p] = estimateVarianceOfMean(p);
  return image;
}

FilmBuffers Film::buffers(unsigned parts) const { return buffers(parts, 0, height_, depthScale()); }

FilmBuffers Film::buffers(unsigned parts, int firstRow, int lastRow, float depthScale) const {
  FilmBuffers b;
  fillBuffers(b, parts, firstRow, lastRow, depthScale);
  return b;
}

void Film::fillBuffers(FilmBuffers& b, unsigned parts, int firstRow, int lastRow,
                       float depthScale) const {
  fillBuffers(b, parts, firstRow, lastRow, depthScale, 0, width_);
}

void Film::fillBuffers(FilmBuffers& b, unsigned parts, int firstRow, int lastRow, float depthScale,
                       int firstColumn, int lastColumn) const {
  firstRow = std::clamp(firstRow, 0, height_);
  lastRow = std::clamp(lastRow, firstRow, height_);
  firstColumn = std::clamp(firstColumn, 0, width_);
  lastColumn = std::clamp(lastColumn, firstColumn, width_);
  const size_t columns = size_t(lastColumn - firstColumn);
  const size_t n = size_t(lastRow - firstRow) * columns;
  const bool wholeRows = columns == size_t(width_);
  const size_t first = size_t(firstRow) * size_t(width_);
  const bool radiance = parts & FilmBuffers::kRadiance, features = parts & FilmBuffers::kFeatures,
             featureVariances = parts & FilmBuffers::kFeatureVariances,
             emissionVariance = parts & FilmBuffers::kEmissionVariance;
  b.width = int(columns);
  b.height = lastRow - firstRow;
  const bool meanOnly = !radiance && (parts & FilmBuffers::kMean);
  // Every entry of a part asked for is written below: sizes only (capacity is kept).
  auto size = [n](auto& v, bool wanted) { wanted ? v.resize(n) : v.clear(); };
  size(b.mean, radiance || meanOnly);
  for (LargeVector<vec3>* v : {&b.variance, &b.halfA, &b.halfB}) size(*v, radiance);
  for (LargeVector<vec3>* v : {&b.emission, &b.albedo, &b.normal}) size(*v, features);
  size(b.depth, features);
  size(b.emissionVariance, emissionVariance);
  size(b.albedoVariance, featureVariances);
  size(b.normalVariance, featureVariances);
  size(b.depthVariance, featureVariances);
  // Each entry is its pixel's own: the pixels in parallel.
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
          const size_t p = wholeRows ? first + i
                                     : (size_t(firstRow) + i / columns) * size_t(width_) +
                                           size_t(firstColumn) + i % columns;
          const FilmPixel& px = pixels_[p];
          // Variances of the means of the features: the sample variance over the
          // count.
          const float perSample = px.meanVarianceScale();
          if (radiance)
            radianceBuffers(p, b, i);
          else if (meanOnly)
            b.mean[i] = vec3(estimate(p));
          if (features) {
            b.emission[i] = px.emission;
            b.albedo[i] = px.albedo;
            b.normal[i] = px.normal;
            b.depth[i] = px.depth * depthScale;
          }
          if (emissionVariance) b.emissionVariance[i] = px.emissionM2 * perSample;
          if (featureVariances) {
            b.albedoVariance[i] = px.albedoM2 * perSample;
            b.normalVariance[i] = px.normalM2 * perSample;
            b.depthVariance[i] = px.depthM2 * perSample * depthScale * depthScale;
          }
        }
      });
}

float Film::depthScale() const {
  double depthSum = 0;
  size_t depthCount = 0;
  for (const FilmPixel& px : pixels_)
    if (px.count > 0 && px.depth > 0) {
      depthSum += px.depth;
      ++depthCount;
    }
  return depthCount && depthSum > 0 ? float(depthCount / depthSum) : 1.0f;
}

vec3 Film::neighbourVariance(size_t p) const {
  // The sample variance of the filtered part's estimates over the 3x3 pixels around p that
  // have samples. It counts the signal's change across them too: an over-estimate at edges and
  // in texture, which the features' weights keep the filter from blurring across.
  const int x = int(p % size_t(width_)), y = int(p / size_t(width_));
  glm::dvec3 sum(0.0), sumSq(0.0);
  int n = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qy < 0 || qx >= width_ || qy >= height_) continue;
      const FilmPixel& q = pixels_[size_t(qy) * size_t(width_) + size_t(qx)];
      if (q.count == 0) continue;
      const glm::dvec3 r(q.residual);
      sum += r;
      sumSq += r * r;
      ++n;
    }
  if (n < 2) return vec3(0.0f);
  const glm::dvec3 mean = sum / double(n);
  return vec3(glm::max((sumSq - double(n) * mean * mean) / double(n - 1), glm::dvec3(0.0)));
}

void Film::radianceBuffers(size_t p, FilmBuffers& b, size_t i) const {
  const FilmPixel& px = pixels_[p];
  b.mean[i] = vec3(px.mean);
  b.variance[i] = px.residualM2 * px.meanVarianceScale();
  const uint32_t countB = px.count - px.countA;
  const vec3 restA = px.countA ? vec3(px.residualSumA / double(px.countA)) : vec3(0.0f);
  const vec3 restB =
      countB ? vec3((glm::dvec3(px.residual) * double(px.count) - px.residualSumA) / double(countB))
             : vec3(0.0f);
  b.halfA[i] = restA + px.emission;
  b.halfB[i] = restB + px.emission;
  if (px.count == 1) {
    // One sample (the viewer's first round): no variance of its own and no second half. Its
    // neighbours' samples stand in for the variance, and both halves are the sample, so that
    // the reconstruction filters the first picture instead of showing its noise.
    b.variance[i] = neighbourVariance(p);
    b.halfB[i] = b.halfA[i];
  }
  if (!stratified(p)) return;
  // The stratified estimate and its variance (which here includes the emission's: an
  // over-estimate only where emitters are seen directly), and stratified halves once every
  // slice has samples in both.
  b.mean[i] = vec3(estimate(p));
  b.variance[i] = estimateVarianceOfMean(p);
  const FilmSlice* s = &slices_[p * size_t(slicesPerPixel())];
  glm::dvec3 a(0.0), bb(0.0);
  for (int k = 0; k < slicesPerPixel(); ++k) {
    const uint32_t sliceCountB = s[k].count - s[k].countA;
    if (s[k].countA == 0 || sliceCountB == 0) return;
    a += s[k].sumA / double(s[k].countA);
    bb += (s[k].mean * double(s[k].count) - s[k].sumA) / double(sliceCountB);
  }
  b.halfA[i] = vec3(a / double(slicesPerPixel()));
  b.halfB[i] = vec3(bb / double(slicesPerPixel()));
}

}  // namespace penumbra
