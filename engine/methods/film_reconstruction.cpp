#include "methods/film_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace penumbra {

namespace {

// A band's output pixels, at most, when the film is reconstructed in bands
// (recon::denoiseInBands): its planes (the film's buffers until the filter has read them, the
// filtered domain and features, about 120 bytes per pixel, and the bank's maps, 80, over the
// band and its halo: 166 rows at 1920 wide) then stay near 70 MB whatever the image's height,
// instead of about 220 bytes per pixel of the whole image.
constexpr size_t kBandPixels = size_t(1) << 18;
// Each band sweeps 2 sureSmoothRadius rows beyond its own: images up to this size (1280x720
// and below) are reconstructed whole.
constexpr size_t kWholePixels = size_t(1) << 20;

int bandRowsFor(const Film& film) {
  const size_t pixels = film.pixelCount();
  if (pixels <= kWholePixels) return std::max(film.height(), 1);
  return int(std::max<size_t>(64, kBandPixels / size_t(std::max(film.width(), 1))));
}

recon::DenoiseInput inputOf(const FilmBuffers& b) {
  recon::DenoiseInput in;
  in.width = b.width;
  in.height = b.height;
  in.mean = b.mean;
  in.variance = b.variance;
  in.halfA = b.halfA;
  in.halfB = b.halfB;
  in.emission = b.emission;
  in.albedo = b.albedo;
  in.albedoVariance = b.albedoVariance;
  in.normal = b.normal;
  in.normalVariance = b.normalVariance;
  in.depth = b.depth;
  in.depthVariance = b.depthVariance;
  return in;
}

// The emission's variance is not read.
constexpr unsigned kReconstructionParts =
    FilmBuffers::kRadiance | FilmBuffers::kFeatures | FilmBuffers::kFeatureVariances;

// Frees every buffer of b but the mean (which a reconstruction's input still points into).
void releaseAllButMean(FilmBuffers& b) {
  for (LargeVector<vec3>* v :
       {&b.variance, &b.halfA, &b.halfB, &b.emission, &b.albedo, &b.albedoVariance, &b.normal})
    LargeVector<vec3>().swap(*v);
  for (LargeVector<float>* v : {&b.normalVariance, &b.depth, &b.depthVariance})
    LargeVector<float>().swap(*v);
}

}  // namespace

recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
                                     const std::atomic<bool>* cancel) {
  return reconstructFilm(film, config, film.depthScale(), cancel);
}

recon::DenoiseResult reconstructFilm(const Film& film, const recon::DenoiseConfig& config,
                                     float depthScale, const std::atomic<bool>* cancel) {
  // The buffers but the mean go once the filter has read them (they are as large as the
  // filter's own planes).
  const int bandRows = bandRowsFor(film);
  if (bandRows < film.height()) {
    // One band's buffers at a time (the last is dropped before the next is made).
    FilmBuffers band;
    return recon::denoiseInBands(
        film.width(), film.height(), config, bandRows,
        [&](int first, int last) {
          band = FilmBuffers{};
          band = film.buffers(kReconstructionParts, first, last, depthScale);
          return inputOf(band);
        },
        cancel, [&band] { releaseAllButMean(band); });
  }
  FilmBuffers b = film.buffers(kReconstructionParts, 0, film.height(), depthScale);
  return recon::denoise(inputOf(b), config, cancel, [&b] { releaseAllButMean(b); });
}

