// The consistent reconstruction of a film (methods/recon/denoise.h) as the methods that
// filter use it (`ld` with --filter, BP's consistent algorithm): its parameters for the
// command line and the panel, the per-pixel error it estimates (what allocation ranks and
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

// The filter's parameters, shared by every method that has a `denoise` member (the same
// names, so one flag sets them all).
const ParamTable<recon::DenoiseConfig>& denoiseParams();

// Denoises the film's buffers.
recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
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

// Albedo, normal, depth, directly seen emission and the raw image's estimated relative error.
void addFilmMaps(Snapshot& snap, const Film& film);
// The chosen scale per pixel (FilterScale) and the filtered image's estimated relative error
// (ErrorEstimate).
void addReconstructionMaps(Snapshot& snap, const recon::DenoiseResult& result,
                           const recon::DenoiseConfig& config, const std::vector<float>& error);

}  // namespace penumbra
