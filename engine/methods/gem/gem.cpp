#include "methods/gem/gem.h"

#include "methods/factory.h"

#include "methods/film_reconstruction.h"

#include "core/rng.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace penumbra {

const ParamTable<GemConfig>& gemParams() {
  static const ParamTable<GemConfig> table = [] {
    ParamTable<GemConfig> t;
    t.include(allocationParams())
        .real("gamma", "gamma",
              "gem: confidence gamma of the bias test (c_gamma needs 1.9 gamma < 1)",
              [](auto& c) -> auto& { return c.gamma; }, 0, 1 / 1.9, {0.01, 0.5})
        .open(true, true);
    return t;
  }();
  return table;
}

namespace gem {

const std::vector<float>& samplingScales() {
  static const std::vector<float> s{1.0f, 2.0f, 4.0f, 8.0f};
  return s;
}

const std::vector<float>& finalScales() {
  static const std::vector<float> s = [] {
    std::vector<float> v;
    for (int i = 0; i < 8; ++i) v.push_back(float(std::sqrt(0.5) * std::pow(std::sqrt(2.0), i)));
    return v;
  }();
  return s;
}

double cGamma(double gamma) { return -std::log(1.0 - std::pow(1.9 * gamma, 1.0 / std::sqrt(2.0))); }

namespace {

// The normalisation of output position i of a line of `length`: the sum of the taps that
// fall inside the line (squared, for the variance of a weighted mean: (sum w)^2).
std::vector<float> edgeNorms(int length, const std::vector<float>& taps, bool squared) {
  const int radius = int(taps.size() / 2);
  std::vector<float> norms(static_cast<size_t>(length));
  for (int i = 0; i < length; ++i) {
    double norm = 0;
    for (int j = std::max(0, i - radius); j <= std::min(length - 1, i + radius); ++j)
      norm += taps[size_t(j - i + radius)];
    norms[size_t(i)] = float(1.0 / (squared ? norm * norm : norm));
  }
  return norms;
}

// Along x: each row on its own, the taps over neighbouring pixels.
void filterRows(const float* src, float* dst, int width, int height, int channels,
                const std::vector<float>& weights, const std::vector<float>& norms) {
  const int radius = int(weights.size() / 2);
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 8), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* row = src + size_t(y) * width * channels;
      float* out = dst + size_t(y) * width * channels;
      for (int i = 0; i < width; ++i) {
        const int lo = std::max(0, i - radius), hi = std::min(width - 1, i + radius);
        float acc[4] = {0, 0, 0, 0};
        for (int j = lo; j <= hi; ++j) {
          const float w = weights[size_t(j - i + radius)];
          for (int c = 0; c < channels; ++c) acc[c] += w * row[size_t(j) * channels + c];
        }
        for (int c = 0; c < channels; ++c)
          out[size_t(i) * channels + c] = acc[c] * norms[size_t(i)];
      }
    }
  });
}

// Along y: each output row is a weighted sum of whole input rows, contiguous in memory (a
// loop the compiler vectorises, where walking down the columns would miss the cache).
void filterColumns(const float* src, float* dst, int width, int height, int channels,
                   const std::vector<float>& weights, const std::vector<float>& norms) {
  const int radius = int(weights.size() / 2);
  const size_t rowFloats = size_t(width) * channels;
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      float* out = dst + size_t(y) * rowFloats;
      std::fill(out, out + rowFloats, 0.0f);
      for (int j = std::max(0, y - radius); j <= std::min(height - 1, y + radius); ++j) {
        const float w = weights[size_t(j - y + radius)];
        const float* row = src + size_t(j) * rowFloats;
        for (size_t k = 0; k < rowFloats; ++k) out[k] += w * row[k];
      }
      const float norm = norms[size_t(y)];
      for (size_t k = 0; k < rowFloats; ++k) out[k] *= norm;
    }
  });
}

}  // namespace

void gaussianFilter(std::span<const float> src, std::span<float> dst, int width, int height,
                    int channels, float sigma, bool squared) {
  if (channels < 1 || channels > 4) throw std::invalid_argument("1 to 4 channels");
  const size_t n = size_t(width) * height * channels;
  if (src.size() != n || dst.size() != n) throw std::invalid_argument("plane size mismatch");
  const int radius = std::max(1, int(std::ceil(3.0f * sigma)));
  std::vector<float> taps(size_t(2 * radius + 1));
  for (int i = -radius; i <= radius; ++i)
    taps[size_t(i + radius)] = float(std::exp(-double(i) * i / (2.0 * double(sigma) * sigma)));
  // For the variance of the weighted mean the weights are squared, and so is the norm.
  std::vector<float> weights = taps;
  if (squared)
    for (float& w : weights) w *= w;
  std::vector<float> tmp(n);
  filterRows(src.data(), tmp.data(), width, height, channels, weights,
             edgeNorms(width, taps, squared));
  filterColumns(tmp.data(), dst.data(), width, height, channels, weights,
                edgeNorms(height, taps, squared));
}

