// The bilateral filterbank of ALGORITHM.md §9.
#include "methods/bp/reconstruct.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace penumbra {
namespace {

void requireConsistent(const Image& image) {
  if (image.width < 0 || image.height < 0 ||
      image.pixels.size() != size_t(image.width) * size_t(image.height))
    throw std::invalid_argument("image of " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " holds " +
                                std::to_string(image.pixels.size()) + " pixels");
}

void requireValidAlpha(float alpha, const char* what) {
  // A negative alpha would weight far pixels more than near ones; NaN would poison every
  // weight.
  if (!(alpha >= 0.0f) || std::isinf(alpha))
    throw std::invalid_argument(std::string(what) + ": spatial falloff alpha " +
                                std::to_string(alpha) + " is not a finite value >= 0");
}

void validate(const FilterConfig& config) {
  if (config.radius < 0)
    throw std::invalid_argument("filter radius " + std::to_string(config.radius) + " < 0");
  if (!(config.sigmaC > 0.0f))
    throw std::invalid_argument("range falloff sigmaC " + std::to_string(config.sigmaC) +
                                " is not > 0");
  if (config.alphas.empty()) throw std::invalid_argument("no spatial falloffs (alphas) given");
  // alphaIndex is stored as uint8_t.
  if (config.alphas.size() > 256)
    throw std::invalid_argument("at most 256 spatial falloffs are supported, got " +
                                std::to_string(config.alphas.size()));
  for (float alpha : config.alphas) requireValidAlpha(alpha, "reconstruct");
  if (config.phi.size() != config.alphas.size() - 1)
    throw std::invalid_argument(
        "need alphas.size() - 1 = " + std::to_string(config.alphas.size() - 1) +
        " bias thresholds (phi), got " + std::to_string(config.phi.size()));
  for (size_t i = 0; i < config.phi.size(); ++i) {
    if (std::isnan(config.phi[i]) || (i > 0 && config.phi[i] < config.phi[i - 1]))
      throw std::invalid_argument("bias thresholds (phi) must be ascending numbers");
  }
  if (config.secondPass &&
      (config.secondPassAlpha < 0 || size_t(config.secondPassAlpha) >= config.alphas.size()))
    throw std::invalid_argument("secondPassAlpha " + std::to_string(config.secondPassAlpha) +
                                " is not an index into the " +
                                std::to_string(config.alphas.size()) + " alphas");
}

}  // namespace

int alphaIndexForBias(float bias, std::span<const float> phi) {
  // An unknown error gets the filter that blurs least.
  if (std::isnan(bias)) return int(phi.size());
  int index = 0;
  for (float threshold : phi) index += threshold <= bias ? 1 : 0;
  return index;
}

