// The error-driven reconstruction of methods/recon/denoise.h: checks, the filtered domain
// (emission out, albedo divided out), the features' planes, and the choice of scale per pixel
// by smoothed SURE. The filter bank itself is methods/recon/sweep.cpp.
#include "methods/recon/denoise.h"

#include "methods/recon/sweep.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace penumbra::recon {
namespace {

using detail::FeaturePlanes;
using detail::Plane;
using detail::Planes3;
using detail::SweepInput;

// Bounds that keep the bank's cost and its uint8_t scale index sane.
constexpr int kMaxRadius = 64;
constexpr size_t kMaxScales = 32;

template <typename T>
void requireSize(std::span<const T> values, const char* field, size_t count, bool required) {
  if (values.empty() && !required) return;
  if (values.size() != count)
    throw std::invalid_argument(std::string("denoise: ") + field + " has " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(count) + " pixels");
}

void checkInput(const DenoiseInput& in) {
  if (in.width < 1 || in.height < 1)
    throw std::invalid_argument("denoise: width " + std::to_string(in.width) + " or height " +
                                std::to_string(in.height) + " is < 1");
  const size_t count = size_t(in.width) * size_t(in.height);
  requireSize(in.mean, "mean", count, true);
  requireSize(in.variance, "variance", count, true);
  requireSize(in.halfA, "halfA", count, false);
  requireSize(in.halfB, "halfB", count, false);
  if (in.halfA.empty() != in.halfB.empty())
    throw std::invalid_argument(std::string("denoise: ") + (in.halfA.empty() ? "halfA" : "halfB") +
                                " is empty while the other half is given");
  requireSize(in.emission, "emission", count, false);
  requireSize(in.albedo, "albedo", count, false);
  requireSize(in.albedoVariance, "albedoVariance", count, false);
  requireSize(in.normal, "normal", count, false);
  requireSize(in.normalVariance, "normalVariance", count, false);
  requireSize(in.depth, "depth", count, false);
  requireSize(in.depthVariance, "depthVariance", count, false);
}

bool finite(float v) { return std::isfinite(v); }

// Which inputs the denoiser reads, and so which must be finite for a pixel to be used.
struct Usage {
  bool cross = false, emission = false, demodulate = false;
  bool albedo = false, normal = false, depth = false;  // as features
};

Usage usageOf(const DenoiseInput& in, const DenoiseConfig& config) {
  Usage use;
  use.cross = config.crossFilter && !in.halfA.empty();
  use.emission = !in.emission.empty();
  use.demodulate = config.demodulate && !in.albedo.empty();
  use.albedo = config.useFeatures && !in.albedo.empty();
  use.normal = config.useFeatures && !in.normal.empty();
  use.depth = config.useFeatures && !in.depth.empty();
  return use;
}

bool inputsFinite(const DenoiseInput& in, const Usage& use, size_t p) {
  bool ok = isFinite(in.mean[p]) && isFinite(in.variance[p]);
  if (use.cross) ok = ok && isFinite(in.halfA[p]) && isFinite(in.halfB[p]);
  if (use.emission) ok = ok && isFinite(in.emission[p]);
  if (use.demodulate || use.albedo) ok = ok && isFinite(in.albedo[p]);
  if (use.albedo && !in.albedoVariance.empty()) ok = ok && isFinite(in.albedoVariance[p]);
  if (use.normal) ok = ok && isFinite(in.normal[p]);
  if (use.normal && !in.normalVariance.empty()) ok = ok && finite(in.normalVariance[p]);
  if (use.depth) ok = ok && finite(in.depth[p]);
  if (use.depth && !in.depthVariance.empty()) ok = ok && finite(in.depthVariance[p]);
  return ok;
}

// fn(p, x, y) for every pixel, rows in parallel; each pixel's work must be its own.
template <typename Fn>
void forEachPixel(int width, int height, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) {
      for (int x = 0; x < width; ++x) fn(size_t(y) * width + x, x, y);
    }
  });
}

void resize3(Planes3& planes, size_t count) {
  for (Plane& plane : planes) plane.assign(count, 0.0f);
}

