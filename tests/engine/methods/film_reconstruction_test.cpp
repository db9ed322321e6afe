// The film's reconstruction at one sample per pixel (the viewer's first round): each pixel's
// variance comes from its neighbours, so the picture is filtered, not its raw noise.
#include "methods/film_reconstruction.h"

#include <gtest/gtest.h>

#include <random>

namespace penumbra {
namespace {

// A flat grey wall (radiance 1 everywhere) seen with one noisy sample per pixel.
Film noisyWall(int size, int samplesPerPixel, uint32_t seed) {
  Film film(size, size);
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(1.0f, 0.5f);
  for (int i = 0; i < samplesPerPixel; ++i)
    for (size_t p = 0; p < film.pixelCount(); ++p) {
      PathFeatures f;
      f.albedo = vec3(0.5f);
      f.normal = vec3(0, 0, 1);
      f.depth = 2.0f;
      film.add(p, vec3(noise(rng)), f);
    }
  return film;
}

double mseAgainstOne(const Image& image) {
  double sum = 0;
  for (const vec3& c : image.pixels) sum += double((c.x - 1) * (c.x - 1));
  return sum / double(image.pixels.size());
}

TEST(FilmReconstruction, OneSamplePerPixelTakesItsVarianceFromItsNeighbours) {
  const Film film = noisyWall(48, 1, 3);
  const FilmBuffers b = film.buffers(FilmBuffers::kRadiance);
  double variance = 0;
  for (size_t p = 0; p < film.pixelCount(); ++p) {
    EXPECT_EQ(b.halfA[p], b.halfB[p]) << p;  // one sample: both halves are it
    variance += b.variance[p].x;
  }
  // The samples' variance is 0.25; a 3x3 neighbourhood's sample variance estimates it.
  EXPECT_NEAR(variance / double(film.pixelCount()), 0.25, 0.025);
}

TEST(FilmReconstruction, TheFirstPictureAtOneSamplePerPixelIsFiltered) {
  const Film film = noisyWall(48, 1, 5);
  const recon::DenoiseResult r = reconstructFilm(film, recon::DenoiseConfig{});
  const double raw = mseAgainstOne(film.meanImage());
  const double filtered = mseAgainstOne(r.output);
  EXPECT_NEAR(raw, 0.25, 0.03);
  // Without a variance the reconstruction kept every pixel as it was (the identity).
  EXPECT_LT(filtered, 0.2 * raw);
}

TEST(FilmReconstruction, TwoSamplesPerPixelUseThePixelsOwnVariance) {
  const Film film = noisyWall(8, 2, 7);
  const FilmBuffers b = film.buffers(FilmBuffers::kRadiance);
  for (size_t p = 0; p < film.pixelCount(); ++p) {
    const FilmPixel& px = film[p];
    EXPECT_EQ(b.variance[p], px.residualM2 * px.meanVarianceScale()) << p;
  }
}

TEST(FilmReconstruction, ALargeImagesFirstPicturesAreReconstructedAtHalfResolution) {
  const recon::DenoiseConfig config;  // coarseReconSpp 4: the whole coarse pass (1 + 1 + 2)
  const Film large(512, 512), small(511, 512);
  EXPECT_TRUE(reconstructsCoarsely(large, config, 1.0, false));
  EXPECT_TRUE(reconstructsCoarsely(large, config, 2.0, false));
  EXPECT_TRUE(reconstructsCoarsely(large, config, 4.0, false));
  EXPECT_FALSE(reconstructsCoarsely(large, config, 4.5, false)) << "past coarseReconSpp";
  EXPECT_FALSE(reconstructsCoarsely(large, config, 1.0, true)) << "a final image is full";
  EXPECT_FALSE(reconstructsCoarsely(small, config, 1.0, false)) << "below kCoarsePixels";
  recon::DenoiseConfig never = config;
  never.coarseReconSpp = 0;
  EXPECT_FALSE(reconstructsCoarsely(large, never, 1.0, false));
}

TEST(FilmReconstruction, AHalfResolutionPictureIsTheCoarseReconstructionOfTheFilm) {
  const Film film = noisyWall(512, 1, 9);
  const recon::DenoiseConfig config;
  const recon::DenoiseResult coarse = reconstructPicture(film, config, 1.0, false);
  const FilmBuffers b = film.buffers(FilmBuffers::kAll);
  recon::DenoiseInput in;
  in.width = in.height = 512;
  in.mean = b.mean, in.variance = b.variance, in.halfA = b.halfA, in.halfB = b.halfB;
  in.emission = b.emission, in.albedo = b.albedo, in.albedoVariance = b.albedoVariance;
  in.normal = b.normal, in.normalVariance = b.normalVariance;
  in.depth = b.depth, in.depthVariance = b.depthVariance;
  const recon::DenoiseResult direct = recon::denoiseCoarse(in, config);
  ASSERT_EQ(coarse.output.pixels.size(), direct.output.pixels.size());
  EXPECT_TRUE(coarse.output.pixels == direct.output.pixels) << "the film's bands, read twice";
  EXPECT_LT(mseAgainstOne(coarse.output), 0.05 * mseAgainstOne(film.meanImage()));
  // The final picture is the full reconstruction.
  const recon::DenoiseResult last = reconstructPicture(film, config, 1.0, true);
  EXPECT_TRUE(last.output.pixels == reconstructFilm(film, config).output.pixels);
  EXPECT_FALSE(last.output.pixels == coarse.output.pixels);
}

}  // namespace
}  // namespace penumbra
