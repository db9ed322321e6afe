// What the multidimensional networks (methods/bp/mdnet.h) would give on a real scene, before
// any selection: LD samples traced with their dimensions (the offset in the pixel, the lens
// point, the time, the first vertex's light chart), one network per pixel fitted to its
// neighbourhood's demodulated samples and averaged over the pixel and those dimensions, against
// the box mean, both scored against a reference. Also the per-pixel oracle of the two (what a
// perfect choice between them would give) and, with --bp, the same against another image (say
// `render --method bp` at the same spp). The per-pixel oracle over-states what a selection could
// take: of two estimates with independent errors the smaller is always below either on average,
// luck included. So, with --bp, also the oracle that chooses by the true squared error averaged
// over each pixel's (2r + 1)^2 box (r = 2, 5; the reconstruction's SURE maps are smoothed over
// r = 5): what a selection whose score were exact but as smooth as SURE's could take. Writes
// the network's image with --out.
//
// Usage: penumbra_bench_mdnet_scene scene.json --reference ref.exr [--spp 16] [--size WxH]
//        [--epochs 200] [--hidden 8] [--radius 2] [--own 0|1] [--at-samples 0|1] [--seed S]
//        [--max-depth D] [--direct N [--per-light 1]] [--bp bp.exr] [--out net.pfm]
// --direct N scores the first vertex's next-event part alone (PathFeatures::directLight), the
// part the light chart explains, against its own mean over N samples a pixel of another seed.
// --at-samples 1 averages the network at the pixel's own samples' points, each remodulated by
// its own albedo and emission, instead of over a fixed set with the pixel's mean albedo.
#include "core/image_io.h"
#include "methods/bp/mdnet.h"
#include "scene/scene_loader.h"
#include "trace/integrator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace penumbra;

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Options {
  std::string scene, reference, other, out;
  int spp = 16, epochs = 200, hidden = 8, radius = 2, width = 0, height = 0, maxDepth = -1;
  int directSpp = 0;  // > 0: score the next-event part against its mean over this many samples
  bool own = true, atSamples = false, perLight = false;
  uint64_t seed = 1;
};

// False (after a message) on a bad command line.
bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    auto number = [&] { return std::atoi(argv[++i]); };
    if (a == "--reference" && more)
      o.reference = argv[++i];
    else if (a == "--bp" && more)
      o.other = argv[++i];
    else if (a == "--out" && more)
      o.out = argv[++i];
    else if (a == "--spp" && more)
      o.spp = std::max(1, number());
    else if (a == "--epochs" && more)
      o.epochs = std::max(1, number());
    else if (a == "--hidden" && more)
      o.hidden = std::clamp(number(), 1, mdnet::kMaxHidden);
    else if (a == "--radius" && more)
      o.radius = std::clamp(number(), 1, 4);
    else if (a == "--own" && more)
      o.own = number() != 0;
    else if (a == "--at-samples" && more)
      o.atSamples = number() != 0;
    else if (a == "--per-light" && more)
      o.perLight = number() != 0;
    else if (a == "--direct" && more)
      o.directSpp = std::max(0, number());
    else if (a == "--max-depth" && more)
      o.maxDepth = number();
    else if (a == "--seed" && more)
      o.seed = uint64_t(std::atoll(argv[++i]));
    else if (a == "--size" && more)
      std::sscanf(argv[++i], "%dx%d", &o.width, &o.height);
    else if (a.rfind("--", 0) != 0 && o.scene.empty())
      o.scene = a;
    else {
      std::fprintf(stderr, "penumbra_bench_mdnet_scene: unknown or incomplete flag %s\n",
                   a.c_str());
      return false;
    }
  }
  if (o.scene.empty() || (o.reference.empty() && o.directSpp == 0)) {
    std::fprintf(stderr,
                 "penumbra_bench_mdnet_scene: a scene and --reference (or --direct N) "
                 "are needed\n");
    return false;
  }
  return true;
}

struct Traced {
  float in[mdnet::kMaxInputs];  // offset in the pixel (2), then lens (2), time, light chart (2)
  vec3 radiance, albedo, emission, direct;
  int lightObject = -1;
};
using Pixels = std::vector<std::vector<Traced>>;

