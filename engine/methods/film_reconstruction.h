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
#include <optional>
#include <vector>

namespace penumbra {

// Denoises the film's buffers.
recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
                                     const std::atomic<bool>* cancel = nullptr);
// The same with the depths multiplied by `depthScale` instead of the film's depthScale().
recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
                                     float depthScale, const std::atomic<bool>* cancel = nullptr);

// A picture's reconstruction kept for the next picture (updateReconstruction): its output and
// chosen scales, and the depth scale it was made with.
struct KeptReconstruction {
  Image output;
  std::vector<uint8_t> scale;
  float depthScale = 1.0f;
  size_t memoryBytes() const { return output.pixels.capacity() * sizeof(vec3) + scale.capacity(); }
};

// The rectangle of `film` an update redoes at most, as a share of the image: beyond it a whole
// reconstruction costs about as much.
inline constexpr double kMaxUpdateShare = 0.5;

// Brings `kept`, a reconstruction of `film` made before the pixels marked in `changed` (one
// entry per pixel) took more samples, up to date. A pixel's output reads the input out to
// recon::reach(config) around it, so only the pixels near a changed one are redone, from
// the rectangle of the film around them out to that reach again; the others keep their
// output. The result is that of reconstructFilm(film, config, kept.depthScale), bit for bit.
// False, and `kept` as it was, when that rectangle holds more than kMaxUpdateShare of the
// image or the update was cancelled. The rectangle is redone in bands of `bandRows` rows (0:
// as many as keep a band's planes near a quarter of a million pixels, as a whole
// reconstruction of a large image), each from its own rows of the film.
bool updateReconstruction(const Film& film, const recon::DenoiseConfig& config,
                          const std::vector<uint8_t>& changed, KeptReconstruction& kept,
                          const std::atomic<bool>* cancel = nullptr, int bandRows = 0);

// A method's pictures, each reconstructPicture's, but made from the last one where they can
// be: a picture that is neither final nor at half resolution (reconstructsCoarsely) after such
// a one redoes only the pixels near those that took samples since (updateReconstruction, with
// that picture's depth scale, so that it is a whole reconstruction with that scale). Where the
// adaptive rounds' samples land on part of a large image (an asset before a sky), a picture
// then costs that part's share. The last picture's output and scales are kept for it, and a
// flag a pixel: 14 bytes a pixel.
class PictureReconstruction {
 public:
  // Pixel p took samples (call it from any thread, each pixel from one).
  void changed(size_t p) {
    if (!changed_.empty()) changed_[p] = 1;
  }
  // The picture of `film` at samplesPerPixel; its mseEstimate and varianceRatio are empty when
  // it was updated from the last one.
  recon::DenoiseResult reconstruct(const Film& film, const recon::DenoiseConfig& config,
                                   double samplesPerPixel, bool final,
                                   const std::atomic<bool>* cancel = nullptr);
  size_t memoryBytes() const { return changed_.capacity() + (kept_ ? kept_->memoryBytes() : 0); }

 private:
  std::optional<KeptReconstruction> kept_;
  std::vector<uint8_t> changed_;  // since kept_ was made; empty before it
};

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
