// The networks as a control variate (issue 26, `--networks 1`): where a pixel's samples vary
// most, a small network (methods/bp/mdnet.h) is fitted to its neighbours' samples over their
// offsets, lens, time and light-sample coordinates; each later sample of the pixel then enters
// the film less the network's prediction for it, plus the network's mean over the pixel
// (regression-based Monte Carlo integration, Salauen et al. 2022).
//  - Unbiased: the network never saw the pixel's own samples (each pixel's samples come from
//    its own scramble), so E[f(x) - mean f] = 0 over the pixel's samples. Its mean is taken
//    over the pixel's footprint (a fixed Halton set) paired with the other dimensions of the
//    neighbours' samples (their distribution, e.g. the light's sampling density).
//  - The film's mean, variance and halves then describe the corrected samples: where the
//    network explains how a pixel's samples vary (a penumbra along the light's position, a
//    moving or defocused edge), their variance falls, and the reconstruction's SURE sees it.
//    A network that explains nothing only adds noise: it corrects the pixel's next samples only
//    while its error on the pixel's kept samples (which it was not fitted on) is at most
//    `maxHeldOut` of their variance. (Under the LD sampler those earlier samples and the next
//    ones share one scramble; the gate's dependence on them is the one departure from strict
//    independence.)
//  - The samples: each pixel that may feed a network keeps its first `capacity` samples with
//    their dimensions (half precision) and demodulated radiance, (L - emission) / (albedo +
//    0.01) each by its own first hit; the correction is remodulated by the sample's albedo.
//  - Which pixels train: the `share` of pixels whose samples vary most relative to their mean
//    (the film's per-sample variance of the filtered part over its mean squared); a pixel whose
//    network corrects keeps it. Only their neighbourhoods keep samples.
//  - A network retrains (warm) once its neighbourhood's samples grew by `growth`.
// Everything depends only on the samples and the configuration, never on the thread count.
#pragma once