// The filtered domain (§1): y = (mean - emission) / demod with demod = albedo + eps, its
// variance V / demod^2; the halves likewise, with the variance 2V of a half's mean.
// identityMse receives the identity's SURE: V / demod^2 back in linear units, summed over the
// channels (+inf where the pixel is not valid).
SweepInput filteredDomain(const DenoiseInput& in, const DenoiseConfig& config, const Usage& use,
                          LargeVector<float>& identityMse) {
  const size_t count = in.mean.size();
  SweepInput out;
  out.width = in.width;
  out.height = in.height;
  out.streams = use.cross ? 2 : 1;
  for (int s = 0; s < out.streams; ++s) resize3(out.value[s], count);
  resize3(out.variance, count);
  resize3(out.demod, count);
  resize3(out.emission, count);
  identityMse.assign(count, std::numeric_limits<float>::infinity());
  out.valid.assign(count, 0.0f);
  forEachPixel(in.width, in.height, [&](size_t p, int, int) {
    bool ok = inputsFinite(in, use, p);
    float value[2][3], demod[3], emission[3], variance[3];
    for (int c = 0; ok && c < 3; ++c) {
      demod[c] = use.demodulate ? std::max(in.albedo[p][c], 0.0f) + config.albedoEpsilon : 1.0f;
      emission[c] = use.emission ? in.emission[p][c] : 0.0f;
      const float v = std::min(std::max(in.variance[p][c], 0.0f), kMaxVariance);
      variance[c] = std::min(v / (demod[c] * demod[c]), kMaxVariance);
      if (use.cross) {
        value[0][c] = (in.halfA[p][c] - emission[c]) / demod[c];
        value[1][c] = (in.halfB[p][c] - emission[c]) / demod[c];
      } else {
        value[0][c] = (in.mean[p][c] - emission[c]) / demod[c];
      }
      for (int s = 0; s < out.streams; ++s) ok = ok && finite(value[s][c]);
    }
    if (!ok) {
      for (int c = 0; c < 3; ++c) out.demod[c][p] = 1.0f;
      return;
    }
    out.valid[p] = 1.0f;
    for (int c = 0; c < 3; ++c) {
      for (int s = 0; s < out.streams; ++s) out.value[s][c][p] = value[s][c];
      out.variance[c][p] = use.cross ? 2.0f * variance[c] : variance[c];
      out.demod[c][p] = demod[c];
      out.emission[c][p] = emission[c];
    }
    identityMse[p] =
        detail::toLinearSum(variance[0], variance[1], variance[2], demod[0], demod[1], demod[2]);
  });
  return out;
}

// Central difference of `plane` at p along a step of `step` pixels, one-sided where one
// neighbour is missing (outside the image or not valid), 0 where both are.
float centralDifference(const Plane& plane, const Plane& valid, size_t p, bool hasLow, bool hasHigh,
                        size_t step) {
  hasLow = hasLow && valid[p - step] > 0.0f;
  hasHigh = hasHigh && valid[p + step] > 0.0f;
  if (hasLow && hasHigh) return 0.5f * (plane[p + step] - plane[p - step]);
  if (hasHigh) return plane[p + step] - plane[p];
  if (hasLow) return plane[p] - plane[p - step];
  return 0.0f;
}

// A feature's planes (§3): components, variance, and 1 / (k_f^2 max(tau, Var_p, |grad_p|^2)).
template <typename Value, typename Variance>
FeaturePlanes featurePlanes(const SweepInput& domain, const DenoiseConfig& config, int components,
                            Value&& valueOf, Variance&& varianceOf) {
  const int width = domain.width, height = domain.height;
  const size_t count = domain.valid.size();
  FeaturePlanes f;
  f.components = components;
  for (int c = 0; c < components; ++c) f.value[c].assign(count, 0.0f);
  f.variance.assign(count, 0.0f);
  f.inverseScale.assign(count, 0.0f);
  forEachPixel(width, height, [&](size_t p, int, int) {
    if (!(domain.valid[p] > 0.0f)) return;
    for (int c = 0; c < components; ++c) f.value[c][p] = valueOf(p, c);
    f.variance[p] = std::min(std::max(varianceOf(p), 0.0f), kMaxVariance);
  });
  const float kf2 = config.kFeature * config.kFeature;
  forEachPixel(width, height, [&](size_t p, int x, int y) {
    if (!(domain.valid[p] > 0.0f)) return;
    float gradient2 = 0.0f;
    for (int c = 0; c < components; ++c) {
      const float gx = centralDifference(f.value[c], domain.valid, p, x > 0, x + 1 < width, 1);
      const float gy =
          centralDifference(f.value[c], domain.valid, p, y > 0, y + 1 < height, size_t(width));
      gradient2 += gx * gx + gy * gy;
    }
    f.inverseScale[p] = 1.0f / (kf2 * std::max({config.tau, f.variance[p], gradient2}));
  });
  return f;
}

