// The multidimensional network (methods/bp/mdnet.h) on synthetic images with known answers,
// each a step along a shear between the image and another dimension of the sample:
//  - a soft shadow: a grating of slats between a small area light and a ground plane seen from
//    above, direct light only, albedo 1 (as after demodulation): image and light point;
//  - stripes moving 6 pixels while the shutter is open: image and time;
//  - stripes out of focus, 6 pixels of blur across the lens: image and lens point.
// Fitted on a pixel's 5x5 neighbourhood's samples over (dx, dy, the other dimensions) and
// averaged over the pixel and those dimensions, the network must beat every image-space filter
// of a single width: it learns the step along the shear, which a filter over the image alone
// cannot see.
#include "methods/bp/mdnet.h"
#include "core/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace penumbra {
namespace {

constexpr int kWidth = 16;              // pixels per side
constexpr float kPixel = 1.2f / 32.0f;  // ground units per pixel
constexpr float kX0 = -0.6f;            // the window's corner on the ground
constexpr float kLightSize = 0.25f;     // a square light at height 2
constexpr int kSpp = 16;
constexpr int kRadius = 2;  // the neighbourhood: 5x5 pixels
constexpr float kPi = 3.14159265f;

// Irradiance from the light point (lu, lv) in [0, 1)^2 at ground point (x, z), times the light's
// area, over pi: the integrand whose mean over a pixel and the light is the pixel's value.
float radiance(float x, float z, float lu, float lv) {
  const float lx = (lu - 0.5f) * kLightSize, lz = (lv - 0.5f) * kLightSize;
  const float dx = lx - x, dy = 2.0f, dz = lz - z;
  const float r2 = dx * dx + dy * dy + dz * dz;
  const float cosine = dy / std::sqrt(r2);
  // Slats along z at height 1, 0.11 wide every 0.2 in x.
  const float crossing = (x + 0.5f * dx) * 5.0f;
  const bool blocked = crossing - std::floor(crossing) < 0.55f;
  return blocked ? 0.0f : cosine * cosine / r2 / kPi * kLightSize * kLightSize;
}

// A synthetic image: the value at image point (x, y), in pixels, for the sample's other two
// dimensions (a, b) in [0, 1)^2.
using Synthetic = float (*)(float x, float y, float a, float b);

float softShadow(float x, float y, float lu, float lv) {
  return radiance(kX0 + x * kPixel, kX0 + y * kPixel, lu, lv);
}

// Slanted stripes 5 pixels wide, bright and dark, moving 6 pixels along x while the shutter is
// open (a = the time; b unused).
float movingStripes(float x, float y, float t, float) {
  const float phase = (x - 0.3f * y - 6.0f * t) / 10.0f;
  return phase - std::floor(phase) < 0.5f ? 1.0f : 0.2f;
}

// The same stripes still but out of focus: the lens point (a, b) on a square aperture moves
// the image point by up to 3 pixels each way.
float defocusedStripes(float x, float y, float u, float v) {
  return movingStripes(x + 6.0f * (u - 0.5f), y + 6.0f * (v - 0.5f), 0.0f, 0.0f);
}

struct Sample {
  float sx, sy, lu, lv;  // position in the pixel, the other two dimensions, all in [0, 1)
  float value;
};

// kSpp samples per pixel: the other dimensions 4x4-stratified, the position Latin-hypercube.
std::vector<std::vector<Sample>> traceSamples(Synthetic scene, uint64_t seed) {
  Pcg32 rng(seed, 7);
  std::vector<std::vector<Sample>> pixels(kWidth * kWidth);
  for (int py = 0; py < kWidth; ++py)
    for (int px = 0; px < kWidth; ++px) {
      std::vector<int> rowX(kSpp), rowY(kSpp);
      for (int k = 0; k < kSpp; ++k) rowX[size_t(k)] = rowY[size_t(k)] = k;
      for (int k = kSpp - 1; k > 0; --k) {
        std::swap(rowX[size_t(k)], rowX[rng.nextUint() % uint32_t(k + 1)]);
        std::swap(rowY[size_t(k)], rowY[rng.nextUint() % uint32_t(k + 1)]);
      }
      auto& out = pixels[size_t(py * kWidth + px)];
      for (int k = 0; k < kSpp; ++k) {
        Sample s;
        s.lu = (float(k % 4) + rng.nextFloat()) / 4.0f;
        s.lv = (float(k / 4) + rng.nextFloat()) / 4.0f;
        s.sx = (float(rowX[size_t(k)]) + rng.nextFloat()) / kSpp;
        s.sy = (float(rowY[size_t(k)]) + rng.nextFloat()) / kSpp;
        s.value = scene(float(px) + s.sx, float(py) + s.sy, s.lu, s.lv);
        out.push_back(s);
      }
    }
  return pixels;
}

// The pixels' values by a 16x16 midpoint rule over the pixel times 8x8 over the other two
// dimensions.
std::vector<float> reference(Synthetic scene) {
  std::vector<float> ref(kWidth * kWidth);
  for (int py = 0; py < kWidth; ++py)
    for (int px = 0; px < kWidth; ++px) {
      double sum = 0;
      for (int i = 0; i < 256; ++i)
        for (int j = 0; j < 64; ++j)
          sum += scene(float(px) + (float(i % 16) + 0.5f) / 16.0f,
                       float(py) + (float(i / 16) + 0.5f) / 16.0f, (float(j % 8) + 0.5f) / 8.0f,
                       (float(j / 8) + 0.5f) / 8.0f);
      ref[size_t(py * kWidth + px)] = float(sum / (256.0 * 64.0));
    }
  return ref;
}

// The pixels whose neighbourhood lies inside the image, as nearly every pixel of a real image.
bool interior(int x, int y) {
  return x >= kRadius && y >= kRadius && x < kWidth - kRadius && y < kWidth - kRadius;
}

// The mean squared error over the interior pixels.
double mse(const std::vector<float>& image, const std::vector<float>& ref) {
  double sum = 0;
  int count = 0;
  for (int y = 0; y < kWidth; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (!interior(x, y)) continue;
      const size_t p = size_t(y * kWidth + x);
      sum += double(image[p] - ref[p]) * (image[p] - ref[p]);
      ++count;
    }
  return sum / double(count);
}

// A Gaussian filter of the pixel means (clamped at the edges), the image-space filter's stand-in.
std::vector<float> gaussian(const std::vector<float>& image, float sigma) {
  const int r = int(std::ceil(3 * sigma));
  std::vector<float> out(image.size());
  for (int y = 0; y < kWidth; ++y)
    for (int x = 0; x < kWidth; ++x) {
      double sum = 0, weight = 0;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int qx = std::clamp(x + dx, 0, kWidth - 1), qy = std::clamp(y + dy, 0, kWidth - 1);
          const double w = std::exp(-double(dx * dx + dy * dy) / (2.0 * sigma * sigma));
          sum += w * image[size_t(qy * kWidth + qx)];
          weight += w;
        }
      out[size_t(y * kWidth + x)] = float(sum / weight);
    }
  return out;
}