namespace {
std::span<const float> floats(const std::vector<vec3>& v) {
  return {reinterpret_cast<const float*>(v.data()), v.size() * 3};
}
std::span<float> floats(std::vector<vec3>& v) {
  return {reinterpret_cast<float*>(v.data()), v.size() * 3};
}
float meanOf(vec3 v) { return (v.x + v.y + v.z) / 3.0f; }
}  // namespace

ScaleSelection selectScales(const PixelStatistics& stats, std::span<const float> sigmas,
                            double gamma, bool finalPass) {
  const int w = stats.width, h = stats.height;
  const size_t n = size_t(w) * h;
  if (stats.mean.size() != n || stats.variance.size() != n || stats.count.size() != n)
    throw std::invalid_argument("GEM statistics: plane size mismatch");
  const double cg = cGamma(gamma);
  ScaleSelection out;
  out.scale.assign(n, 0);
  out.count = stats.count;
  out.estimate = stats.mean;
  out.mse.resize(n);
  for (size_t p = 0; p < n; ++p) out.mse[p] = meanOf(stats.variance[p]);
  std::vector<uint8_t> alive(n, 1);
  std::vector<vec3> fineI = stats.mean, fineV = stats.variance, coarseI(n), coarseV(n);
  std::vector<float> coarseN(n), invalid(n), smoothed(n), delta(n);
  float fineSigma = 0;
  for (size_t s = 0; s < sigmas.size(); ++s) {
    const float sigma = sigmas[s];
    gaussianFilter(floats(stats.mean), floats(coarseI), w, h, 3, sigma, false);
    gaussianFilter(floats(stats.variance), floats(coarseV), w, h, 3, sigma, true);
    gaussianFilter(stats.count, coarseN, w, h, 1, sigma, false);
    const double beta = fineSigma == 0
                            ? 1.0
                            : (double(sigma) * sigma + double(fineSigma) * fineSigma) /
                                  (double(sigma) * sigma - double(fineSigma) * fineSigma);
    for (size_t p = 0; p < n; ++p) {
      const vec3 gain = fineV[p] - coarseV[p];
      const vec3 d = fineI[p] - coarseI[p];
      const vec3 loss = float(beta) * d * d;
      const float z = float(cg * std::max(0.0, 1.0 - 1.0 / std::max(1e-6f, coarseN[p])));
      invalid[p] = meanOf(z * loss - gain) >= 0.0f ? 1.0f : 0.0f;
      delta[p] = meanOf(loss - gain);
    }
    gaussianFilter(invalid, smoothed, w, h, 1, sigma, false);
    for (size_t p = 0; p < n; ++p) {
      const float rounded = smoothed[p] >= 0.5f ? 1.0f : 0.0f;
      const bool bad = (finalPass ? std::min(invalid[p], rounded) : rounded) > 0.5f;
      if (!alive[p]) continue;
      if (bad) {
        alive[p] = 0;
        continue;
      }
      out.scale[p] = uint8_t(s + 1);
      out.mse[p] += delta[p];
      out.count[p] = coarseN[p];
      out.estimate[p] = coarseI[p];
    }
    std::swap(fineI, coarseI);
    std::swap(fineV, coarseV);
    fineSigma = sigma;
  }
  for (float& m : out.mse) m = std::max(0.0f, m);
  return out;
}

float pixelError(const ScaleSelection& s, size_t p, int spp) {
  const vec3 e = s.estimate[p];
  const double rel = s.mse[p] / (1e-3 + meanOf(e * e));
  const double gain = double(spp) / (double(spp) + std::max(0.0f, s.count[p]));
  const double v = rel * gain;
  return std::isfinite(v) ? float(v) : 0.0f;
}

}  // namespace gem

namespace {

class GemMethod final : public AllocationMethod {
 public:
  GemMethod(const PreparedScene& prepared, const RunShape& shape, const GemConfig& config)
      : AllocationMethod(prepared, shape, config, "gem"),
        gamma_(config.gamma),
        mean_(pixelCount_, glm::dvec3(0.0)),
        m2_(pixelCount_, glm::dvec3(0.0)),
        n_(pixelCount_, 0),
        samplingScale_(pixelCount_, 0) {}

 protected:
  void addSample(size_t p, uint32_t, vec3 L) override {
    // Welford: mean and sum of squared deviations, in sample order.
    ++n_[p];
    const glm::dvec3 x(L);
    const glm::dvec3 d = x - mean_[p];
    mean_[p] += d / double(n_[p]);
    m2_[p] += d * (x - mean_[p]);
  }

  void computeScores(std::vector<float>& scores) override {
    const gem::ScaleSelection s =
        gem::selectScales(statistics(), gem::samplingScales(), gamma_, false);
    const int spp = config_.effectiveBatch(shape_);
    for (size_t p = 0; p < pixelCount_; ++p) {
      scores[p] = gem::pixelError(s, p, spp);
      samplingScale_[p] = s.scale[p];
    }
  }

