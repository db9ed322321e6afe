// A consistent, error-driven image reconstruction (docs RECONSTRUCTION.md §1-4): a bank of
// non-local-means filters of growing window radius, one of which (or the unfiltered mean) is
// chosen per pixel by Stein's unbiased risk estimate of its squared error.
//  - Colour weights with a range term scaled by each pixel's variance of the mean, compared
//    over 3x3 patches (Rousselle, Knaus, Zwicker, "Adaptive rendering with non-local means
//    filtering", SIGGRAPH Asia 2012), cross-filtered between two half buffers so that the
//    weights of one half never depend on the values they average (Rousselle, Manzi, Zwicker,
//    "Robust denoising using feature and color information", Pacific Graphics 2013).
//  - Feature weights on first-hit albedo, normal and depth, variance- and gradient-normalised
//    (the same RDFC paper).
//  - Scale selection per pixel by SURE (Li, Wu, Chuang, "SURE-based optimization for adaptive
//    sampling and reconstruction", SIGGRAPH Asia 2012), in the spirit of Rousselle, Knaus,
//    Zwicker, "Adaptive sampling and reconstruction using greedy error minimization",
//    SIGGRAPH Asia 2011. The unfiltered mean is
//    always a candidate, with estimated error V; as V -> 0 with more samples any filter's bias
//    makes it lose, so the output tends to the mean: the reconstruction is consistent.
// Directly seen emission is kept out of the filter and added back; the rest is filtered
// divided by (albedo + eps) and multiplied back, so textures stay sharp.
// Each scale's spatial falloff is a box: every pixel of the (2r+1)^2 window clipped to the
// image counts alike, as in the NL-means filter of the 2012 paper; the colour and feature
// weights do the shaping. The result depends only on the inputs and the configuration, not on
// the thread count.
// Units: the feature distances of §3 are not normalised. Along a slope of g per pixel in a
// feature, Phi_j reaches 1 about k_f max(sqrt(tau), g) / g pixels away, so depth should come
// in units where one surface's pixel-to-pixel steps are small next to sqrt(tau).
#pragma once

#include "methods/params.h"

#include "core/image.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace penumbra::recon {

// Larger variances of a mean are clamped to this, so that sums of them stay finite.
inline constexpr float kMaxVariance = 1e30f;

struct DenoiseInput {
  int width = 0, height = 0;
  // Per pixel, rows top first, linear RGB:
  std::span<const vec3> mean;      // the pixel's estimate (directly seen emission included)
  std::span<const vec3> variance;  // per channel: variance of `mean` (of the mean, not per sample)
  // Means of the two half buffers (samples alternate A, B; equal counts). May be empty: then
  // no cross-filtering (weights from `mean`).
  std::span<const vec3> halfA, halfB;
  // Directly seen emission part of `mean` (may be empty = none). What is filtered is
  // mean - emission (and half - emission for each half); the emission is added back
  // unfiltered.
  std::span<const vec3> emission;
  // First-hit features, per pixel means and variances of the mean; any may be empty (= not
  // used; an empty variance next to a given feature counts as 0).
  std::span<const vec3> albedo;
  std::span<const vec3> albedoVariance;
  std::span<const vec3> normal;
  std::span<const float> normalVariance;  // variance summed over xyz
  std::span<const float> depth;
  std::span<const float> depthVariance;
};