void addFeatures(const DenoiseInput& in, const DenoiseConfig& config, const Usage& use,
                 SweepInput& domain) {
  if (use.albedo) {
    domain.features.push_back(featurePlanes(
        domain, config, 3, [&](size_t p, int c) { return in.albedo[p][c]; },
        [&](size_t p) {
          if (in.albedoVariance.empty()) return 0.0f;
          const vec3 v = in.albedoVariance[p];
          return v.x + v.y + v.z;
        }));
  }
  if (use.normal) {
    domain.features.push_back(featurePlanes(
        domain, config, 3, [&](size_t p, int c) { return in.normal[p][c]; },
        [&](size_t p) { return in.normalVariance.empty() ? 0.0f : in.normalVariance[p]; }));
  }
  if (use.depth) {
    domain.features.push_back(featurePlanes(
        domain, config, 1, [&](size_t p, int) { return in.depth[p]; },
        [&](size_t p) { return in.depthVariance.empty() ? 0.0f : in.depthVariance[p]; }));
  }
}

}  // namespace

std::vector<float> boxMean(std::span<const float> values, int width, int height, int radius,
                           std::span<const float> valid) {
  // Separable: each row's sums and counts over the window, then each column's over those, in
  // double so that wide windows of small values keep their digits.
  if (radius <= 0) return std::vector<float>(values.begin(), values.end());
  const size_t w = size_t(width);
  auto counts = [&](size_t q) {
    return std::isfinite(values[q]) && (valid.empty() || valid[q] > 0.0f);
  };
  // Huge pages (core/large_pages.h): these are made afresh at every round and picture.
  LargeVector<double> rowSum(values.size()), rowCount(values.size());
  std::vector<float> out(values.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        double sum = 0, n = 0;
        for (int t = std::max(0, x - radius); t <= std::min(width - 1, x + radius); ++t) {
          const size_t q = size_t(y) * w + size_t(t);
          if (!counts(q)) continue;
          sum += values[q];
          n += 1;
        }
        rowSum[size_t(y) * w + size_t(x)] = sum;
        rowCount[size_t(y) * w + size_t(x)] = n;
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        const size_t p = size_t(y) * w + size_t(x);
        double sum = 0, n = 0;
        for (int t = std::max(0, y - radius); t <= std::min(height - 1, y + radius); ++t) {
          sum += rowSum[size_t(t) * w + size_t(x)];
          n += rowCount[size_t(t) * w + size_t(x)];
        }
        const bool own = valid.empty() || valid[p] > 0.0f;
        out[p] = own && n > 0 ? float(sum / n) : values[p];
      }
    }
  });
  return out;
}

const ParamTable<DenoiseConfig>& denoiseParams() {
  static const ParamTable<DenoiseConfig> table = [] {
    ParamTable<DenoiseConfig> t;
    t.group("Reconstruction (NL-means, features, SURE)")
        .real(
            "nl-k", "colour k", "NL-means colour strength k (RECONSTRUCTION.md section 2)",
            [](auto& c) -> auto& { return c.k; }, 1e-3, 100, {0.05, 2}, true)
        .integer("nl-patch", "patch radius",
                 "NL-means patch radius: colour distances are averaged over (2r + 1)^2 pixels",
                 [](auto& c) -> auto& { return c.patchRadius; }, 0, 8, {0, 4})
        .integer("sure-smooth", "SURE smoothing",
                 "Box radius over which each scale's SURE map is smoothed before the choice",
                 [](auto& c) -> auto& { return c.sureSmoothRadius; }, 0, 16, {0, 6})
        .real(
            "feature-k", "feature k_f", "Feature weight strength k_f (section 3)",
            [](auto& c) -> auto& { return c.kFeature; }, 1e-3, 100, {0.05, 4}, true)
        .toggle(
            "features", "feature weights", "Colour weights only: no albedo, normal, depth terms",
            "--no-features", [](auto& c) -> auto& { return c.useFeatures; })
        .toggle(
            "demodulate", "albedo demodulation", "Filter radiance, not radiance over albedo",
            "--no-demodulate", [](auto& c) -> auto& { return c.demodulate; })
        .toggle(
            "cross-filter", "cross-filtering",
            "Weights from the pixel's own mean instead of the other half buffer",
            "--no-cross-filter", [](auto& c) -> auto& { return c.crossFilter; })
        .integer("coarse-recon-spp", "half-res recon up to spp",
                 "A large image's pictures are reconstructed at half resolution while it has at "
                 "most this many samples per pixel (0: never; a final image never is)",
                 [](auto& c) -> auto& { return c.coarseReconSpp; }, 0, 1024, {0, 16});
    return t;
  }();
  return table;
}