// The interior pixels' network estimates over the first `inputs` of (dx, dy, a, b), fitted with
// or without the pixel's own samples.
std::vector<float> networkEstimate(const std::vector<std::vector<Sample>>& pixels, int inputs,
                                   bool ownSamples = true) {
  mdnet::Config config;
  config.inputs = inputs;
  config.epochs = 300;
  const float lo[] = {-0.5f, -0.5f, -0.5f, -0.5f}, hi[] = {0.5f, 0.5f, 0.5f, 0.5f};
  const std::vector<float> nodes = mdnet::haltonPoints(inputs, 256, lo, hi);
  // The interior pixels' neighbourhoods as one batch, trained in lane groups.
  mdnet::Batch batch;
  std::vector<int> owner;  // batch pixel -> image pixel
  for (int py = 0; py < kWidth; ++py)
    for (int px = 0; px < kWidth; ++px) {
      if (!interior(px, py)) continue;
      for (int dy = -kRadius; dy <= kRadius; ++dy)
        for (int dx = -kRadius; dx <= kRadius; ++dx) {
          const int qx = px + dx, qy = py + dy;
          if (!ownSamples && dx == 0 && dy == 0) continue;
          for (const Sample& s : pixels[size_t(qy * kWidth + qx)]) {
            const float in[] = {float(dx) + s.sx - 0.5f, float(dy) + s.sy - 0.5f, s.lu - 0.5f,
                                s.lv - 0.5f};
            batch.inputs.insert(batch.inputs.end(), in, in + inputs);
            batch.targets.push_back(glm::vec3(s.value));
          }
        }
      batch.offsets.push_back(uint32_t(batch.targets.size()));
      owner.push_back(py * kWidth + px);
    }
  std::vector<mdnet::Net> nets(owner.size());
  std::vector<mdnet::Net*> pointers;
  for (size_t j = 0; j < nets.size(); ++j) {
    mdnet::init(nets[j], config, uint64_t(owner[j]));
    pointers.push_back(&nets[j]);
  }
  mdnet::fitBatch(config, pointers, batch);
  std::vector<float> out(pixels.size());
  for (size_t j = 0; j < nets.size(); ++j)
    out[size_t(owner[j])] = mdnet::average(nets[j], config, nodes).x;
  return out;
}