// Every pixel's LD samples with their dimensions.
Pixels trace(const PreparedScene& prepared, const Options& o) {
  const int w = prepared.scene.settings.width, h = prepared.scene.settings.height;
  const bool lens = prepared.usesLens, time = prepared.usesTime;
  Pixels pixels(size_t(w) * size_t(h));
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    PixelSampler sampler(SamplerKind::LowDiscrepancy, o.seed, uint32_t(o.spp));
    PathCounters counters;
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x)
        for (int i = 0; i < o.spp; ++i) {
          sampler.startSample(x, y, uint32_t(i));
          const CameraSample cs = sampler.cameraSample(lens, time);
          PathFeatures f;
          const vec3 L = traceRadiance(prepared, cs, sampler, counters, &f);
          if (!isFinite(L)) continue;
          Traced t;
          int k = 0;
          t.in[k++] = cs.imageX - float(x) - 0.5f;
          t.in[k++] = cs.imageY - float(y) - 0.5f;
          if (lens) t.in[k++] = cs.lensU - 0.5f, t.in[k++] = cs.lensV - 0.5f;
          if (time) t.in[k++] = cs.time - 0.5f;
          t.in[k++] = f.lightChart.x - 0.5f;
          t.in[k++] = f.lightChart.y - 0.5f;
          t.radiance = L;
          t.albedo = f.albedo;
          t.emission = f.emission;
          t.direct = f.directLight;
          t.lightObject = f.lightObject;
          pixels[size_t(y) * size_t(w) + size_t(x)].push_back(t);
        }
  });
  return pixels;
}

// The first vertex's next-event part, its mean over `spp` samples a pixel of another seed.
Image directReference(const PreparedScene& prepared, const Options& o) {
  const int w = prepared.scene.settings.width, h = prepared.scene.settings.height;
  Image reference(w, h);
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    PixelSampler sampler(SamplerKind::LowDiscrepancy, o.seed + 1000, uint32_t(o.directSpp));
    PathCounters counters;
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        glm::dvec3 sum(0.0);
        for (int i = 0; i < o.directSpp; ++i) {
          sampler.startSample(x, y, uint32_t(i));
          PathFeatures f;
          traceRadiance(prepared, sampler.cameraSample(prepared.usesLens, prepared.usesTime),
                        sampler, counters, &f);
          if (isFinite(f.directLight)) sum += glm::dvec3(f.directLight);
        }
        reference.pixels[size_t(y) * size_t(w) + size_t(x)] = vec3(sum / double(o.directSpp));
      }
  });
  return reference;
}

constexpr float kEpsilon = 0.01f;  // demodulation: (radiance - emission) / (albedo + epsilon)

// The networks' training data: per pixel, one entry per light object (with --per-light and
// --direct; otherwise one), and each entry's share of its neighbourhood's samples.
struct Training {
  mdnet::Batch batch;
  std::vector<int> objects{-2};  // -2: every sample in one network
  std::vector<float> share;      // pixel x objects
};

Training gather(const Pixels& pixels, int w, int h, int inputs, const Options& o) {
  Training t;
  if (o.perLight && o.directSpp > 0) {
    t.objects.clear();
    for (const auto& px : pixels)
      for (const Traced& s : px)
        if (s.lightObject >= 0 &&
            std::find(t.objects.begin(), t.objects.end(), s.lightObject) == t.objects.end())
          t.objects.push_back(s.lightObject);
  }
  const size_t perPixel = t.objects.size();
  t.share.assign(pixels.size() * perPixel, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (size_t k = 0; k < perPixel; ++k) {
        size_t chosen = 0, all = 0;
        for (int dy = -o.radius; dy <= o.radius; ++dy)
          for (int dx = -o.radius; dx <= o.radius; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h || (!o.own && dx == 0 && dy == 0)) continue;
            for (const Traced& s : pixels[size_t(qy) * size_t(w) + size_t(qx)]) {
              ++all;
              if (t.objects[k] != -2 && s.lightObject != t.objects[k]) continue;
              ++chosen;
              float in[mdnet::kMaxInputs];
              std::copy(s.in, s.in + mdnet::kMaxInputs, in);
              in[0] += float(dx), in[1] += float(dy);
              t.batch.inputs.insert(t.batch.inputs.end(), in, in + inputs);
              t.batch.targets.push_back(o.directSpp > 0
                                            ? s.direct / (s.albedo + kEpsilon)
                                            : (s.radiance - s.emission) / (s.albedo + kEpsilon));
            }
          }
        t.batch.offsets.push_back(uint32_t(t.batch.targets.size()));
        t.share[(size_t(y) * size_t(w) + size_t(x)) * perPixel + k] =
            all ? float(chosen) / float(all) : 0.0f;
      }
  return t;
}