Image bilateralPass(const Image& image, std::span<const float> alphaOf, const ToneMap& tone,
                    int radius, float sigmaC, const std::atomic<bool>* cancel) {
  requireConsistent(image);
  if (alphaOf.size() != image.pixels.size())
    throw std::invalid_argument("bilateralPass: " + std::to_string(alphaOf.size()) +
                                " alphas for " + std::to_string(image.pixels.size()) + " pixels");
  if (radius < 0) throw std::invalid_argument("bilateralPass: radius < 0");
  if (!(sigmaC > 0.0f)) throw std::invalid_argument("bilateralPass: sigmaC is not > 0");
  for (float alpha : alphaOf) requireValidAlpha(alpha, "bilateralPass");

  const int width = image.width, height = image.height;
  const size_t count = image.pixels.size();

  // The range term compares tone-mapped colours; mapping once per pass instead of once per
  // tap saves (2r+1)^2 - 1 tone maps per pixel.
  std::vector<vec3> mapped(count);
  std::vector<uint8_t> finite(count);
  for (size_t i = 0; i < count; ++i) {
    finite[i] = isFinite(image.pixels[i]);
    mapped[i] = tone.apply(image.pixels[i]);
  }

  // One spatial table per distinct alpha: the filterbank uses a handful of values, so
  // exp(-alpha d^2 / 2) is evaluated a few hundred times instead of once per tap.
  std::vector<float> distinct(alphaOf.begin(), alphaOf.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  const int side = 2 * radius + 1;
  const size_t taps = size_t(side) * side;
  std::vector<double> spatial(distinct.size() * taps);
  for (size_t a = 0; a < distinct.size(); ++a) {
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        const double d2 = double(dx) * dx + double(dy) * dy;
        spatial[a * taps + size_t(dy + radius) * side + (dx + radius)] =
            std::exp(-double(distinct[a]) * d2 / 2.0);
      }
    }
  }
  // Clamped so that a tiny sigma_c cannot make the scale inf, which would turn the centre tap's
  // 0 * scale into NaN.
  const float rangeScale = float(std::min(1.0 / (2.0 * double(sigmaC) * double(sigmaC)),
                                          double(std::numeric_limits<float>::max())));

  Image out(width, height);
  // Every output pixel reads only the input and writes only itself, in a fixed tap order,
  // so the result does not depend on how rows are split between threads.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      const int y0 = std::max(0, y - radius), y1 = std::min(height - 1, y + radius);
      for (int x = 0; x < width; ++x) {
        const size_t p = size_t(y) * width + x;
        if (!finite[p]) {
          out.pixels[p] = image.pixels[p];
          continue;
        }
        const size_t table = size_t(std::lower_bound(distinct.begin(), distinct.end(), alphaOf[p]) -
                                    distinct.begin());
        const double* weights = spatial.data() + table * taps;
        const vec3 centre = mapped[p];
        const int x0 = std::max(0, x - radius), x1 = std::min(width - 1, x + radius);
        // Clipping the window at the borders and dividing by the weights actually used is
        // the renormalisation of eq. 18.
        double sumW = 0.0, sumR = 0.0, sumG = 0.0, sumB = 0.0;
        for (int qy = y0; qy <= y1; ++qy) {
          const size_t row = size_t(qy) * width;
          const double* rowWeights = weights + size_t(qy - y + radius) * side;
          for (int qx = x0; qx <= x1; ++qx) {
            const size_t q = row + qx;
            if (!finite[q]) continue;  // a NaN or inf neighbour would poison the average
            const vec3 d = mapped[q] - centre;
            // The range factor is evaluated in float (expf is about twice as fast as exp and
            // this is the only transcendental per tap); sums stay in double.
            const float range = d.x * d.x + d.y * d.y + d.z * d.z;
            const double w = rowWeights[qx - x + radius] * double(std::exp(-range * rangeScale));
            const vec3 c = image.pixels[q];
            sumW += w;
            sumR += w * c.x;
            sumG += w * c.y;
            sumB += w * c.z;
          }
        }
        // sumW >= 1: the centre tap has zero distance in space and in colour.
        out.pixels[p] = vec3(float(sumR / sumW), float(sumG / sumW), float(sumB / sumW));
      }
    }
  });
  return out;
}

Reconstruction reconstruct(const Image& estimate, std::span<const float> bias, const ToneMap& tone,
                           const FilterConfig& config, const std::atomic<bool>* cancel) {
  requireConsistent(estimate);
  if (bias.size() != estimate.pixels.size())
    throw std::invalid_argument("reconstruct: bias has " + std::to_string(bias.size()) +
                                " values for " + std::to_string(estimate.pixels.size()) +
                                " pixels");
  validate(config);

  Reconstruction result;
  result.alphaIndex.resize(bias.size());
  std::vector<float> alphaOf(bias.size());
  for (size_t i = 0; i < bias.size(); ++i) {
    const int index = alphaIndexForBias(bias[i], config.phi);
    result.alphaIndex[i] = uint8_t(index);
    alphaOf[i] = config.alphas[size_t(index)];
  }
  result.firstPass = bilateralPass(estimate, alphaOf, tone, config.radius, config.sigmaC, cancel);

  if (!config.secondPass) {
    result.output = result.firstPass;
    return result;
  }
  // Softens the seams where the first pass switches abruptly between alphas (§9.4); the
  // range term now sees the first pass's colours.
  std::fill(alphaOf.begin(), alphaOf.end(), config.alphas[size_t(config.secondPassAlpha)]);
  result.output =
      bilateralPass(result.firstPass, alphaOf, tone, config.radius, config.sigmaC, cancel);
  return result;
}

}  // namespace penumbra