// Mean squared errors over three independent sets of samples, pooled over the 144 interior
// pixels of each (one set of 64 pixels left the network's ratio to the best filter anywhere
// between 0.2 and 0.55 on the soft shadow).
struct Errors {
  double box = 0, bestFilter = 0, network = 0, imageOnly = 0, neighboursOnly = 0;
};
Errors compare(Synthetic scene, int inputs, bool variants) {
  const std::vector<float> ref = reference(scene);
  Errors e;
  double filter[4] = {0, 0, 0, 0};
  const float sigmas[] = {0.5f, 1.0f, 2.0f, 4.0f};
  for (uint64_t seed : {1, 2, 3}) {
    const auto pixels = traceSamples(scene, seed);
    std::vector<float> box(pixels.size());
    for (size_t p = 0; p < pixels.size(); ++p) {
      double sum = 0;
      for (const Sample& s : pixels[p]) sum += s.value;
      box[p] = float(sum / double(pixels[p].size()));
    }
    e.box += mse(box, ref) / 3;
    for (int k = 0; k < 4; ++k) filter[k] += mse(gaussian(box, sigmas[k]), ref) / 3;
    e.network += mse(networkEstimate(pixels, inputs), ref) / 3;
    if (!variants) continue;
    e.imageOnly += mse(networkEstimate(pixels, 2), ref) / 3;
    e.neighboursOnly += mse(networkEstimate(pixels, inputs, false), ref) / 3;
  }
  e.bestFilter = std::min(e.box, *std::min_element(filter, filter + 4));
  std::printf("box %.3e  best filter %.3e  network %.3e", e.box, e.bestFilter, e.network);
  if (variants)
    std::printf(", on the neighbours' samples only %.3e; over (dx, dy) only %.3e", e.neighboursOnly,
                e.imageOnly);
  std::printf("\n");
  return e;
}

TEST(MdNet, ASoftShadowIsReconstructedAlongTheLightsDimensions) {
  const Errors e = compare(softShadow, 4, true);
  EXPECT_LT(e.network, 0.5 * e.bestFilter) << "better than any filter of one width";
  EXPECT_LT(e.network, 0.5 * e.imageOnly) << "the light's dimensions carry the information";
  // Fitted without the pixel's own samples, the estimate is independent of the pixel's mean
  // (what an unbiased score of it needs) and still better than any filter (0.51x the best
  // one here, against 0.40x with the pixel's own samples).
  EXPECT_LT(e.neighboursOnly, 0.75 * e.bestFilter);
}

TEST(MdNet, MovingStripesAreReconstructedAlongTime) {
  const Errors e = compare(movingStripes, 3, false);
  EXPECT_LT(e.network, 0.5 * e.bestFilter);
}

TEST(MdNet, DefocusedStripesAreReconstructedAlongTheLens) {
  const Errors e = compare(defocusedStripes, 4, false);
  EXPECT_LT(e.network, 0.5 * e.bestFilter);
}

