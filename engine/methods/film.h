// The film: what every pixel accumulates from its samples, for the image, the variance of
// its mean, the allocation of the next samples and a consistent reconstruction
// (RECONSTRUCTION.md §1):
//  - the running mean and squared deviations of the radiance (Welford, in sample order, in
//    double: the LD image is exactly this mean, as before the film existed);
//  - two half buffers: the samples alternate between A and B by their order in the pixel,
//    for a second estimate of the variance of the mean and for cross-filtering;
//  - first-hit features (albedo, shading normal, depth) and the directly seen emission
//    (trace/integrator.h's PathFeatures), each as a running mean with its variance.
// Adding a sample consumes no random numbers. One pixel is written by one thread at a time.
#pragma once

#include "core/image.h"
#include "core/large_pages.h"
#include "trace/integrator.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

struct FilmPixel {
  glm::dvec3 mean{0.0}, m2{0.0};  // radiance: Welford's running mean and squared deviations
  uint32_t count = 0, countA = 0;
  vec3 albedo{0.0f}, albedoM2{0.0f};
  vec3 normal{0.0f};
  float normalM2 = 0;  // summed over x, y, z
  float depth = 0, depthM2 = 0;
  vec3 emission{0.0f}, emissionM2{0.0f};  // directly seen emission: running mean, deviations
  // The rest, radiance - emission (what a reconstruction filters): its running mean and
  // deviations, and the sum over half A.
  vec3 residual{0.0f}, residualM2{0.0f};
  glm::dvec3 residualSumA{0.0};

  // Adds one finite sample; samples alternate between the halves, A first.
  void add(vec3 radiance, const PathFeatures& f);
  vec3 variance() const;        // per channel: unbiased sample variance (0 below 2 samples)
  vec3 varianceOfMean() const;  // variance() / count
  // 1 / ((n - 1) n): turns a running sum of squared deviations into a variance of the mean.
  float meanVarianceScale() const {
    return count > 1 ? 1.0f / (float(count - 1) * float(count)) : 0.0f;
  }
  // The halves' means (0 while empty), as FilmBuffers has them: the half's mean of the
  // radiance less the emission, plus the emission's mean over all samples (the emission is not
  // kept per half: 24 bytes a pixel less).
  vec3 meanA() const;
  vec3 meanB() const;
  // (A - B)^2 nA nB / n^2: the two-buffer estimate of the variance of the mean.
  vec3 halfVarianceOfMean() const;
};

// One sub-pixel slice of a pixel (Film::enableSlices): its samples' running mean and squared
// deviations (Welford), and the count and sum of those in its half A (samples alternate
// between the halves within the slice, A first).
struct FilmSlice {
  glm::dvec3 mean{0.0}, sumA{0.0};
  vec3 m2{0.0f};
  uint32_t count = 0, countA = 0;
};

// What a reconstruction reads, one entry per pixel: the film's means and variances of the
// mean. `variance` is that of the part a filter smooths (radiance - emission), the emission's
// own is apart; the halves are the filtered part's halves plus the whole emission mean (so
// that half - emission is the half's filtered part). Depth is divided by the image's mean
// depth, so that feature weights do not depend on the scene's units.
struct FilmBuffers {
  // Which of them Film::buffers fills (the others stay empty): the radiance's (mean, variance
  // and halves), the features' means (emission, albedo, normal, depth), the features' variances
  // of the mean, the emission's.
  enum Parts : unsigned {
    kRadiance = 1u,
    kFeatures = 2u,
    kFeatureVariances = 4u,
    kEmissionVariance = 8u,
    kAll = 15u,
    kMean = 16u  // the mean alone (kRadiance has it too)
  };
  int width = 0, height = 0;
  LargeVector<vec3> mean, variance, halfA, halfB, emission, emissionVariance;
  LargeVector<vec3> albedo, albedoVariance, normal;
  LargeVector<float> normalVariance, depth, depthVariance;
};

// The image's pixels. With slices enabled (a method that samples some sub-pixel slices more
// than others), a pixel's estimate is the stratified one: the mean of its slices' means, each
// slice weighing its area, so that it stays unbiased however unevenly the slices are sampled;
// its variance of the mean is sum_k s_k^2 / (S^4 n_k). Until every slice has a sample the
// plain mean stands in. The features, the emission and (until every slice has a sample in
// each half) the halves stay plain means: they steer the reconstruction, and a filter that
// tends to the identity as samples accumulate returns the stratified estimate.
class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixelCount() const { return pixels_.size(); }
  FilmPixel& operator[](size_t p) { return pixels_[p]; }
  const FilmPixel& operator[](size_t p) const { return pixels_[p]; }

  // S x S slices per pixel (S >= 1), numbered sy * S + sx; every pixel must still be empty.
  void enableSlices(int perSide);
  int slicesPerSide() const { return slicesPerSide_; }  // 0: no slices
  int slicesPerPixel() const { return slicesPerSide_ * slicesPerSide_; }
  const FilmSlice& slice(size_t p, int k) const {
    return slices_[p * size_t(slicesPerPixel()) + size_t(k)];
  }
  // Adds one finite sample to pixel p and, with slices, to its slice `slice`.
  void add(size_t p, vec3 radiance, const PathFeatures& features, int slice = -1);

  // The pixel's estimate and its variance of the mean (per channel): stratified over the
  // slices when every slice has a sample, else the plain mean's (exactly FilmPixel::mean).
  glm::dvec3 estimate(size_t p) const;
  vec3 estimateVarianceOfMean(size_t p) const;
  bool stratified(size_t p) const;

  Image meanImage() const;  // the estimates
  Image varianceOfMeanImage() const;
  FilmBuffers buffers(unsigned parts = FilmBuffers::kAll) const;
  // Rows [firstRow, lastRow) only (clipped to the image; height lastRow - firstRow), their
  // depths multiplied by `depthScale` (depthScale() for the same entries as buffers()).
  FilmBuffers buffers(unsigned parts, int firstRow, int lastRow, float depthScale) const;
  // The same into `b`, whose vectors keep their memory: the parts asked for are resized, the
  // others emptied (their capacity kept). A reconstruction that reads the film band by band
  // fills one FilmBuffers again and again, and its pages are not made, faulted and cleared
  // afresh for every band.
  void fillBuffers(FilmBuffers& b, unsigned parts, int firstRow, int lastRow,
                   float depthScale) const;
  // Columns [firstColumn, lastColumn) of those rows only (clipped to the image; width
  // lastColumn - firstColumn): a rectangle of the image.
  void fillBuffers(FilmBuffers& b, unsigned parts, int firstRow, int lastRow, float depthScale,
                   int firstColumn, int lastColumn) const;
  // What FilmBuffers' depths are multiplied by: 1 / the mean depth of the pixels that have one.
  float depthScale() const;
  size_t memoryBytes() const {
    return pixels_.capacity() * sizeof(FilmPixel) + slices_.capacity() * sizeof(FilmSlice);
  }

 private:
  int width_, height_;
  std::vector<FilmPixel, LargePageAllocator<FilmPixel>> pixels_;  // (core/large_pages.h)
  int slicesPerSide_ = 0;
  std::vector<FilmSlice> slices_;

  // Pixel p's radiance buffers (mean, variance, halves) in entry i of b.
  void radianceBuffers(size_t p, FilmBuffers& b, size_t i) const;
  // A pixel with one sample's stand-in variance, from its neighbours' samples.
  vec3 neighbourVariance(size_t p) const;
};

}  // namespace penumbra