std::string validate(const DenoiseConfig& config) {
  if (std::string problem = checkParams(denoiseParams().params(), config); !problem.empty())
    return problem;
  if (config.radii.size() > kMaxScales)
    return "radii: at most " + std::to_string(kMaxScales) + " scales, got " +
           std::to_string(config.radii.size());
  for (size_t i = 0; i < config.radii.size(); ++i) {
    const int r = config.radii[i];
    if (r < 1 || r > kMaxRadius)
      return "radii: radius " + std::to_string(r) + " is not in [1, " + std::to_string(kMaxRadius) +
             "]";
    if (i > 0 && r <= config.radii[i - 1]) return "radii: must be strictly ascending";
  }
  auto positive = [](float v) { return v > 0.0f && std::isfinite(v); };
  if (!(config.noiseCancel >= 0.0f) || !std::isfinite(config.noiseCancel))
    return "noiseCancel: must be a finite value >= 0";
  if (!positive(config.tau)) return "tau: must be a finite value > 0";
  if (!positive(config.albedoEpsilon)) return "albedoEpsilon: must be a finite value > 0";
  if (config.denseRadius < 1) return "denseRadius: must be >= 1";
  // A radius just above denseRadius needs offsets of its sparse ring that are kept.
  for (int r : config.radii) {
    if (r == config.denseRadius + 1 && r % 2 == 1)
      return "denseRadius: radius " + std::to_string(r) + " is denseRadius + 1 and odd, so " +
             "none of its outer offsets (even coordinates only) would be taken";
  }
  return {};
}