TEST(MdNet, FitsAStepAlongAShearAndAveragesIt) {
  // A step along x - 0.5 t over (x, t) in [-1, 1]^2: its mean over the square is 0.5 (the step
  // line halves it), which a network must give from 400 samples.
  mdnet::Config config;
  config.inputs = 2;
  config.epochs = 300;
  Pcg32 rng(3, 1);
  std::vector<float> x;
  std::vector<glm::vec3> y;
  for (int k = 0; k < 400; ++k) {
    const float a = 2 * rng.nextFloat() - 1, t = 2 * rng.nextFloat() - 1;
    x.insert(x.end(), {a, t});
    y.push_back(glm::vec3(a - 0.5f * t > 0 ? 1.0f : 0.0f, 0.0f, 2.0f));
  }
  mdnet::Net net;
  mdnet::init(net, config, 9);
  const float loss = mdnet::fit(net, config, x, y);
  EXPECT_LT(loss, 0.1f);
  EXPECT_GT(mdnet::predict(net, config, std::vector<float>{0.6f, 0.0f}.data()).x, 0.8f);
  EXPECT_LT(mdnet::predict(net, config, std::vector<float>{-0.6f, 0.0f}.data()).x, 0.2f);
  const float lo[] = {-1, -1}, hi[] = {1, 1};
  const glm::vec3 mean = mdnet::average(net, config, mdnet::haltonPoints(2, 1024, lo, hi));
  EXPECT_NEAR(mean.x, 0.5f, 0.05f);
  EXPECT_NEAR(mean.z, 2.0f, 1e-3f) << "a constant channel stays constant";
  // Warm start: a second fit from these weights starts near the end of the first.
  config.epochs = 1;
  EXPECT_LT(mdnet::fit(net, config, x, y), 0.12f);
}

// Eleven pixels' data (not a multiple of any lane count): steps along different shears of
// (x, t), with different sample counts, one pixel with none.
mdnet::Batch shearedSteps() {
  mdnet::Batch batch;
  Pcg32 rng(21, 4);
  for (int j = 0; j < 11; ++j) {
    const int n = j == 7 ? 0 : 150 + 20 * j;
    const float shear = 0.2f * float(j - 5);
    for (int k = 0; k < n; ++k) {
      const float a = 2 * rng.nextFloat() - 1, t = 2 * rng.nextFloat() - 1;
      batch.inputs.insert(batch.inputs.end(), {a, t});
      batch.targets.push_back(glm::vec3(a - shear * t > 0 ? 1.0f : 0.0f, 0.5f * a, 1.0f + t));
    }
    batch.offsets.push_back(uint32_t(batch.targets.size()));
  }
  return batch;
}

// The networks of the sheared steps: 2 inputs, 150 epochs.
mdnet::Config stepConfig() {
  mdnet::Config config;
  config.inputs = 2;
  config.epochs = 150;
  return config;
}

TEST(MdNet, ABatchTrainsEachPixelAsAloneAndAsTheScalarFit) {
  const mdnet::Config config = stepConfig();
  const mdnet::Batch batch = shearedSteps();
  const int pixels = batch.pixelCount();
  std::vector<mdnet::Net> batched(static_cast<size_t>(pixels)), scalar(static_cast<size_t>(pixels));
  std::vector<mdnet::Net*> pointers;
  for (int j = 0; j < pixels; ++j) {
    mdnet::init(batched[size_t(j)], config, uint64_t(100 + j));
    mdnet::init(scalar[size_t(j)], config, uint64_t(100 + j));
    pointers.push_back(&batched[size_t(j)]);
  }
  const std::vector<float> loss = mdnet::fitBatch(config, pointers, batch);
  const float lo[] = {-1, -1}, hi[] = {1, 1};
  const std::vector<float> nodes = mdnet::haltonPoints(2, 256, lo, hi);
  for (int j = 0; j < pixels; ++j) {
    const uint32_t begin = batch.offsets[size_t(j)], end = batch.offsets[size_t(j) + 1];
    if (begin == end) {
      EXPECT_EQ(batched[size_t(j)].step, 0) << "a pixel without samples is left as it was";
      continue;
    }
    const float scalarLoss =
        mdnet::fit(scalar[size_t(j)], config,
                   std::span<const float>(batch.inputs.data() + 2 * begin, 2 * (end - begin)),
                   std::span<const glm::vec3>(batch.targets.data() + begin, end - begin));
    // The same training up to rounding (a polynomial e^x, fused multiply-adds): the same loss
    // and the same average to well within the estimate's own error.
    EXPECT_NEAR(loss[size_t(j)], scalarLoss, 0.01f + 0.05f * scalarLoss) << j;
    const glm::vec3 a = mdnet::average(batched[size_t(j)], config, nodes);
    const glm::vec3 b = mdnet::average(scalar[size_t(j)], config, nodes);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.01f) << j << " channel " << c;
    EXPECT_EQ(batched[size_t(j)].step, config.epochs);
  }
  // A pixel's result does not depend on the pixels that share its lane group: pixel 3 trained
  // alone (in lane 0, its group otherwise empty) gives the same bits.
  mdnet::Batch alone;
  const uint32_t begin = batch.offsets[3], end = batch.offsets[4];
  alone.inputs.assign(batch.inputs.begin() + 2 * begin, batch.inputs.begin() + 2 * end);
  alone.targets.assign(batch.targets.begin() + begin, batch.targets.begin() + end);
  alone.offsets.push_back(end - begin);
  mdnet::Net single;
  mdnet::init(single, config, 103);
  mdnet::Net* singlePointer = &single;
  mdnet::fitBatch(config, std::span<mdnet::Net* const>(&singlePointer, 1), alone);
  for (int i = 0; i < 2; ++i)
    for (int h = 0; h < config.hidden; ++h) EXPECT_EQ(single.w1[i][h], batched[3].w1[i][h]);
  for (int h = 0; h < config.hidden; ++h)
    for (int o = 0; o < 3; ++o) EXPECT_EQ(single.w2[h][o], batched[3].w2[h][o]);
}

