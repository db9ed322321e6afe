// denoiseCoarse (methods/recon/denoise.h): the half-resolution reconstruction of a large
// image's first pictures. Pass 1 averages the input's 2x2 blocks, band by band; the
// half-resolution image is denoised; pass 2 brings its filtered radiance over albedo back to
// each pixel, band by band.
#include "methods/recon/denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra::recon {
namespace {

// The half-resolution input, held whole (a quarter of the image's pixels).
struct HalfImage {
  int width = 0, height = 0;
  std::vector<vec3> mean, variance, halfA, halfB, emission, albedo, albedoVariance, normal;
  std::vector<float> normalVariance, depth, depthVariance;

  DenoiseInput input() const {
    DenoiseInput in;
    in.width = width;
    in.height = height;
    in.mean = mean, in.variance = variance, in.halfA = halfA, in.halfB = halfB;
    in.emission = emission, in.albedo = albedo, in.albedoVariance = albedoVariance;
    in.normal = normal, in.normalVariance = normalVariance;
    in.depth = depth, in.depthVariance = depthVariance;
    return in;
  }
};

template <typename T>
bool finiteAt(std::span<const T> values, size_t p) {
  if (values.empty()) return true;
  if constexpr (std::is_same_v<T, float>)
    return std::isfinite(values[p]);
  else
    return isFinite(values[p]);
}

// Whether every given input of pixel p is finite (the pixel is used).
bool pixelFinite(const DenoiseInput& in, size_t p) {
  return finiteAt(in.mean, p) && finiteAt(in.variance, p) && finiteAt(in.halfA, p) &&
         finiteAt(in.halfB, p) && finiteAt(in.emission, p) && finiteAt(in.albedo, p) &&
         finiteAt(in.albedoVariance, p) && finiteAt(in.normal, p) &&
         finiteAt(in.normalVariance, p) && finiteAt(in.depth, p) && finiteAt(in.depthVariance, p);
}

template <typename T>
void sizeLike(std::vector<T>& out, std::span<const T> given, size_t count) {
  if (!given.empty()) out.assign(count, T(0));
}

void prepare(HalfImage& half, const DenoiseInput& like) {
  const size_t n = size_t(half.width) * size_t(half.height);
  half.mean.assign(n, vec3(0.0f));
  half.variance.assign(n, vec3(0.0f));
  sizeLike(half.halfA, like.halfA, n), sizeLike(half.halfB, like.halfB, n);
  sizeLike(half.emission, like.emission, n), sizeLike(half.albedo, like.albedo, n);
  sizeLike(half.albedoVariance, like.albedoVariance, n), sizeLike(half.normal, like.normal, n);
  sizeLike(half.normalVariance, like.normalVariance, n), sizeLike(half.depth, like.depth, n);
  sizeLike(half.depthVariance, like.depthVariance, n);
}

// Averages the 2x2 blocks of a band (rows [first, first + in.height) of the image, first even)
// into the half image's rows first / 2 on.
void downsampleBand(const DenoiseInput& in, int first, HalfImage& half) {
  const int rows = (in.height + 1) / 2;
  const size_t w = size_t(in.width);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int Y = r.begin(); Y != r.end(); ++Y) {
      for (int X = 0; X < half.width; ++X) {
        const size_t P = size_t(first / 2 + Y) * size_t(half.width) + size_t(X);
        int k = 0;
        vec3 mean(0.0f), variance(0.0f), a(0.0f), b(0.0f), emission(0.0f), albedo(0.0f),
            albedoVariance(0.0f), normal(0.0f);
        float normalVariance = 0.0f, depth = 0.0f, depthVariance = 0.0f;
        for (int j = 0; j < 2; ++j) {
          const int y = 2 * Y + j;
          if (y >= in.height) break;
          for (int i = 0; i < 2; ++i) {
            const int x = 2 * X + i;
            if (x >= in.width) break;
            const size_t p = size_t(y) * w + size_t(x);
            if (!pixelFinite(in, p)) continue;
            ++k;
            mean += in.mean[p];
            variance += glm::clamp(in.variance[p], vec3(0.0f), vec3(kMaxVariance));
            if (!in.halfA.empty()) a += in.halfA[p], b += in.halfB[p];
            if (!in.emission.empty()) emission += in.emission[p];
            if (!in.albedo.empty()) albedo += in.albedo[p];
            if (!in.albedoVariance.empty()) albedoVariance += in.albedoVariance[p];
            if (!in.normal.empty()) normal += in.normal[p];
            if (!in.normalVariance.empty()) normalVariance += in.normalVariance[p];
            if (!in.depth.empty()) depth += in.depth[p];
            if (!in.depthVariance.empty()) depthVariance += in.depthVariance[p];
          }
        }
        if (k == 0) {  // no finite pixel: the block is not used
          half.mean[P] = vec3(std::numeric_limits<float>::quiet_NaN());
          continue;
        }
        // Means of k pixels; the variance of a mean of k independent means is their sum / k^2.
        const float inv = 1.0f / float(k), inv2 = inv * inv;
        half.mean[P] = mean * inv;
        half.variance[P] = glm::min(variance * inv2, vec3(kMaxVariance));
        if (!half.halfA.empty()) half.halfA[P] = a * inv, half.halfB[P] = b * inv;
        if (!half.emission.empty()) half.emission[P] = emission * inv;
        if (!half.albedo.empty()) half.albedo[P] = albedo * inv;
        if (!half.albedoVariance.empty()) half.albedoVariance[P] = albedoVariance * inv2;
        if (!half.normal.empty()) half.normal[P] = normal * inv;
        if (!half.normalVariance.empty()) half.normalVariance[P] = normalVariance * inv2;
        if (!half.depth.empty()) half.depth[P] = depth * inv;
        if (!half.depthVariance.empty()) half.depthVariance[P] = depthVariance * inv2;
      }
    }
  });
}