namespace {

// A result of width x height before any pixel is filtered: black, scale 0 (the identity), no
// error, variance ratio 1.
DenoiseResult sizedResult(int width, int height) {
  const size_t count = size_t(width) * size_t(height);
  DenoiseResult result;
  result.output = Image(width, height);
  result.scale.assign(count, 0);
  result.mseEstimate.assign(count, 0.0f);
  result.varianceRatio.assign(count, 1.0f);
  return result;
}

// denoiseDetailed for the output rows [outFirst, outLast) of `in` (the result holds those rows
// only): the bank is swept over them and sureSmoothRadius rows either side, whose SURE the
// box reads; every row of `in` may be read as a neighbour. For a pixel whose rows out to
// reach(config) lie in `in` (or end where the image does), the result is the whole
// image's, bit for bit: every step is the pixel's own or reads a fixed neighbourhood.
DenoiseResult denoiseRows(const DenoiseInput& in, const DenoiseConfig& config,
                          DenoiseDetail* detail, const std::atomic<bool>* cancel,
                          const std::function<void()>& inputsRead, int outFirst, int outLast) {
  const Usage use = usageOf(in, config);
  const size_t width = size_t(in.width);
  // The candidates, index 0 the identity: the mean itself, whose squared error is V exactly
  // (its output and variance ratio, in.mean and 1, are not copied).
  std::vector<detail::ScaleMaps> candidates(1);
  SweepInput domain = filteredDomain(in, config, use, candidates[0].mse);
  addFeatures(in, config, use, domain);
  if (inputsRead) inputsRead();  // from here on only in.mean is read
  const int sweepFirst = std::max(0, outFirst - config.sureSmoothRadius);
  const int sweepLast = std::min(in.height, outLast + config.sureSmoothRadius);
  const int sweepRows = sweepLast - sweepFirst;
  domain.firstRow = sweepFirst;
  domain.lastRow = sweepLast;
  {
    const detail::SweepConfig sweep{config.radii, config.k, config.noiseCancel, config.patchRadius,
                                    config.denseRadius};
    std::vector<detail::ScaleMaps> filtered = detail::sweepScales(domain, sweep, cancel);
    // Cancelled: the sweep stopped part way, and what follows (the SURE maps' smoothing, the
    // choice) would take tens of milliseconds at 1280x720 for nothing. The result keeps its
    // size (denoise.h), its values those of a result just made.
    if (cancel && cancel->load(std::memory_order_relaxed))
      return sizedResult(in.width, outLast - outFirst);
    for (detail::ScaleMaps& maps : filtered) candidates.push_back(std::move(maps));
  }
  // The identity's SURE of the swept rows only.
  if (sweepFirst > 0 || sweepLast < in.height) {
    LargeVector<float>& mse = candidates[0].mse;
    LargeVector<float>(mse.begin() + ptrdiff_t(size_t(sweepFirst) * width),
                       mse.begin() + ptrdiff_t(size_t(sweepLast) * width))
        .swap(mse);
  }
  // Of the filtered domain only the pixels' validity is read from here on: the rest goes, and
  // each candidate's SURE once it is smoothed (unless `detail` wants it), so that a large
  // image's reconstruction does not hold them all at once.
  Plane valid;
  valid.assign(size_t(sweepRows) * width, 0.0f);
  std::copy(domain.valid.begin() + ptrdiff_t(size_t(sweepFirst) * width),
            domain.valid.begin() + ptrdiff_t(size_t(sweepLast) * width), valid.begin());
  domain = SweepInput{};
  std::vector<std::vector<float>> smoothedMse;
  for (detail::ScaleMaps& maps : candidates) {
    smoothedMse.push_back(boxMean(maps.mse, in.width, sweepRows, config.sureSmoothRadius,
                                  std::span<const float>(valid.data(), valid.size())));
    if (!detail) LargeVector<float>().swap(maps.mse);
  }

  const size_t skip = size_t(outFirst - sweepFirst) * width;  // output row 0 in the swept rows
  const size_t base = size_t(outFirst) * width;               // and in `in`
  DenoiseResult result = sizedResult(in.width, outLast - outFirst);
  forEachPixel(in.width, outLast - outFirst, [&](size_t o, int, int) {
    const size_t p = base + o, i = skip + o;
    // The least smoothed SURE wins; ties go to the narrower scale (the identity first).
    size_t best = 0;
    if (valid[i] > 0.0f) {
      for (size_t s = 1; s < candidates.size(); ++s)
        if (smoothedMse[s][i] < smoothedMse[best][i]) best = s;
    }
    vec3 output = best == 0 ? in.mean[p] : candidates[best].output[i];
    // Belt and braces: a finite mean never becomes a non-finite output.
    if (!isFinite(output) && isFinite(in.mean[p])) {
      best = 0;
      output = in.mean[p];
    }
    result.output.pixels[o] = output;
    result.scale[o] = uint8_t(best);
    const float mse = smoothedMse[best][i] / 3.0f;
    // NaN becomes 0; a pixel that is not valid keeps +inf (its variance counts as infinite).
    result.mseEstimate[o] = mse > 0.0f ? mse : 0.0f;
    result.varianceRatio[o] = best == 0 ? 1.0f : candidates[best].varianceRatio[i];
  });

  if (detail) {
    *detail = DenoiseDetail{};
    candidates[0].output.assign(in.mean.begin(), in.mean.end());
    candidates[0].varianceRatio.assign(in.mean.size(), 1.0f);
    for (size_t s = 0; s < candidates.size(); ++s) {
      Image image(in.width, in.height);
      image.pixels.assign(candidates[s].output.begin(), candidates[s].output.end());
      detail->scaleOutput.push_back(std::move(image));
      std::vector<float> raw(candidates[s].mse.begin(), candidates[s].mse.end()),
          smooth = smoothedMse[s];
      for (float& v : raw) v /= 3.0f;
      for (float& v : smooth) v /= 3.0f;
      detail->scaleMse.push_back(std::move(raw));
      detail->scaleMseSmoothed.push_back(std::move(smooth));
      detail->scaleVarianceRatio.emplace_back(candidates[s].varianceRatio.begin(),
                                              candidates[s].varianceRatio.end());
    }
  }
  return result;
}

}  // namespace

int reach(const DenoiseConfig& config) {
  return config.sureSmoothRadius + (config.radii.empty() ? 0 : config.radii.back()) +
         config.patchRadius + 1;
}