struct DenoiseConfig {
  std::vector<int> radii{1, 2, 4, 8};  // window radii of the bank, ascending; the identity is
                                       // always in it as well
  // Colour strength (§2). Rousselle et al. use k = 0.45 with 7x7 patches; a distance averaged
  // over a 3x3 patch's 27 values instead of 147 is sqrt(147 / 27) = 2.3x as noisy, and keeping
  // its false rejections of pure-noise pairs as rare takes k^2 sqrt(values) constant:
  // 0.45 (147 / 27)^(1/4) = 0.70. Measured against 0.45 (16 spp, 2 seeds): BP's MSE 0.84-0.95x
  // on the five shipped scenes, 0.88x on balls at 256 spp (docs/bp-method.md).
  float k = 0.7f;
  float noiseCancel = 1.0f;  // alpha of §2
  int patchRadius = 1;       // 3x3 patches
  float kFeature = 0.6f;     // k_f of §3
  float tau = 1e-3f;         // §3
  // Box radius for smoothing each SURE map before selection. One pixel's SURE is too noisy to
  // choose by at low counts: with 3x3 boxes the choice flipped from pixel to pixel between the
  // identity and r = 8 in flat regions, leaving speckles. Measured at 16 spp, 2 seeds, BP's
  // default MSE x LD with radius 1 -> 5: stairs 0.12 -> 0.05, cornell 0.07 -> 0.04, tire 0.05
  // -> 0.03, dragon 0.24 -> 0.23, balls 0.17 -> 0.16; at 256 spp cornell 0.17 -> 0.15 and balls
  // 0.31 -> 0.29 (docs/RESULTS.md). The colour and feature weights keep edges.
  int sureSmoothRadius = 5;
  bool demodulate = true;  // filter (mean - emission) / (albedo + albedoEpsilon), multiply back
  float albedoEpsilon = 1e-2f;
  bool crossFilter = true;  // filter A with weights from B and vice versa (when halves given)
  bool useFeatures = true;
  // Window offsets whose Chebyshev norm exceeds denseRadius are taken only where both
  // coordinates are even, their spatial weights scaled up so that each scale's ring keeps its
  // total spatial weight (about 4x fewer weights beyond it). A radius of denseRadius + 1 must
  // be even, so that its ring holds some of them.
  int denseRadius = 4;
  // The first pictures of a large image (methods/film_reconstruction.h says which) are
  // reconstructed at half resolution (denoiseCoarse) while its samples per pixel are at most
  // this: 0 never. A final image is always reconstructed in full. 4 covers the coarse pass
  // (1 + 1 + 2 spp): at 1280x720 its 4-spp picture then costs 0.2 s instead of 0.6-1.1 s and
  // lands about a second sooner, and the next (full) picture sooner with it (docs/BENCHMARKS.md:
  // the .glb and tire in the window, relMSE at 2 and 4 s after a move).
  int coarseReconSpp = 4;
};

struct DenoiseResult {
  Image output;                // linear RGB, emission added back
  std::vector<uint8_t> scale;  // per pixel: 0 = identity, i + 1 = radii[i]
  // Per pixel: estimated squared error of output (mean over channels, linear units^2), from
  // the smoothed SURE of the chosen scale (>= 0; +inf for a pixel with non-finite input).
  std::vector<float> mseEstimate;
  // Per pixel: estimated variance of the output / variance of the raw mean (1 for identity;
  // clamped to [0, 1]).
  std::vector<float> varianceRatio;
};

// Every candidate of the bank, index 0 the identity and i + 1 radii[i]; for tests and
// debug views.
struct DenoiseDetail {
  std::vector<Image> scaleOutput;                    // the candidate's output, linear RGB
  std::vector<std::vector<float>> scaleMse;          // its estimated squared error per pixel
                                                     // (mean over channels, linear units^2,
                                                     // before smoothing; may be < 0)
  std::vector<std::vector<float>> scaleMseSmoothed;  // the same after the box of
                                                     // sureSmoothRadius
  std::vector<std::vector<float>> scaleVarianceRatio;
};

// The mean of each pixel's (2 radius + 1)^2 neighbourhood (clipped at the borders), over the
// finite values of the pixels that are `valid` (> 0; all when empty); a pixel that is not
// valid, or has no such neighbour, keeps its own value. How the SURE maps are smoothed.
std::vector<float> boxMean(std::span<const float> values, int width, int height, int radius,
                           std::span<const float> valid = {});

// The filter's parameters, shared by every method that has a `denoise` member (the same
// names, so one flag sets them all): its flags, panel widgets and ranges.
const ParamTable<DenoiseConfig>& denoiseParams();

// Empty when the configuration is valid, else a message naming the flag (denoiseParams()'s
// ranges) or the field that has none (the bank's radii, the internal constants).
std::string validate(const DenoiseConfig& config);

// Throws std::invalid_argument naming the field when a non-empty span has the wrong size
// (mean and variance are required), width or height < 1, or the configuration is bad.
// `cancel` is polled between rows; a cancelled result may be incomplete.
// A pixel with any non-finite input counts as having infinite variance: it gets no weight as
// a neighbour and its output is its mean.
// `inputsRead`, when set, is called once every span of `in` but `mean` has been read for the
// last time: the caller may free those buffers then, so that they are not held with the
// filter's own planes (a large image's peak memory).
DenoiseResult denoise(const DenoiseInput& in, const DenoiseConfig& config,
                      const std::atomic<bool>* cancel = nullptr,
                      const std::function<void()>& inputsRead = {});