bool updateReconstruction(const Film& film, const recon::DenoiseConfig& config,
                          const std::vector<uint8_t>& changed, KeptReconstruction& kept,
                          const std::atomic<bool>* cancel, int bandRows) {
  const int width = film.width(), height = film.height();
  const size_t w = size_t(width);
  if (changed.size() != film.pixelCount() || kept.output.width != width ||
      kept.output.height != height || kept.scale.size() != film.pixelCount())
    throw std::invalid_argument(
        "updateReconstruction: the kept reconstruction or the changed "
        "pixels are not of the film's size");
  // The changed pixels' bounding box.
  int x0 = width, x1 = 0, y0 = height, y1 = 0;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = changed.data() + size_t(y) * w;
    int first = 0;
    while (first < width && !row[first]) ++first;
    if (first == width) continue;
    int last = width;
    while (!row[last - 1]) --last;
    x0 = std::min(x0, first), x1 = std::max(x1, last);
    y0 = std::min(y0, y), y1 = y + 1;
  }
  if (x0 >= x1) return true;  // nothing changed
  // The outputs that may change: within the reach of a changed pixel, and one more, since a
  // pixel of one sample reads its neighbours' (Film::neighbourVariance). Then the input those
  // read.
  const int reach = recon::reach(config);
  const int grow = reach + 1;
  const int ox0 = std::max(0, x0 - grow), ox1 = std::min(width, x1 + grow);
  const int oy0 = std::max(0, y0 - grow), oy1 = std::min(height, y1 + grow);
  const int ix0 = std::max(0, ox0 - reach), ix1 = std::min(width, ox1 + reach);
  const int iy0 = std::max(0, oy0 - reach), iy1 = std::min(height, oy1 + reach);  // its input
  if (double(ix1 - ix0) * double(iy1 - iy0) > kMaxUpdateShare * double(w) * double(height))
    return false;
  // In bands of rows of the rectangle, each from its own input rows, as a whole
  // reconstruction of a large image is made (its planes stay near kBandPixels), and written to
  // `kept` only once all are made.
  const size_t partWidth = size_t(ix1 - ix0), columns = size_t(ox1 - ox0);
  if (bandRows <= 0) bandRows = int(std::max<size_t>(64, kBandPixels / partWidth));
  std::vector<recon::DenoiseResult> parts;
  FilmBuffers b;
  for (int y = oy0; y < oy1; y += bandRows) {
    const int last = std::min(oy1, y + bandRows);
    const int first = std::max(0, y - reach), end = std::min(height, last + reach);
    film.fillBuffers(b, kReconstructionParts, first, end, kept.depthScale, ix0, ix1);
    parts.push_back(recon::denoiseRows(inputOf(b), config, y - first, last - first, cancel));
    if (cancel && cancel->load()) return false;
  }
  for (int y = oy0; y < oy1; ++y) {
    const recon::DenoiseResult& part = parts[size_t((y - oy0) / bandRows)];
    const size_t from = size_t((y - oy0) % bandRows) * partWidth + size_t(ox0 - ix0);
    const size_t to = size_t(y) * w + size_t(ox0);
    std::copy_n(part.output.pixels.begin() + ptrdiff_t(from), columns,
                kept.output.pixels.begin() + ptrdiff_t(to));
    std::copy_n(part.scale.begin() + ptrdiff_t(from), columns, kept.scale.begin() + ptrdiff_t(to));
  }
  return true;
}

recon::DenoiseResult PictureReconstruction::reconstruct(const Film& film,
                                                        const recon::DenoiseConfig& config,
                                                        double samplesPerPixel, bool final,
                                                        const std::atomic<bool>* cancel) {
  // The first pictures of a large image at half resolution, and the last one whole.
  if (final || reconstructsCoarsely(film, config, samplesPerPixel, final))
    return reconstructPicture(film, config, samplesPerPixel, final, cancel);
  recon::DenoiseResult r;
  if (kept_ && updateReconstruction(film, config, changed_, *kept_, cancel)) {
    r.output = kept_->output;
    r.scale = kept_->scale;
  } else {
    if (cancel && cancel->load()) return r;
    kept_.reset();  // not held with the new one
    const float depthScale = film.depthScale();
    r = reconstructFilm(film, config, depthScale, cancel);
    if (cancel && cancel->load()) return r;
    kept_ = KeptReconstruction{r.output, r.scale, depthScale};
  }
  changed_.assign(film.pixelCount(), 0);
  return r;
}

bool reconstructsCoarsely(const Film& film, const recon::DenoiseConfig& config,
                          double samplesPerPixel, bool final) {
  return !final && film.pixelCount() >= kCoarsePixels && config.coarseReconSpp > 0 &&
         samplesPerPixel <= double(config.coarseReconSpp);
}

recon::DenoiseResult reconstructPicture(const Film& film, const recon::DenoiseConfig& config,
                                        double samplesPerPixel, bool final,
                                        const std::atomic<bool>* cancel) {
  if (!reconstructsCoarsely(film, config, samplesPerPixel, final))
    return reconstructFilm(film, config, cancel);
  // Bands of the film's buffers in both passes: what the filter reads, then what the
  // upsampling reads (the estimate and the features' means). Each band is filled into the
  // last one's memory.
  const float depthScale = film.depthScale();
  FilmBuffers band;
  auto source = [&](unsigned parts) {
    return [&, parts](int first, int last) {
      film.fillBuffers(band, parts, first, last, depthScale);
      return inputOf(band);
    };
  };
  return recon::denoiseCoarse(film.width(), film.height(), config,
                              int(std::max<size_t>(64, kBandPixels / size_t(film.width()))),
                              source(kReconstructionParts),
                              source(FilmBuffers::kMean | FilmBuffers::kFeatures), cancel);
}