  void placeSamples(uint32_t pixel, int count, std::vector<uint32_t>& landing) override {
    landing.assign(size_t(count), pixel);
    const int scale = samplingScale_[pixel];
    if (scale == 0) return;
    const float sigma = gem::samplingScales()[size_t(scale - 1)];
    Pcg32 rng(hashValues(shape_.seed, pixel, round()), 0x67656du);
    const int px = int(pixel % width_), py = int(pixel / width_);
    for (int k = 0; k < count; ++k)
      for (int attempt = 0; attempt < 4; ++attempt) {
        // Box-Muller: a position from the scale's Gaussian centred on the pixel.
        const float u1 = std::max(1e-7f, rng.nextFloat()), u2 = rng.nextFloat();
        const float r = sigma * std::sqrt(-2.0f * std::log(u1));
        const float x = float(px) + 0.5f + r * std::cos(6.2831853f * u2);
        const float y = float(py) + 0.5f + r * std::sin(6.2831853f * u2);
        if (x < 0 || y < 0 || x >= float(width_) || y >= float(height_)) continue;
        landing[size_t(k)] = uint32_t(int(y)) * uint32_t(width_) + uint32_t(int(x));
        break;
      }
  }

  vec3 pixelMean(size_t p) const override { return vec3(mean_[p]); }

  void finishSnapshot(Snapshot& snap, bool reconstructImage, const std::atomic<bool>*) override {
    if (!reconstructImage) return;
    const gem::ScaleSelection s = gem::selectScales(statistics(), gem::finalScales(), gamma_, true);
    snap.reconstructed = Image(width_, height_);
    snap.reconstructed.pixels.assign(s.estimate.begin(), s.estimate.end());
    snap.addMap(maps::FilterScale, "filter scale", asFloats(s.scale),
                MapLegend::categorical(scaleLabels()));
    shownScale_ = s.scale;  // what the inspector tells of the pixel
  }

  void addInspectedValues(size_t pixel, PixelInspection& in) const override {
    if (pixel >= shownScale_.size()) return;
    const uint8_t scale = shownScale_[pixel];
    const std::vector<std::string> labels = scaleLabels();
    in.addValue("filter scale", {float(scale)},
                "filter scale " + (scale < labels.size() ? labels[scale] : std::string("?")),
                maps::FilterScale);
  }

  size_t statisticsBytes() const override {
    return (mean_.capacity() + m2_.capacity()) * sizeof(glm::dvec3) +
           n_.capacity() * sizeof(uint32_t) + samplingScale_.capacity();
  }
  std::string scoreName() const override { return "estimated relative MSE"; }
  // GEM shows its filtered image: the error it estimates for the scale it chose.
 public:
  std::vector<float> shownRelativeError() const override {
    const gem::ScaleSelection s = gem::selectScales(statistics(), gem::finalScales(), gamma_, true);
    std::vector<float> e(pixelCount_);
    for (size_t p = 0; p < pixelCount_; ++p)
      e[p] = s.mse[p] / relativeErrorRegulariser(s.estimate[p]);
    return e;
  }

 protected:
 private:
  gem::PixelStatistics statistics() const {
    gem::PixelStatistics st;
    st.width = width_;
    st.height = height_;
    st.mean.resize(pixelCount_);
    st.variance.resize(pixelCount_);
    st.count.resize(pixelCount_);
    for (size_t p = 0; p < pixelCount_; ++p) {
      st.mean[p] = vec3(mean_[p]);
      st.count[p] = float(n_[p]);
      st.variance[p] = n_[p] > 1 ? vec3(m2_[p] / (double(n_[p] - 1) * double(n_[p]))) : vec3(0.0f);
    }
    return st;
  }

  // The filter scales' labels: index 0 is the unfiltered mean, then the final sigmas.
  static std::vector<std::string> scaleLabels() {
    std::vector<std::string> labels = {"none"};
    for (float sigma : gem::finalScales()) {
      char label[24];
      std::snprintf(label, sizeof label, "s=%.2g", double(sigma));
      labels.push_back(label);
    }
    return labels;
  }

  double gamma_;
  std::vector<uint8_t> shownScale_;  // the scale per pixel of the last reconstructed snapshot
  std::vector<glm::dvec3> mean_, m2_;
  std::vector<uint32_t> n_;
  std::vector<uint8_t> samplingScale_;
};

}  // namespace

std::unique_ptr<ProgressiveMethod> makeGemMethod(const PreparedScene& prepared,
                                                 const RunShape& shape, const GemConfig& config) {
  return makeValidated<GemMethod>(gemMethod(), prepared, shape, config);
}

const MethodDescriptor& gemMethod() {
  static const MethodDescriptor descriptor(allocationDefinition<GemMethod, GemConfig>(
      "gem", "GEM (Rousselle et al. 2011)", gemParams(), true, {&maps::FilterScale}));
  return descriptor;
}

}  // namespace penumbra