TEST(MdNet, NarrowerKernelsTrainAsTheWidest) {
  // The SSE kernel (4 lanes), which a CPU without AVX2 runs, and the AVX2 one (8) where the
  // widest here is AVX-512, against the widest.
  const mdnet::Config config = stepConfig();
  const mdnet::Batch batch = shearedSteps();
  const int pixels = batch.pixelCount();
  auto train = [&](int lanes, std::vector<mdnet::Net>& nets) {
    nets.assign(static_cast<size_t>(pixels), mdnet::Net{});
    std::vector<mdnet::Net*> pointers;
    for (int j = 0; j < pixels; ++j) {
      mdnet::init(nets[size_t(j)], config, uint64_t(7 * j));
      pointers.push_back(&nets[size_t(j)]);
    }
    return mdnet::fitBatch(config, pointers, batch, lanes);
  };
  std::vector<mdnet::Net> wide, narrow;
  const std::vector<float> wideLoss = train(0, wide);
  const float lo[] = {-1, -1}, hi[] = {1, 1};
  const std::vector<float> nodes = mdnet::haltonPoints(2, 256, lo, hi);
  for (int lanes : {4, 8}) {
    if (lanes >= mdnet::batchLanes()) continue;
    const std::vector<float> loss = train(lanes, narrow);
    for (int j = 0; j < pixels; ++j) {
      EXPECT_NEAR(loss[size_t(j)], wideLoss[size_t(j)], 0.01f + 0.05f * wideLoss[size_t(j)])
          << lanes << " lanes, pixel " << j;
      const glm::vec3 a = mdnet::average(narrow[size_t(j)], config, nodes);
      const glm::vec3 b = mdnet::average(wide[size_t(j)], config, nodes);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.01f) << lanes << " lanes, pixel " << j;
    }
  }
  std::vector<mdnet::Net*> none;
  EXPECT_THROW(mdnet::fitBatch(config, none, mdnet::Batch{}, 3), std::invalid_argument);
}

TEST(MdNet, HaltonPointsFillTheBox) {
  const float lo[] = {0, -1, 2}, hi[] = {1, 1, 3};
  const std::vector<float> p = mdnet::haltonPoints(3, 64, lo, hi);
  ASSERT_EQ(p.size(), 192u);
  double mean[3] = {0, 0, 0};
  for (int k = 0; k < 64; ++k)
    for (int d = 0; d < 3; ++d) {
      const float v = p[size_t(k * 3 + d)];
      EXPECT_GE(v, lo[d]);
      EXPECT_LE(v, hi[d]);
      mean[d] += v / 64.0;
    }
  EXPECT_NEAR(mean[0], 0.5, 0.03);
  EXPECT_NEAR(mean[1], 0.0, 0.06);
  EXPECT_NEAR(mean[2], 2.5, 0.03);
  EXPECT_THROW(mdnet::haltonPoints(9, 4, lo, hi), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