double mse(const Image& a, const Image& ref) {
  double sum = 0;
  for (size_t p = 0; p < ref.pixels.size(); ++p) {
    const vec3 d = a.pixels[p] - ref.pixels[p];
    sum += double(d.x * d.x + d.y * d.y + d.z * d.z) / 3.0;
  }
  return sum / double(ref.pixels.size());
}

// The per-pixel squared errors of an image (mean over channels).
std::vector<double> squaredErrors(const Image& a, const Image& ref) {
  std::vector<double> e(ref.pixels.size());
  for (size_t p = 0; p < e.size(); ++p) {
    const vec3 d = a.pixels[p] - ref.pixels[p];
    e[p] = double(d.x * d.x + d.y * d.y + d.z * d.z) / 3.0;
  }
  return e;
}

// Each value's mean over its (2r + 1)^2 box, clipped to the image.
std::vector<double> boxMeanOf(const std::vector<double>& v, int w, int h, int r) {
  std::vector<double> out(v.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      int count = 0;
      for (int qy = std::max(0, y - r); qy <= std::min(h - 1, y + r); ++qy)
        for (int qx = std::max(0, x - r); qx <= std::min(w - 1, x + r); ++qx, ++count)
          sum += v[size_t(qy) * size_t(w) + size_t(qx)];
      out[size_t(y) * size_t(w) + size_t(x)] = sum / count;
    }
  return out;
}

// The MSE of choosing, per pixel, whichever of a and b has the smaller true squared error
// averaged over the pixel's (2r + 1)^2 box.
double smoothedOracleMse(const Image& a, const Image& b, const Image& ref, int r) {
  const std::vector<double> ea = squaredErrors(a, ref), eb = squaredErrors(b, ref);
  const std::vector<double> sa = boxMeanOf(ea, ref.width, ref.height, r),
                            sb = boxMeanOf(eb, ref.width, ref.height, r);
  double sum = 0;
  for (size_t p = 0; p < ea.size(); ++p) sum += sa[p] < sb[p] ? ea[p] : eb[p];
  return sum / double(ea.size());
}

// Per pixel, the better of two images by the true error: an upper bound for a selection.
Image oracle(const Image& a, const Image& b, const Image& reference) {
  Image out(reference.width, reference.height);
  for (size_t p = 0; p < out.pixels.size(); ++p) {
    const vec3 da = a.pixels[p] - reference.pixels[p], db = b.pixels[p] - reference.pixels[p];
    out.pixels[p] = glm::dot(da, da) < glm::dot(db, db) ? a.pixels[p] : b.pixels[p];
  }
  return out;
}