#include "core/image.h"
#include "methods/bp/mdnet.h"
#include "methods/film.h"
#include "methods/progressive.h"
#include "methods/recon/denoise.h"
#include "scene/camera.h"
#include "trace/integrator.h"

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bp {

struct NetReconConfig {
  int reach = 2;            // the neighbourhood's radius: (2 reach + 1)^2 pixels
  float share = 0.03f;      // of the image's pixels, at most, train a network
  int capacity = 16;        // samples kept per pixel
  int hidden = 8;           // sigmoid units
  int epochs = 100;         // a first training; a warm retraining takes half
  float growth = 1.5f;      // retrain once the neighbourhood's samples grew this much
  float maxHeldOut = 0.5f;  // a network corrects while its held-out error is at most this
  int nodes = 64;           // Halton points the network is averaged over
};

// One kept sample: its inputs as half floats (offset from its pixel's centre, lens u, v, time,
// light chart s, t; each centred on 0) and its demodulated radiance.
struct NetSample {
  uint16_t in[mdnet::kMaxInputs];
  float target[3];
};

class NetRecon {
 public:
  NetRecon(int width, int height, bool lens, bool time, const NetReconConfig& config);

  // Keeps a sample of pixel (px, py) (index p) when that pixel stores and has room. Pixels may
  // be recorded from several threads, each pixel by one at a time.
  void record(size_t p, int px, int py, const CameraSample& cs, vec3 radiance,
              const PathFeatures& f);

  // Chooses the pixels that train from the film, stops keeping samples outside their
  // neighbourhoods, and (re)trains the networks that are due, first fits first (the widest
  // spreads first), within a budget: the run's training, in samples x epochs, stays within
  // `trainingPerRay` of the rays traced so far (`rays`), a count, so that the result never
  // depends on the machine's speed. Returns false when cancelled.
  bool train(const Film& film, uint64_t rays, const std::atomic<bool>* cancel);

  // What the film takes off a sample of pixel (px, py) (index p): the network's prediction for
  // it less its mean over the pixel, remodulated by the sample's albedo; 0 without a network
  // that corrects.
  // A network corrects at most an eighth as many samples as it was fitted on: its mean over the
  // pixel is itself an average over those samples, whose error every corrected sample carries;
  // so capped, that error stays below an eighth of the pixel's own variance and its share of
  // the pixel's mean falls as 1/n once the cap is reached (the estimate stays consistent).
  vec3 correction(size_t p, int px, int py, const CameraSample& cs, const PathFeatures& f);

  // A pixel's network, for the inspector.
  struct PixelNetwork {
    bool trained = false;   // it has a network that has been fitted
    bool corrects = false;  // which corrects its samples
    float heldOut = 0;      // its error on the pixel's kept samples over their variance
    uint32_t samples = 0;   // the neighbours' samples it was last fitted on
    uint32_t kept = 0;      // the pixel's own kept samples
    vec3 mean{0.0f};        // its mean over the pixel (demodulated)
  };
  PixelNetwork pixelNetwork(size_t p) const;

  // A fitted network along the input that matters most, against the samples: for the
  // inspector. The input's importance is how much the network's mean over the neighbourhood's
  // samples moves when that input alone is swept over its range (a partial dependence); the
  // curve and samples are demodulated luminances. None without a fitted network.
  std::optional<InspectedFit> fitAlong(size_t p) const;

  // What each pixel does for the networks (the `networks` map), or kRoleNone:
  //  kStores:   it keeps samples for a neighbour's network and has none of its own;
  //  kWaiting:  it has a network, not fitted yet (too few samples, or the budget);
  //  kHeldOut:  fitted, but its held-out error is above maxHeldOut: it corrects nothing;
  //  kCorrects: it corrects the pixel's samples;
  //  kCapped:   it corrected as many as it may; the samples enter raw until it retrains.
  enum Role : int { kStores = 0, kWaiting, kHeldOut, kCorrects, kCapped, kRoles };
  static constexpr int kRoleNone = -1;
  static std::vector<std::string> roleLabels();
  std::vector<float> roleMap() const;

  // Per pixel: 1 where a network corrects the samples, else 0.
  std::vector<float> trainedMap() const;
  // Per pixel: the network's held-out error on the pixel's own samples over their variance
  // (0 where none trained; below 1: it explains some of the pixel's spread).
  std::vector<float> heldOutMap() const;

  int inputs() const { return config_.inputs; }
  // The inputs' names, in order: "x offset", "y offset", ["lens u", "lens v",] ["time",]
  // "light s", "light t".
  std::vector<const char*> inputNames() const;
  size_t trainedPixels() const { return slots_.size() - freeSlots_.size(); }
  size_t correctingPixels() const;
  uint64_t fits() const { return fits_; }
  // Training allowed per traced ray, in samples x epochs. A sample-epoch of the fit costs about
  // 8 ns on one AVX-512 core (8 hidden units; docs/bp-method.md), a ray about 330 ns of a core
  // in the shipped scenes: 10 keeps the training near a fifth of the tracing's time.
  static constexpr double kTrainingPerRay = 5.0;
  size_t memoryBytes() const;

 private:
  void choose(const Film& film);
  // A sample's inputs (config_.inputs floats).
  void inputsOf(int px, int py, const CameraSample& cs, const PathFeatures& f, float* in) const;
  // Each due pixel's training inputs and targets (its neighbours' samples).
  void gather(const std::vector<uint32_t>& due, mdnet::Batch& batch) const;
  uint32_t neighbourhoodCount(size_t p) const;

  int width_, height_;
  bool lens_, time_;
  NetReconConfig settings_;
  mdnet::Config config_;
  std::vector<float> nodes_;                  // Halton points, config_.inputs floats each
  std::vector<std::vector<NetSample>> kept_;  // per pixel
  std::vector<uint8_t> storing_;              // per pixel: keeps samples
  std::vector<int32_t> slotOf_;               // per pixel: its network's slot, -1 none
  struct Slot {
    mdnet::Net net;
    uint32_t pixel = 0;
    uint32_t trainedAt = 0;  // neighbourhood samples at its last training (0: never)
    vec3 mean{0.0f};         // its mean over the nodes (demodulated)
    float heldOut = 0;
    bool corrects = false;
    uint32_t corrected = 0;  // samples it corrected
  };
  std::vector<Slot> slots_;
  std::vector<uint32_t> freeSlots_;
  uint64_t fits_ = 0;
  uint64_t trained_ = 0;  // samples x epochs trained so far
};

}  // namespace penumbra::bp
