// The film's per-pixel statistics: the mean is Welford's in sample order (LD's image as it has
// always been), the halves alternate, and the two variance estimates agree with the spread.
#include "methods/film.h"

#include <gtest/gtest.h>

#include <random>

namespace penumbra {
namespace {

TEST(Film, TheMeanIsWelfordsInSampleOrderAndTheHalvesAlternate) {
  FilmPixel px;
  const float values[] = {1.0f, 3.0f, 2.0f, 10.0f, 0.5f};
  glm::dvec3 mean(0.0), m2(0.0);
  int n = 0;
  for (float v : values) {
    px.add(vec3(v), PathFeatures{});
    ++n;
    const glm::dvec3 d = glm::dvec3(vec3(v)) - mean;
    mean += d / double(n);
    m2 += d * (glm::dvec3(vec3(v)) - mean);
  }
  EXPECT_EQ(px.mean, mean);  // bit for bit
  EXPECT_EQ(px.m2, m2);
  EXPECT_EQ(px.count, 5u);
  EXPECT_EQ(px.countA, 3u);                                 // samples 0, 2, 4
  EXPECT_FLOAT_EQ(px.meanA().x, (1.0f + 2.0f + 0.5f) / 3);  // A
  EXPECT_FLOAT_EQ(px.meanB().x, (3.0f + 10.0f) / 2);        // B
  EXPECT_FLOAT_EQ(px.varianceOfMean().x, float(m2.x / (4.0 * 5.0)));
}

TEST(Film, BothVarianceEstimatesMatchTheSpreadOfTheMean) {
  // Many pixels with independent samples of known variance 4: the mean over pixels of each
  // estimate of the variance of the mean is close to 4 / n.
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(1.0f, 2.0f);
  const int n = 16;
  double welford = 0, halves = 0;
  const int pixels = 4000;
  for (int p = 0; p < pixels; ++p) {
    FilmPixel px;
    for (int i = 0; i < n; ++i) px.add(vec3(noise(rng)), PathFeatures{});
    welford += px.varianceOfMean().x;
    halves += px.halfVarianceOfMean().x;
  }
  EXPECT_NEAR(welford / pixels, 4.0 / n, 0.05 * 4.0 / n);
  EXPECT_NEAR(halves / pixels, 4.0 / n, 0.1 * 4.0 / n);  // one degree of freedom: noisier
}

TEST(Film, FeaturesAreRunningMeansWithVariancesAndBrokenOnesAreDropped) {
  Film film(1, 1);
  PathFeatures a, b;
  a.albedo = vec3(0.2f);
  a.normal = vec3(0, 0, 1);
  a.depth = 2;
  a.emission = vec3(1.0f);
  b.albedo = vec3(0.6f);
  b.normal = vec3(0, 1, 0);
  b.depth = 4;
  film[0].add(vec3(1.0f), a);
  film[0].add(vec3(1.0f), b);
  PathFeatures broken = a;
  broken.albedo = vec3(NAN);
  film[0].add(vec3(1.0f), broken);  // the radiance counts, the features are the defaults
  EXPECT_EQ(film[0].count, 3u);
  const FilmBuffers buffers = film.buffers();
  EXPECT_NEAR(buffers.albedo[0].x, (0.2f + 0.6f + 1.0f) / 3, 1e-6f);
  EXPECT_NEAR(buffers.emission[0].x, 1.0f / 3, 1e-6f);  // the broken sample adds none
  EXPECT_NEAR(buffers.depth[0], 1.0f, 1e-6f);           // divided by the image's mean depth
  EXPECT_GT(buffers.albedoVariance[0].x, 0.0f);
  EXPECT_GT(buffers.normalVariance[0], 0.0f);
}

// With slices, a pixel's estimate weighs each slice by its area whatever its count (the
// stratified estimate), its variance is sum_k s_k^2 / (S^4 n_k), and the halves are the
// slices' halves, also weighed by area; until every slice has a sample the plain mean stands.
TEST(Film, WithSlicesThePixelIsTheAreaWeightedMeanOfItsSlices) {
  Film film(1, 1);
  film.enableSlices(2);
  // Slice 0 holds the bright sub-pixel structure and gets most samples.
  const std::vector<std::pair<int, float>> samples = {{0, 8.0f}, {1, 1.0f},  {2, 1.0f}, {0, 10.0f},
                                                      {0, 6.0f}, {0, 12.0f}, {1, 3.0f}, {2, 1.0f}};
  for (size_t i = 0; i < samples.size(); ++i) {
    film.add(0, vec3(samples[i].second), PathFeatures{}, samples[i].first);
    if (i == 2) {
      EXPECT_FALSE(film.stratified(0));  // slice 3 is still empty: the plain mean
      EXPECT_FLOAT_EQ(film.estimate(0).x, (8.0f + 1.0f + 1.0f) / 3.0f);
    }
  }
  film.add(0, vec3(5.0f), PathFeatures{}, 3);
  ASSERT_TRUE(film.stratified(0));
  // Slice means 9, 2, 1, 5: the plain mean (47 / 9) would favour the over-sampled slice 0.
  EXPECT_FLOAT_EQ(film.estimate(0).x, (9.0f + 2.0f + 1.0f + 5.0f) / 4.0f);
  EXPECT_FLOAT_EQ(film.meanImage().pixels[0].x, 17.0f / 4.0f);
  // Per-sample variances: slice 0 {8,10,6,12}: 20/3; slice 1 {1,3}: 2; slice 2 {1,1}: 0;
  // slice 3 has one sample and takes the pixel's pooled variance.
  const FilmPixel& px = film[0];
  const float pooled = px.variance().x;
  const float expected = (20.0f / 3.0f / 4.0f + 2.0f / 2.0f + 0.0f / 2.0f + pooled / 1.0f) / 16.0f;
  EXPECT_NEAR(film.estimateVarianceOfMean(0).x, expected, 1e-5f * expected);
  // Slice 3 has no sample in half B yet: the halves stay plain.
  FilmBuffers b = film.buffers();
  EXPECT_FLOAT_EQ(b.mean[0].x, 17.0f / 4.0f);
  EXPECT_FLOAT_EQ(b.halfA[0].x, px.meanA().x);
  film.add(0, vec3(7.0f), PathFeatures{}, 3);
  b = film.buffers();
  // Halves per slice (A takes each slice's 1st, 3rd, ... sample): A = {8, 6}, {1}, {1}, {5};
  // B = {10, 12}, {3}, {1}, {7}.
  EXPECT_FLOAT_EQ(b.halfA[0].x, (7.0f + 1.0f + 1.0f + 5.0f) / 4.0f);
  EXPECT_FLOAT_EQ(b.halfB[0].x, (11.0f + 3.0f + 1.0f + 7.0f) / 4.0f);
}

// Equal counts in every slice give the plain mean: stratification changes nothing then.
TEST(Film, WithEquallySampledSlicesTheEstimateIsThePlainMean) {
  Film film(1, 1);
  film.enableSlices(2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(0.0f, 4.0f);
  for (int i = 0; i < 32; ++i) film.add(0, vec3(value(rng)), PathFeatures{}, i % 4);
  EXPECT_NEAR(film.estimate(0).x, float(film[0].mean.x), 1e-6f);
}

// A range of rows is those rows of the whole image's buffers, bit for bit.
TEST(Film, BuffersOfARangeOfRowsAreThoseRowsOfTheWhole) {
  Film film(5, 7);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(0.0f, 4.0f);
  for (size_t p = 0; p < film.pixelCount(); ++p) {
    for (int i = 0; i < int(p % 4); ++i) {
      PathFeatures f;
      f.albedo = vec3(value(rng) / 4.0f);
      f.normal = vec3(0, 0, 1);
      f.depth = value(rng) + 1.0f;
      f.emission = vec3(p % 3 == 0 ? value(rng) : 0.0f);
      film.add(p, vec3(value(rng)), f);
    }
  }
  const FilmBuffers whole = film.buffers();
  const FilmBuffers rows = film.buffers(FilmBuffers::kAll, 2, 5, film.depthScale());
  EXPECT_EQ(rows.width, 5);
  EXPECT_EQ(rows.height, 3);
  auto expectRows = [&](const auto& all, const auto& part) {
    ASSERT_EQ(part.size(), size_t(15));
    for (size_t i = 0; i < part.size(); ++i) EXPECT_EQ(part[i], all[10 + i]) << i;
  };
  expectRows(whole.mean, rows.mean);
  expectRows(whole.variance, rows.variance);
  expectRows(whole.halfA, rows.halfA);
  expectRows(whole.halfB, rows.halfB);
  expectRows(whole.emission, rows.emission);
  expectRows(whole.emissionVariance, rows.emissionVariance);
  expectRows(whole.albedo, rows.albedo);
  expectRows(whole.albedoVariance, rows.albedoVariance);
  expectRows(whole.normal, rows.normal);
  expectRows(whole.normalVariance, rows.normalVariance);
  expectRows(whole.depth, rows.depth);
  expectRows(whole.depthVariance, rows.depthVariance);

  // Filled again into the same buffers (as a banded reconstruction does): the same rows, and
  // the parts not asked for are empty, whatever the last fill held.
  FilmBuffers band;
  film.fillBuffers(band, FilmBuffers::kAll, 0, 7, film.depthScale());
  film.fillBuffers(band, FilmBuffers::kMean | FilmBuffers::kFeatures, 2, 5, film.depthScale());
  EXPECT_EQ(band.height, 3);
  expectRows(whole.mean, band.mean);
  expectRows(whole.albedo, band.albedo);
  expectRows(whole.normal, band.normal);
  expectRows(whole.depth, band.depth);
  expectRows(whole.emission, band.emission);
  EXPECT_TRUE(band.variance.empty() && band.halfA.empty() && band.halfB.empty());
  EXPECT_TRUE(band.emissionVariance.empty() && band.albedoVariance.empty());
  EXPECT_TRUE(band.normalVariance.empty() && band.depthVariance.empty());
  film.fillBuffers(band, FilmBuffers::kAll, 2, 5, film.depthScale());
  expectRows(whole.variance, band.variance);
  expectRows(whole.halfB, band.halfB);
  expectRows(whole.depthVariance, band.depthVariance);
}

}  // namespace
}  // namespace penumbra