int run(const Options& o) {
  Scene scene = loadScene(o.scene);
  if (o.width > 0 && o.height > 0) scene.settings.width = o.width, scene.settings.height = o.height;
  if (o.maxDepth >= 0) scene.settings.maxDepth = o.maxDepth;
  const auto prepared = prepareScene(std::move(scene));
  const int w = prepared->scene.settings.width, h = prepared->scene.settings.height;
  const Image reference = o.directSpp > 0 ? directReference(*prepared, o) : readImage(o.reference);
  if (reference.width != w || reference.height != h)
    throw std::runtime_error(o.reference + ": not " + std::to_string(w) + "x" + std::to_string(h));
  const bool lens = prepared->usesLens, time = prepared->usesTime;
  double start = now();
  const Pixels pixels = trace(*prepared, o);
  const double traceSeconds = now() - start;

  // The box means, and the per-pixel albedo and emission means that remodulate the networks.
  Image box(w, h), albedo(w, h), emission(w, h);
  for (size_t p = 0; p < pixels.size(); ++p) {
    glm::dvec3 l(0.0), a(0.0), e(0.0);
    for (const Traced& t : pixels[p])
      l += glm::dvec3(o.directSpp > 0 ? t.direct : t.radiance), a += glm::dvec3(t.albedo),
          e += glm::dvec3(o.directSpp > 0 ? vec3(0.0f) : t.emission);
    const double n = std::max<double>(1.0, double(pixels[p].size()));
    box.pixels[p] = vec3(l / n), albedo.pixels[p] = vec3(a / n), emission.pixels[p] = vec3(e / n);
  }

  mdnet::Config config;
  config.inputs = 2 + (lens ? 2 : 0) + (time ? 1 : 0) + 2;
  config.hidden = o.hidden;
  config.epochs = o.epochs;
  const Training training = gather(pixels, w, h, config.inputs, o);
  const size_t perPixel = training.objects.size();
  std::vector<mdnet::Net> nets(pixels.size() * perPixel);
  std::vector<mdnet::Net*> pointers;
  for (size_t j = 0; j < nets.size(); ++j) {
    mdnet::init(nets[j], config, j);
    pointers.push_back(&nets[j]);
  }
  start = now();
  mdnet::fitBatch(config, pointers, training.batch);
  const double fitSeconds = now() - start;
  const std::vector<float> lo(size_t(config.inputs), -0.5f), hi(size_t(config.inputs), 0.5f);
  const std::vector<float> nodes = mdnet::haltonPoints(config.inputs, 256, lo, hi);
  Image network(w, h);
  for (size_t p = 0; p < pixels.size(); ++p) {
    if (o.atSamples && !pixels[p].empty()) {
      // At the pixel's own samples' points, each remodulated by its own albedo and emission.
      glm::dvec3 sum(0.0);
      for (const Traced& t : pixels[p])
        sum += glm::dvec3((o.directSpp > 0 ? vec3(0.0f) : t.emission) +
                          (t.albedo + kEpsilon) * mdnet::predict(nets[p * perPixel], config, t.in));
      network.pixels[p] = vec3(sum / double(pixels[p].size()));
      continue;
    }
    vec3 f(0.0f);
    for (size_t k = 0; k < perPixel; ++k)
      f += (perPixel > 1 ? training.share[p * perPixel + k] : 1.0f) *
           mdnet::average(nets[p * perPixel + k], config, nodes);
    network.pixels[p] = emission.pixels[p] + (albedo.pixels[p] + kEpsilon) * f;
  }
  std::printf(
      "%s at %dx%d, %d spp, %d inputs (offset%s%s, light chart), %d hidden, %d epochs, "
      "radius %d%s%s\n",
      o.scene.c_str(), w, h, o.spp, config.inputs, lens ? ", lens" : "", time ? ", time" : "",
      o.hidden, o.epochs, o.radius, o.own ? "" : ", neighbours' samples only",
      o.directSpp > 0 ? ", the next-event part alone" : "");
  std::printf("trace %.1f s, fit %.1f s\n", traceSeconds, fitSeconds);
  const double boxMse = mse(box, reference), netMse = mse(network, reference);
  const double bestOf = mse(oracle(network, box, reference), reference);
  std::printf("box        MSE %.4e\n", boxMse);
  std::printf("network    MSE %.4e (%.2fx box)\n", netMse, netMse / boxMse);
  std::printf("oracle     MSE %.4e (%.2fx box): the better of the two per pixel\n", bestOf,
              bestOf / boxMse);
  if (!o.other.empty()) {
    const Image other = readImage(o.other);
    const double otherMse = mse(other, reference);
    const double both = mse(oracle(network, other, reference), reference);
    std::printf("other      MSE %.4e (%.2fx box): %s\n", otherMse, otherMse / boxMse,
                o.other.c_str());
    std::printf("oracle     MSE %.4e (%.2fx box): the better of it and the network per pixel\n",
                both, both / boxMse);
    for (int r : {2, 5}) {
      const double smoothed = smoothedOracleMse(network, other, reference, r);
      std::printf("oracle     MSE %.4e (%.3fx it): by the true error over %dx%d boxes\n", smoothed,
                  smoothed / otherMse, 2 * r + 1, 2 * r + 1);
    }
  }
  if (!o.out.empty()) writeImage(o.out, network);
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) return 2;
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_bench_mdnet_scene: %s\n", e.what());
    return 1;
  }
}
