// The consistent reconstruction of a film (methods/recon/denoise.h, whose denoiseParams() are
// the filter's flags) as the methods that filter use it (`ld` with --filter, BP's consistent
// algorithm): the per-pixel error it estimates (what allocation ranks and
// the noise threshold tests), and the maps that show the film's features and the filter's
// choices.
#pragma once

#include "methods/film.h"
#include "methods/params.h"
#include "methods/recon/denoise.h"
#include "methods/snapshot.h"

#include <atomic>
#include <vector>

namespace penumbra {

// Denoises the film's buffers.
recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
                                     const std::atomic<bool>* cancel = nullptr);

// Images of at least this many pixels (512x512) reconstruct their first pictures at half
// resolution (recon::denoiseCoarse): below it the full reconstruction takes a few tenths of a
// second at most on two cores.
inline constexpr size_t kCoarsePixels = size_t(1) << 18;

// Whether a picture of `film` is reconstructed coarsely: it is not final, the image has at least
// kCoarsePixels pixels, and samplesPerPixel (the samples traced so far over the pixels) is at
// most config.coarseReconSpp. It depends on the samples only, never on time, so a picture still
// depends only on the seed.
bool reconstructsCoarsely(const Film& film, const recon::DenoiseConfig& config,
                          double samplesPerPixel, bool final);

// The reconstruction of a picture: recon::denoiseCoarse of the film when reconstructsCoarsely,
// else reconstructFilm.
recon::DenoiseResult reconstructPicture(const Film& film, const recon::DenoiseConfig& config,
                                        double samplesPerPixel, bool final,
                                        const std::atomic<bool>* cancel = nullptr);

// Per pixel, the estimated relative squared error of the filtered pixel,
// mse / (mean luminance^2 + 0.01) (RECONSTRUCTION.md §5; the metrics' relMSE uses the same
// regulariser).
std::vector<float> relativeError(const recon::DenoiseResult& result, const Film& film);
// The same for the unfiltered mean: its variance over (mean luminance^2 + 0.01).
std::vector<float> rawRelativeError(const Film& film);
// The denominator of both: the mean's luminance (channel mean) squared, plus 0.01.
float relativeErrorRegulariser(vec3 mean);
// The mean of a per-pixel map's finite values (0 when none).
double meanOf(const std::vector<float>& values);

namespace maps {
// The film's first-hit features and buffers (methods/film.h), published by addFilmMaps:
inline constexpr MapKind Albedo{"albedo", nullptr, "Albedo (first hit)", 8};  // linear RGB
// The mean shading normal there, shown as 0.5 + 0.5 n.
inline constexpr MapKind Normal{"normal", nullptr, "Normal (first hit)", 9};
inline constexpr MapKind Depth{"depth", nullptr, "Depth (first hit)", 10};  // over the mean
inline constexpr MapKind Emission{"emission", nullptr, "Directly seen emission", 11};
// The estimated relative squared error of the unfiltered pixel mean.
inline constexpr MapKind RawError{"raw_error", nullptr, "Raw estimate's relMSE (estimated)", 12};
// The maps addFilmMaps publishes, and what a method with a film and its reconstruction lists
// in its descriptor (these, and the framework's maps::shared()).
inline constexpr const MapKind* kFilm[] = {&Albedo, &Normal, &Depth, &Emission, &RawError};
}  // namespace maps

// Albedo, normal, depth, directly seen emission and the raw image's estimated relative error.
void addFilmMaps(Snapshot& snap, const Film& film);
// The chosen scale per pixel (FilterScale).
void addFilterScaleMap(Snapshot& snap, const recon::DenoiseResult& result,
                       const recon::DenoiseConfig& config);
// The chosen scale per pixel (FilterScale) and the filtered image's estimated relative error
// (ErrorEstimate).
void addReconstructionMaps(Snapshot& snap, const recon::DenoiseResult& result,
                           const recon::DenoiseConfig& config, const std::vector<float>& error);

}  // namespace penumbra
