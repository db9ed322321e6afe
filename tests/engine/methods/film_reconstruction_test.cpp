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

// A scene's film with edges in every input: two albedos, a disc nearer the camera with its own
// normal, and a brighter band, each sample with noise; `samples` more per pixel of `region`
// (x0, y0, x1, y1), marked in `changed`.
struct Region {
  int x0, y0, x1, y1;
};
void addSamples(Film& film, int samples, Region region, std::mt19937& rng,
                std::vector<uint8_t>* changed = nullptr) {
  std::normal_distribution<float> noise(0.0f, 0.3f);
  const int w = film.width();
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const size_t p = size_t(y) * size_t(w) + size_t(x);
      const bool disc = (x - 70) * (x - 70) + (y - 40) * (y - 40) < 400;
      for (int i = 0; i < samples; ++i) {
        PathFeatures f;
        f.albedo = x < 50 ? vec3(0.2f, 0.5f, 0.8f) : vec3(0.7f, 0.6f, 0.1f);
        f.normal = disc ? vec3(0.6f, 0.0f, 0.8f) : vec3(0, 0, 1);
        // Each sample's depth within the pixel's footprint: the mean depth moves with more.
        f.depth = (disc ? 1.5f : 3.0f + 0.01f * float(y)) * (1.0f + 0.1f * noise(rng));
        const float light = (y / 12) % 2 ? 1.5f : 0.6f;
        film.add(p, vec3(light + noise(rng), light * 0.8f + noise(rng), 0.4f + noise(rng)), f);
      }
      if (changed) (*changed)[p] = 1;
    }
}

// A 128x96 film of 4 samples a pixel (seeded by `seed`), its whole reconstruction `first`, kept
// with its depth scale, and no pixel changed since.
struct Kept {
  Film film{128, 96};
  std::mt19937 rng;
  recon::DenoiseConfig config;
  recon::DenoiseResult first;
  KeptReconstruction kept;
  std::vector<uint8_t> changed;
  explicit Kept(uint32_t seed) : rng(seed), changed(film.pixelCount(), 0) {
    addSamples(film, 4, {0, 0, 128, 96}, rng);
    const float depthScale = film.depthScale();
    first = reconstructFilm(film, config, depthScale);
    kept = {first.output, first.scale, depthScale};
  }
};

// An update redoes only what a region's new samples can change, and gives the whole
// reconstruction's bits with the kept depth scale: in the image's middle and at its corners, in
// one band and in bands of 7 rows.
TEST(FilmReconstruction, AnUpdateAfterARegionsNewSamplesIsTheWholeReconstruction) {
  struct Case {
    Region region;
    int bandRows;
  };
  for (const auto [region, bandRows] :
       {Case{{60, 30, 67, 36}, 0}, Case{{0, 0, 5, 4}, 0}, Case{{120, 90, 128, 96}, 0},
        Case{{60, 30, 67, 36}, 7}, Case{{120, 90, 128, 96}, 7}}) {
    Kept k(11);
    auto& [film, rng, config, first, kept, changed] = k;
    addSamples(film, 3, region, rng, &changed);
    ASSERT_NE(film.depthScale(), kept.depthScale) << "the depth scale must move for this test";
    ASSERT_TRUE(updateReconstruction(film, config, changed, kept, nullptr, bandRows));
    const recon::DenoiseResult whole = reconstructFilm(film, config, kept.depthScale);
    size_t moved = 0, far = 0;
    for (size_t p = 0; p < film.pixelCount(); ++p) {
      ASSERT_EQ(kept.output.pixels[p], whole.output.pixels[p]) << "pixel " << p;
      ASSERT_EQ(kept.scale[p], whole.scale[p]) << "pixel " << p;
      if (kept.output.pixels[p] != first.output.pixels[p]) {
        ++moved;
        const int x = int(p % 128), y = int(p / 128);
        // Nothing moves beyond the reach (and one) of the region.
        const int reach = recon::reach(config) + 1;
        if (x < region.x0 - reach || x >= region.x1 + reach || y < region.y0 - reach ||
            y >= region.y1 + reach)
          ++far;
      }
    }
    EXPECT_GT(moved, size_t((region.x1 - region.x0) * (region.y1 - region.y0)));
    EXPECT_EQ(far, 0u);
  }
}

// Nothing changed: nothing to do. Changes over most of the image: a whole reconstruction is
// due, and `kept` stays as it was.
TEST(FilmReconstruction, AnUpdateOfNothingOrOfMostOfTheImageLeavesTheKeptPicture) {
  Kept k(12);
  auto& [film, rng, config, first, kept, changed] = k;
  EXPECT_TRUE(updateReconstruction(film, config, changed, kept));
  EXPECT_EQ(kept.output.pixels, first.output.pixels);
  addSamples(film, 1, {10, 10, 100, 80}, rng, &changed);
  EXPECT_FALSE(updateReconstruction(film, config, changed, kept));
  EXPECT_EQ(kept.output.pixels, first.output.pixels);
  EXPECT_EQ(kept.scale, first.scale);
  std::vector<uint8_t> wrongSize(10, 0);
  EXPECT_THROW(updateReconstruction(film, config, wrongSize, kept), std::invalid_argument);
}

// A method's pictures: the first whole, the next updated from it with its depth scale where the
// samples went to one region, and the final one whole with the film's own.
TEST(FilmReconstruction, PicturesAreUpdatedFromTheLastAndTheFinalOneIsWhole) {
  Film film(128, 96);
  std::mt19937 rng(13);
  PictureReconstruction pictures;
  const recon::DenoiseConfig config;
  auto sample = [&](int samples, Region region) {
    for (int y = region.y0; y < region.y1; ++y)
      for (int x = region.x0; x < region.x1; ++x) pictures.changed(size_t(y) * 128 + size_t(x));
    addSamples(film, samples, region, rng);
  };
  sample(4, {0, 0, 128, 96});
  const float firstScale = film.depthScale();
  const recon::DenoiseResult first = pictures.reconstruct(film, config, 4, false);
  EXPECT_EQ(first.output.pixels, reconstructFilm(film, config).output.pixels);
  EXPECT_FALSE(first.mseEstimate.empty());  // made whole
  EXPECT_GE(pictures.memoryBytes(), size_t(14) * film.pixelCount());
  sample(2, {80, 20, 90, 30});
  ASSERT_NE(film.depthScale(), firstScale);
  const recon::DenoiseResult second = pictures.reconstruct(film, config, 4.02, false);
  EXPECT_TRUE(second.mseEstimate.empty());  // updated
  EXPECT_EQ(second.output.pixels, reconstructFilm(film, config, firstScale).output.pixels);
  EXPECT_EQ(second.scale, reconstructFilm(film, config, firstScale).scale);
  EXPECT_NE(second.output.pixels, first.output.pixels);
  sample(2, {20, 60, 26, 66});
  const recon::DenoiseResult last = pictures.reconstruct(film, config, 4.03, true);
  EXPECT_EQ(last.output.pixels, reconstructFilm(film, config).output.pixels);
}

}  // namespace
}  // namespace penumbra