// denoise, filling `detail` (when not null) with every candidate of the bank.
DenoiseResult denoiseDetailed(const DenoiseInput& in, const DenoiseConfig& config,
                              DenoiseDetail* detail, const std::atomic<bool>* cancel = nullptr,
                              const std::function<void()>& inputsRead = {});

// Rows [first, last) of an input: every span that is not empty cut to them.
DenoiseInput rowsOf(const DenoiseInput& in, int first, int last);

// How far from a pixel (in rows and in columns) its output reads the input: the SURE maps' box,
// then the widest window, the patch and the features' gradients around those.
int reach(const DenoiseConfig& config);

// denoise of the output rows [first, last) of `in` only (the result has last - first rows of
// in.width): the bank is swept over them and sureSmoothRadius rows either side. A pixel whose
// input out to reach(config) lies in `in` (or ends where the whole image does) gets the output
// that denoise of the whole image gives it, bit for bit: every step is the pixel's own or reads
// a fixed neighbourhood, in the same order wherever the pixel lies. So an input cut from a
// larger image, rows and columns, gives that image's output away from the cut's own edges.
DenoiseResult denoiseRows(const DenoiseInput& in, const DenoiseConfig& config, int first, int last,
                          const std::atomic<bool>* cancel = nullptr);

// The input rows [first, last) of an image (all its columns; height last - first): every span
// that the whole image's input would fill, holding those rows only. The spans must stay valid
// until the next call.
using BandSource = std::function<DenoiseInput(int first, int last)>;

// denoise in bands of `bandRows` output rows, each from the rows of the input around it that
// its output reads (the bank's widest window, the patch and the SURE box), so that only a
// band's planes are held at a time: the same result as denoise on the whole image, bit for
// bit, at the cost of sweeping 2 sureSmoothRadius more rows per band. `source` is asked for
// each band's rows in turn (rows top first); `inputsRead`, when set, is called once a band's
// spans but `mean` have been read for the last time (as denoise's). A cancelled result is
// incomplete.
DenoiseResult denoiseInBands(int width, int height, const DenoiseConfig& config, int bandRows,
                             const BandSource& source, const std::atomic<bool>* cancel = nullptr,
                             const std::function<void()>& inputsRead = {});
// The same over an input held whole (its bands are sub-spans of it).
DenoiseResult denoiseInBands(const DenoiseInput& in, const DenoiseConfig& config, int bandRows,
                             const std::atomic<bool>* cancel = nullptr);

// A quick reconstruction for the first pictures of a large image, about a quarter of
// denoise's cost: the input's 2x2 blocks are averaged (their variance of the mean is the sum of
// the pixels' over 4^2), that image is denoised with coarseConfig(config), and each pixel takes
// the filtered radiance over albedo of the blocks around it, interpolated bilinearly and
// weighted by how alike their normal and depth are to its own (joint bilateral upsampling,
// Kopf et al. 2007), times its own albedo, plus its own directly seen emission. Textures, lights
// and silhouettes therefore stay at full resolution; only the illumination is filtered at half.
// The result's scale is the block's, as the nearest radius of config's bank (a block's identity
// is radius 1); its mse estimate and variance ratio are the block's. The result depends only on
// the inputs and the configuration. `source` gives the input's rows [first, last) (every span
// denoise reads), `upsampleSource` the same rows' mean, emission, albedo, normal and depth (the
// others may be empty); both are asked for bands of bandRows rows (rounded up to even) in turn.
DenoiseResult denoiseCoarse(int width, int height, const DenoiseConfig& config, int bandRows,
                            const BandSource& source, const BandSource& upsampleSource,
                            const std::atomic<bool>* cancel = nullptr);
// The same over an input held whole.
DenoiseResult denoiseCoarse(const DenoiseInput& in, const DenoiseConfig& config,
                            const std::atomic<bool>* cancel = nullptr);
// The configuration of denoiseCoarse's half-resolution image: each radius of the bank halved
// (rounded up, duplicates dropped), as are the dense radius and the SURE box, so that every
// window covers about what it does at full resolution.
DenoiseConfig coarseConfig(const DenoiseConfig& config);

}  // namespace penumbra::recon
