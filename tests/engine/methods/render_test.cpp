// Whole-image tests: determinism across thread counts, visible motion blur, and the
// regression of `cornell` against a stored reference by a per-pixel z-test.
#include "methods/render.h"

#include "core/image_io.h"
#include "eval/metrics.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

RenderResult renderCornell(int size, int spp, int threads, uint64_t seed, SamplerKind sampler) {
  Scene scene = loadScene(test::sourcePath("scenes/cornell.json"));
  scene.settings.width = scene.settings.height = size;
  auto prepared = prepareScene(std::move(scene));
  RenderOptions options;
  options.spp = spp;
  options.threads = threads;
  options.seed = seed;
  options.sampler = sampler;
  return renderImage(*prepared, options);
}

TEST(Render, SameSeedGivesTheSameImageWhateverTheThreadCount) {
  for (SamplerKind kind : {SamplerKind::LowDiscrepancy, SamplerKind::Independent}) {
    const RenderResult one = renderCornell(40, 4, 1, 3, kind);
    const RenderResult two = renderCornell(40, 4, 2, 3, kind);
    const RenderResult other = renderCornell(40, 4, 2, 4, kind);
    EXPECT_EQ(one.image.pixels, two.image.pixels);
    EXPECT_EQ(one.rays, two.rays);
    EXPECT_NE(one.image.pixels, other.image.pixels);
  }
}

TEST(Render, CancelStopsEarly) {
  Scene scene = loadScene(test::sourcePath("scenes/cornell.json"));
  auto prepared = prepareScene(std::move(scene));
  std::atomic<bool> cancel{true};
  RenderOptions options;
  options.cancel = &cancel;
  const RenderResult r = renderImage(*prepared, options);
  EXPECT_TRUE(r.cancelled);
  EXPECT_EQ(r.rays, 0u);
}

// Standard deviation of luminance along the middle row of the image.
double rowContrast(const Image& image) {
  double sum = 0, sum2 = 0;
  const int y = image.height / 2;
  for (int x = image.width / 4; x < 3 * image.width / 4; ++x) {
    const double l = luminance(image.at(x, y));
    sum += l;
    sum2 += l * l;
  }
  const double n = image.width / 2;
  return std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
}

TEST(Render, SpinningStripedSphereBlursItsStripes) {
  const char* json = R"({
    "render": {"width": 48, "height": 48, "max_depth": 1},
    "camera": {"eye": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30},
    "background": 1,
    "textures": {"stripes": {"type": "stripes", "colors": [[0.9, 0.9, 0.9], [0.05, 0.05, 0.05]], "scale": [8, 1]}},
    "materials": {"ball": {"type": "diffuse", "albedo": "stripes"}},
    "objects": [{"shape": "sphere", "radius": 1, "material": "ball",
                 "motion": {"rotate": {"axis": [0, 1, 0], "degrees": 360}}}]})";
  auto render = [&](float shutterClose) {
    Scene scene = parseSceneJson(json, "spin.json", ".");
    scene.camera.shutterClose = shutterClose;
    auto prepared = prepareScene(std::move(scene));
    RenderOptions options;
    options.spp = 64;
    return renderImage(*prepared, options).image;
  };
  const double frozen = rowContrast(render(0.0f));
  const double spinning = rowContrast(render(1.0f));
  EXPECT_GT(frozen, 0.2) << "stripes are visible on a frozen sphere";
  EXPECT_LT(spinning, 0.25 * frozen) << "a full turn during the shutter averages the stripes";
}

// Mitsuba-style regression: a per-pixel Welch z-test of the render against a stored
// reference mean and variance (tests/data, made by scripts/make_test_reference.sh), with
// Sidak correction so the whole image fails with probability alpha = 1% by chance; and a
// z-test of the image mean, which catches small global changes that no single pixel shows.
TEST(Render, CornellMatchesTheStoredReference) {
  const Image reference = readImage(test::sourcePath("tests/data/cornell_ref.exr"));
  const Image referenceVariance = readImage(test::sourcePath("tests/data/cornell_ref_var.exr"));
  const RenderResult r = renderCornell(reference.width, 256, 0, 12345, SamplerKind::Independent);
  ASSERT_EQ(r.image.width, reference.width);

  const double alpha = 0.01;
  const double n = double(reference.pixels.size());
  const double pixelAlpha = 1.0 - std::pow(1.0 - alpha, 1.0 / n);
  int failures = 0;
  double diffSum = 0, varSum = 0;
  Image zImage(reference.width, reference.height);
  for (size_t i = 0; i < reference.pixels.size(); ++i) {
    const double d = luminance(r.image.pixels[i]) - luminance(reference.pixels[i]);
    const double v =
        luminance(r.varianceOfMean.pixels[i]) + luminance(referenceVariance.pixels[i]) + 1e-12;
    const double z = d / std::sqrt(v);
    const double p = std::erfc(std::abs(z) / std::sqrt(2.0));
    zImage.pixels[i] = vec3(float(std::abs(z)));
    failures += p < pixelAlpha ? 1 : 0;
    diffSum += d;
    varSum += v;
  }
  const double meanZ = diffSum / std::sqrt(varSum);
  const bool pass = failures == 0 && std::abs(meanZ) < 2.576;  // two-sided 1% for the mean
  if (!pass) {
    writeImage(test::outputPath("cornell_render.exr"), r.image);
    writeImage(test::outputPath("cornell_reference.exr"), reference);
    double maxZ = 0;
    writeImage(test::outputPath("cornell_zscore.png"), falseColor(zImage, 6.0f));
    writeImage(test::outputPath("cornell_relerr.png"),
               falseColor(errorImage(r.image, reference, maxZ), float(maxZ)));
  }
  EXPECT_EQ(failures, 0) << "pixels failing the z-test (images in " << test::outputPath("") << ")";
  EXPECT_LT(std::abs(meanZ), 2.576) << "image mean differs: z = " << meanZ;
}

}  // namespace
}  // namespace penumbra