// The filtered block, as radiance over albedo without its emission (the quantity that is
// interpolated), and whether it may be used.
struct Block {
  vec3 value{0.0f};
  vec3 normal{0.0f};
  float depth = 0.0f;
  bool valid = false;
};

// How alike a pixel's geometry is to a block's: 1 for the same normal and depth, falling
// with the squared normal difference (1 - cos 18 degrees = e^-1 scale) and the relative depth
// difference (5% = e^-1); a small floor keeps every pixel some weight, so that a pixel unlike
// all four blocks is interpolated plainly.
float geometryWeight(vec3 normal, float depth, const Block& block, bool useNormal, bool useDepth) {
  float d2 = 0.0f;
  if (useNormal) {
    const vec3 dn = normal - block.normal;
    d2 += glm::dot(dn, dn) / 0.1f;
  }
  if (useDepth) {
    const float scale = 0.05f * std::max(std::abs(depth), std::abs(block.depth));
    if (scale > 0.0f) {
      const float dd = (depth - block.depth) / scale;
      d2 += dd * dd;
    }
  }
  return std::exp(-std::min(d2, 80.0f)) + 1e-4f;
}

int nearestScale(const DenoiseConfig& config, int radius) {
  // Index + 1 of the bank's radius nearest `radius` (the first of equals).
  int best = 0, bestDistance = std::numeric_limits<int>::max();
  for (size_t i = 0; i < config.radii.size(); ++i) {
    const int d = std::abs(config.radii[i] - radius);
    if (d < bestDistance) best = int(i) + 1, bestDistance = d;
  }
  return best;
}

}  // namespace