float relativeErrorRegulariser(vec3 mean) {
  const float y = (mean.x + mean.y + mean.z) / 3.0f;
  return y * y + 0.01f;
}

std::vector<float> relativeError(const recon::DenoiseResult& result, const Film& film) {
  std::vector<float> e(film.pixelCount());
  for (size_t p = 0; p < e.size(); ++p) {
    // The emission is added back unfiltered: its own variance of the mean adds to the error.
    const FilmPixel& px = film[p];
    const vec3 ev = px.emissionM2 * px.meanVarianceScale();
    e[p] = (result.mseEstimate[p] + (ev.x + ev.y + ev.z) / 3.0f) /
           relativeErrorRegulariser(result.output.pixels[p]);
  }
  return e;
}

std::vector<float> rawRelativeError(const Film& film) {
  std::vector<float> e(film.pixelCount());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, e.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t p = range.begin(); p < range.end(); ++p) {
          const vec3 v = film.estimateVarianceOfMean(p);
          e[p] = (v.x + v.y + v.z) / 3.0f / relativeErrorRegulariser(vec3(film.estimate(p)));
        }
      });
  return e;
}

double meanOf(const std::vector<float>& values) {
  double sum = 0;
  size_t used = 0;
  for (float v : values)
    if (std::isfinite(v)) {
      sum += v;
      ++used;
    }
  return used ? sum / double(used) : 0.0;
}

void addFilmMaps(Snapshot& snap, const Film& film) {
  if (!snap.withMaps) return;
  const size_t n = film.pixelCount();
  std::vector<float> albedo(3 * n), normal(3 * n), depth(n), emission(3 * n);
  // As FilmBuffers has them, read from the film (no copy of its buffers).
  const float depthScale = film.depthScale();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t p = r.begin(); p < r.end(); ++p) {
                        const FilmPixel& px = film[p];
                        for (int k = 0; k < 3; ++k) {
                          albedo[3 * p + k] = px.albedo[k];
                          normal[3 * p + k] = 0.5f + 0.5f * px.normal[k];
                          emission[3 * p + k] = px.emission[k];
                        }
                        depth[p] = px.depth * depthScale;
                      }
                    });
  snap.addMap(maps::Albedo, "albedo", std::move(albedo), MapLegend::rgb());
  snap.addMap(maps::Normal, "normal (0.5 + 0.5 n)", std::move(normal), MapLegend::rgb());
  const float depthTop = std::max(1e-3f, percentileOf(depth, 0.99f));
  snap.addMap(maps::Depth, "depth / mean depth", std::move(depth),
              MapLegend::sequential(0.0f, depthTop));
  snap.addMap(maps::Emission, "directly seen emission", std::move(emission), MapLegend::rgb());
  std::vector<float> raw = rawRelativeError(film);
  const float rawTop = std::max(1e-6f, percentileOf(raw, 0.99f));
  snap.addMap(maps::RawError, "raw relMSE (estimated)", std::move(raw),
              MapLegend::sequential(0.0f, rawTop));
}

void addFilterScaleMap(Snapshot& snap, const recon::DenoiseResult& result,
                       const recon::DenoiseConfig& config) {
  if (!snap.withMaps) return;
  std::vector<std::string> labels{"identity"};
  for (int r : config.radii) labels.push_back("r=" + std::to_string(r));
  snap.addMap(maps::FilterScale, "filter window", asFloats(result.scale),
              MapLegend::categorical(std::move(labels)));
}

void addReconstructionMaps(Snapshot& snap, const recon::DenoiseResult& result,
                           const recon::DenoiseConfig& config, const std::vector<float>& error) {
  if (!snap.withMaps) return;
  addFilterScaleMap(snap, result, config);
  const float top = std::max(1e-6f, percentileOf(error, 0.99f));
  snap.addMap(maps::ErrorEstimate, "relMSE (estimated, filtered)", error,
              MapLegend::sequential(0.0f, top));
}

}  // namespace penumbra