DenoiseResult denoiseRows(const DenoiseInput& in, const DenoiseConfig& config, int first, int last,
                          const std::atomic<bool>* cancel) {
  if (const std::string problem = validate(config); !problem.empty())
    throw std::invalid_argument("denoise: " + problem);
  checkInput(in);
  if (first < 0 || last > in.height || first >= last)
    throw std::invalid_argument("denoise: rows " + std::to_string(first) + " to " +
                                std::to_string(last) + " are not within the input's " +
                                std::to_string(in.height));
  return denoiseRows(in, config, nullptr, cancel, {}, first, last);
}

DenoiseInput rowsOf(const DenoiseInput& in, int first, int last) {
  DenoiseInput out = in;
  out.height = last - first;
  const size_t offset = size_t(first) * size_t(in.width), count = size_t(out.height) * in.width;
  auto cut = [&]<typename T>(std::span<const T>& s) {
    if (!s.empty()) s = s.subspan(offset, count);
  };
  cut(out.mean), cut(out.variance), cut(out.halfA), cut(out.halfB), cut(out.emission);
  cut(out.albedo), cut(out.albedoVariance), cut(out.normal), cut(out.normalVariance);
  cut(out.depth), cut(out.depthVariance);
  return out;
}

DenoiseResult denoise(const DenoiseInput& in, const DenoiseConfig& config,
                      const std::atomic<bool>* cancel, const std::function<void()>& inputsRead) {
  return denoiseDetailed(in, config, nullptr, cancel, inputsRead);
}

DenoiseResult denoiseDetailed(const DenoiseInput& in, const DenoiseConfig& config,
                              DenoiseDetail* detail, const std::atomic<bool>* cancel,
                              const std::function<void()>& inputsRead) {
  if (const std::string problem = validate(config); !problem.empty())
    throw std::invalid_argument("denoise: " + problem);
  checkInput(in);
  return denoiseRows(in, config, detail, cancel, inputsRead, 0, in.height);
}

DenoiseResult denoiseInBands(int width, int height, const DenoiseConfig& config, int bandRows,
                             const BandSource& source, const std::atomic<bool>* cancel,
                             const std::function<void()>& inputsRead) {
  if (const std::string problem = validate(config); !problem.empty())
    throw std::invalid_argument("denoise: " + problem);
  if (width < 1 || height < 1 || bandRows < 1)
    throw std::invalid_argument("denoise: width " + std::to_string(width) + ", height " +
                                std::to_string(height) + " or band rows " +
                                std::to_string(bandRows) + " is < 1");
  DenoiseResult result = sizedResult(width, height);
  const int halo = reach(config);
  for (int y0 = 0; y0 < height; y0 += bandRows) {
    if (cancel && cancel->load(std::memory_order_relaxed)) break;
    const int y1 = std::min(height, y0 + bandRows);
    const int first = std::max(0, y0 - halo), last = std::min(height, y1 + halo);
    const DenoiseInput in = source(first, last);
    if (in.width != width || in.height != last - first)
      throw std::invalid_argument("denoise: the band source gave " + std::to_string(in.width) +
                                  "x" + std::to_string(in.height) + " for rows " +
                                  std::to_string(first) + " to " + std::to_string(last));
    checkInput(in);
    DenoiseResult band =
        denoiseRows(in, config, nullptr, cancel, inputsRead, y0 - first, y1 - first);
    const size_t at = size_t(y0) * size_t(width);
    std::copy(band.output.pixels.begin(), band.output.pixels.end(),
              result.output.pixels.begin() + ptrdiff_t(at));
    std::copy(band.scale.begin(), band.scale.end(), result.scale.begin() + ptrdiff_t(at));
    std::copy(band.mseEstimate.begin(), band.mseEstimate.end(),
              result.mseEstimate.begin() + ptrdiff_t(at));
    std::copy(band.varianceRatio.begin(), band.varianceRatio.end(),
              result.varianceRatio.begin() + ptrdiff_t(at));
  }
  return result;
}

DenoiseResult denoiseInBands(const DenoiseInput& in, const DenoiseConfig& config, int bandRows,
                             const std::atomic<bool>* cancel) {
  checkInput(in);
  return denoiseInBands(
      in.width, in.height, config, bandRows,
      [&](int first, int last) { return rowsOf(in, first, last); }, cancel);
}

}  // namespace penumbra::recon