DenoiseConfig coarseConfig(const DenoiseConfig& config) {
  DenoiseConfig c = config;
  c.radii.clear();
  for (int r : config.radii) {
    const int h = (r + 1) / 2;
    if (c.radii.empty() || h > c.radii.back()) c.radii.push_back(h);
  }
  c.denseRadius = std::max(1, (config.denseRadius + 1) / 2);
  c.sureSmoothRadius = (config.sureSmoothRadius + 1) / 2;
  // A radius just above the dense one must be even (validate): make it dense too.
  for (int r : c.radii)
    if (r == c.denseRadius + 1 && r % 2 == 1) c.denseRadius = r;
  c.coarseReconSpp = 0;
  return c;
}

DenoiseResult denoiseCoarse(int width, int height, const DenoiseConfig& config, int bandRows,
                            const BandSource& source, const BandSource& upsampleSource,
                            const std::atomic<bool>* cancel) {
  if (const std::string problem = validate(config); !problem.empty())
    throw std::invalid_argument("denoise: " + problem);
  if (width < 1 || height < 1 || bandRows < 1)
    throw std::invalid_argument("denoise: width " + std::to_string(width) + ", height " +
                                std::to_string(height) + " or band rows " +
                                std::to_string(bandRows) + " is < 1");
  bandRows += bandRows % 2;
  const DenoiseConfig half = coarseConfig(config);
  HalfImage image;
  image.width = (width + 1) / 2;
  image.height = (height + 1) / 2;
  bool demodulate = false, useNormal = false, useDepth = false;
  for (int y0 = 0; y0 < height; y0 += bandRows) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return {};
    const int y1 = std::min(height, y0 + bandRows);
    const DenoiseInput in = source(y0, y1);
    if (in.width != width || in.height != y1 - y0 || in.mean.size() != size_t(width) * in.height)
      throw std::invalid_argument("denoise: the band source gave the wrong size for rows " +
                                  std::to_string(y0) + " to " + std::to_string(y1));
    if (y0 == 0) {
      prepare(image, in);
      demodulate = config.demodulate && !in.albedo.empty();
      useNormal = config.useFeatures && !in.normal.empty();
      useDepth = config.useFeatures && !in.depth.empty();
    }
    downsampleBand(in, y0, image);
  }
  // A large half image is filtered in bands too (denoiseInBands: the same result).
  const int halfBand = std::max(64, int((size_t(1) << 18) / size_t(image.width)));
  DenoiseResult filtered = halfBand < image.height
                               ? denoiseInBands(image.input(), half, halfBand, cancel)
                               : denoise(image.input(), half, cancel);
  if (cancel && cancel->load(std::memory_order_relaxed)) return {};

  // The blocks as pass 2 reads them.
  std::vector<Block> blocks(size_t(image.width) * size_t(image.height));
  for (size_t P = 0; P < blocks.size(); ++P) {
    Block& b = blocks[P];
    const vec3 out = filtered.output.pixels[P];
    if (!isFinite(out) || !isFinite(image.mean[P])) continue;
    const vec3 emission = image.emission.empty() ? vec3(0.0f) : image.emission[P];
    const vec3 demod =
        demodulate ? glm::max(image.albedo[P], vec3(0.0f)) + config.albedoEpsilon : vec3(1.0f);
    b.value = (out - emission) / demod;
    b.valid = isFinite(b.value);
    if (useNormal) b.normal = image.normal[P];
    if (useDepth) b.depth = image.depth[P];
  }
  image = HalfImage{};  // only the blocks are read from here on
  // A block's identity averages 2x2 pixels (about radius 1); its radius r covers 2r pixels.
  std::vector<int> blockScale(blocks.size());
  for (size_t P = 0; P < blocks.size(); ++P) {
    const uint8_t s = filtered.scale[P];
    blockScale[P] = nearestScale(config, s == 0 ? 1 : 2 * half.radii[s - 1]);
  }

  DenoiseResult result;
  const size_t count = size_t(width) * size_t(height);
  result.output = Image(width, height);
  result.scale.assign(count, 0);
  result.mseEstimate.assign(count, 0.0f);
  result.varianceRatio.assign(count, 1.0f);
  const int bw = (width + 1) / 2, bh = (height + 1) / 2;
  for (int y0 = 0; y0 < height; y0 += bandRows) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return result;
    const int y1 = std::min(height, y0 + bandRows);
    const DenoiseInput in = upsampleSource(y0, y1);
    if (in.width != width || in.height != y1 - y0 || in.mean.size() != size_t(width) * in.height)
      throw std::invalid_argument("denoise: the upsampling source gave the wrong size for rows " +
                                  std::to_string(y0) + " to " + std::to_string(y1));
    tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y != r.end(); ++y) {
        // Block centres sit at full-resolution coordinates 2 Y + 1: a pixel's (y + 0.5)
        // lies at (y - 0.5) / 2 in block units.
        const float fy = (float(y) - 0.5f) * 0.5f;
        const int Y0 = int(std::floor(fy));
        const float ty = fy - float(Y0);
        for (int x = 0; x < width; ++x) {
          const size_t o = size_t(y) * size_t(width) + size_t(x);
          const size_t i = o - size_t(y0) * size_t(width);
          const size_t own = size_t(y / 2) * size_t(bw) + size_t(x / 2);
          result.scale[o] = uint8_t(blockScale[own]);
          result.mseEstimate[o] = filtered.mseEstimate[own];
          result.varianceRatio[o] = filtered.varianceRatio[own];
          const vec3 mean = in.mean[i];
          const bool finitePixel = isFinite(mean) && finiteAt(in.emission, i) &&
                                   finiteAt(in.albedo, i) && finiteAt(in.normal, i) &&
                                   finiteAt(in.depth, i);
          if (!finitePixel) {
            result.output.pixels[o] = mean;
            result.scale[o] = 0;
            result.mseEstimate[o] = std::numeric_limits<float>::infinity();
            result.varianceRatio[o] = 1.0f;
            continue;
          }
          const vec3 normal = useNormal ? in.normal[i] : vec3(0.0f);
          const float depth = useDepth ? in.depth[i] : 0.0f;
          const float fx = (float(x) - 0.5f) * 0.5f;
          const int X0 = int(std::floor(fx));
          const float tx = fx - float(X0);
          vec3 sum(0.0f);
          float weight = 0.0f;
          for (int j = 0; j < 2; ++j) {
            const int Y = std::clamp(Y0 + j, 0, bh - 1);
            const float wy = j ? ty : 1.0f - ty;
            for (int k = 0; k < 2; ++k) {
              const int X = std::clamp(X0 + k, 0, bw - 1);
              const Block& b = blocks[size_t(Y) * size_t(bw) + size_t(X)];
              if (!b.valid) continue;
              const float w =
                  wy * (k ? tx : 1.0f - tx) * geometryWeight(normal, depth, b, useNormal, useDepth);
              sum += w * b.value;
              weight += w;
            }
          }
          if (!(weight > 0.0f)) {  // no usable block around: the pixel's own mean
            result.output.pixels[o] = mean;
            result.scale[o] = 0;
            result.varianceRatio[o] = 1.0f;
            continue;
          }
          const vec3 emission = in.emission.empty() ? vec3(0.0f) : in.emission[i];
          const vec3 demod =
              demodulate ? glm::max(in.albedo[i], vec3(0.0f)) + config.albedoEpsilon : vec3(1.0f);
          const vec3 out = sum / weight * demod + emission;
          result.output.pixels[o] = isFinite(out) ? out : mean;
        }
      }
    });
  }
  return result;
}

DenoiseResult denoiseCoarse(const DenoiseInput& in, const DenoiseConfig& config,
                            const std::atomic<bool>* cancel) {
  if (in.width < 1 || in.height < 1 || in.mean.size() != size_t(in.width) * size_t(in.height))
    throw std::invalid_argument("denoise: the input's size does not match its mean");
  auto rows = [&](int first, int last) { return rowsOf(in, first, last); };
  return denoiseCoarse(in.width, in.height, config, in.height, rows, rows, cancel);
}

}  // namespace penumbra::recon
