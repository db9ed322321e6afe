// What the multidimensional networks (methods/bp/mdnet.h) would give on a real scene, before
// any selection: LD samples traced with their dimensions (the offset in the pixel, the lens
// point, the time, the first vertex's light chart), one network per pixel fitted to its
// neighbourhood's demodulated samples and averaged over the pixel and those dimensions, against
// the box mean, both scored against a reference. Also the per-pixel oracle of the two (what a
// perfect choice between them would give) and, with --bp, the same against another image (say
// `render --method bp` at the same spp). Writes the network's image with --out.
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

struct Traced {
  float in[mdnet::kMaxInputs];  // offset in the pixel (2), then lens (2), time, light chart (2)
  vec3 radiance, albedo, emission, direct;
  int lightObject = -1;
};

double mse(const Image& a, const Image& ref) {
  double sum = 0;
  for (size_t p = 0; p < ref.pixels.size(); ++p) {
    const vec3 d = a.pixels[p] - ref.pixels[p];
    sum += double(d.x * d.x + d.y * d.y + d.z * d.z) / 3.0;
  }
  return sum / double(ref.pixels.size());
}
}  // namespace

int main(int argc, char** argv) {
  std::string scenePath, referencePath, bpPath, outPath;
  int spp = 16, epochs = 200, hidden = 8, radius = 2, width = 0, height = 0, maxDepth = -1;
  bool own = true, atSamples = false;
  int directSpp = 0;
  bool perLight = false;
  uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--reference" && more)
      referencePath = argv[++i];
    else if (a == "--bp" && more)
      bpPath = argv[++i];
    else if (a == "--out" && more)
      outPath = argv[++i];
    else if (a == "--spp" && more)
      spp = std::max(1, std::atoi(argv[++i]));
    else if (a == "--epochs" && more)
      epochs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--hidden" && more)
      hidden = std::clamp(std::atoi(argv[++i]), 1, mdnet::kMaxHidden);
    else if (a == "--radius" && more)
      radius = std::clamp(std::atoi(argv[++i]), 1, 4);
    else if (a == "--per-light" && more)
      perLight = std::atoi(argv[++i]) != 0;
    else if (a == "--direct" && more)
      directSpp = std::max(0, std::atoi(argv[++i]));
    else if (a == "--max-depth" && more)
      maxDepth = std::atoi(argv[++i]);
    else if (a == "--at-samples" && more)
      atSamples = std::atoi(argv[++i]) != 0;
    else if (a == "--own" && more)
      own = std::atoi(argv[++i]) != 0;
    else if (a == "--seed" && more)
      seed = uint64_t(std::atoll(argv[++i]));
    else if (a == "--size" && more)
      std::sscanf(argv[++i], "%dx%d", &width, &height);
    else if (a.rfind("--", 0) != 0 && scenePath.empty())
      scenePath = a;
    else {
      std::fprintf(stderr,
                   "penumbra_bench_mdnet_scene: unknown or incomplete flag %s\nusage: %s "
                   "scene.json --reference ref.exr [--spp N] [--size WxH] [--epochs E] "
                   "[--hidden H] [--radius R] [--own 0|1] [--seed S] [--bp bp.exr] [--out F]\n",
                   a.c_str(), argv[0]);
      return 2;
    }
  }
  if (scenePath.empty() || (referencePath.empty() && directSpp == 0)) {
    std::fprintf(stderr, "penumbra_bench_mdnet_scene: a scene and --reference are needed\n");
    return 2;
  }
  try {
    Scene scene = loadScene(scenePath);
    if (width > 0 && height > 0) scene.settings.width = width, scene.settings.height = height;
    if (maxDepth >= 0) scene.settings.maxDepth = maxDepth;
    const auto prepared = prepareScene(std::move(scene));
    const int w = prepared->scene.settings.width, h = prepared->scene.settings.height;
    // With --direct N: everything is about the first vertex's next-event part, whose
    // reference is its mean over N samples a pixel of another seed.
    Image reference(w, h);
    if (directSpp > 0) {
      tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        PixelSampler sampler(SamplerKind::LowDiscrepancy, seed + 1000, uint32_t(directSpp));
        PathCounters counters;
        for (int y = rows.begin(); y != rows.end(); ++y)
          for (int x = 0; x < w; ++x) {
            glm::dvec3 sum(0.0);
            for (int i = 0; i < directSpp; ++i) {
              sampler.startSample(x, y, uint32_t(i));
              PathFeatures f;
              traceRadiance(*prepared, sampler.cameraSample(prepared->usesLens, prepared->usesTime),
                            sampler, counters, &f);
              if (isFinite(f.directLight)) sum += glm::dvec3(f.directLight);
            }
            reference.pixels[size_t(y) * size_t(w) + size_t(x)] = vec3(sum / double(directSpp));
          }
      });
    } else {
      reference = readImage(referencePath);
    }
    if (reference.width != w || reference.height != h)
      throw std::runtime_error(referencePath + ": not " + std::to_string(w) + "x" +
                               std::to_string(h));
    // The inputs: the offset, then the lens and the time where the scene uses them, then the
    // light chart.
    const bool lens = prepared->usesLens, time = prepared->usesTime;
    const int inputs = 2 + (lens ? 2 : 0) + (time ? 1 : 0) + 2;

    // 1. Trace.
    double start = now();
    std::vector<std::vector<Traced>> pixels(size_t(w) * size_t(h));
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      PixelSampler sampler(SamplerKind::LowDiscrepancy, seed, uint32_t(spp));
      PathCounters counters;
      for (int y = rows.begin(); y != rows.end(); ++y)
        for (int x = 0; x < w; ++x)
          for (int i = 0; i < spp; ++i) {
            sampler.startSample(x, y, uint32_t(i));
            const CameraSample cs = sampler.cameraSample(lens, time);
            PathFeatures f;
            const vec3 L = traceRadiance(*prepared, cs, sampler, counters, &f);
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
    const double traceSeconds = now() - start;

    // 2. Box means and the per-pixel albedo and emission means (the remodulation).
    const float epsilon = 0.01f;
    Image box(w, h), albedo(w, h), emission(w, h);
    for (size_t p = 0; p < pixels.size(); ++p) {
      glm::dvec3 l(0.0), a(0.0), e(0.0);
      for (const Traced& t : pixels[p])
        l += glm::dvec3(directSpp > 0 ? t.direct : t.radiance), a += glm::dvec3(t.albedo),
            e += glm::dvec3(directSpp > 0 ? vec3(0.0f) : t.emission);
      const double n = std::max<double>(1.0, double(pixels[p].size()));
      box.pixels[p] = vec3(l / n), albedo.pixels[p] = vec3(a / n), emission.pixels[p] = vec3(e / n);
    }

    // 3. One network per pixel on its neighbourhood's demodulated samples.
    mdnet::Config config;
    config.inputs = inputs;
    config.hidden = hidden;
    config.epochs = epochs;
    // With --per-light (and --direct), one network per pixel and light object, on the samples
    // that chose that light, weighted by the share of the neighbourhood's samples that did.
    std::vector<int> objects{-2};  // -2: all samples in one network
    if (perLight && directSpp > 0) {
      objects.clear();
      for (const auto& px : pixels)
        for (const Traced& t : px)
          if (t.lightObject >= 0 &&
              std::find(objects.begin(), objects.end(), t.lightObject) == objects.end())
            objects.push_back(t.lightObject);
    }
    const size_t perPixel = objects.size();
    std::vector<float> share(pixels.size() * perPixel, 0.0f);
    mdnet::Batch batch;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (size_t o = 0; o < perPixel; ++o) {
          size_t chosen = 0, all = 0;
          for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx) {
              const int qx = x + dx, qy = y + dy;
              if (qx < 0 || qy < 0 || qx >= w || qy >= h || (!own && dx == 0 && dy == 0)) continue;
              for (const Traced& t : pixels[size_t(qy) * size_t(w) + size_t(qx)]) {
                ++all;
                if (objects[o] != -2 && t.lightObject != objects[o]) continue;
                ++chosen;
                float in[mdnet::kMaxInputs];
                std::copy(t.in, t.in + mdnet::kMaxInputs, in);
                in[0] += float(dx), in[1] += float(dy);
                batch.inputs.insert(batch.inputs.end(), in, in + config.inputs);
                batch.targets.push_back(directSpp > 0
                                            ? t.direct / (t.albedo + epsilon)
                                            : (t.radiance - t.emission) / (t.albedo + epsilon));
              }
            }
          batch.offsets.push_back(uint32_t(batch.targets.size()));
          share[(size_t(y) * size_t(w) + size_t(x)) * perPixel + o] =
              all ? float(chosen) / float(all) : 0.0f;
        }
    std::vector<mdnet::Net> nets(size_t(w) * size_t(h) * perPixel);
    std::vector<mdnet::Net*> pointers;
    for (size_t p = 0; p < nets.size(); ++p) {
      mdnet::init(nets[p], config, p);
      pointers.push_back(&nets[p]);
    }
    start = now();
    mdnet::fitBatch(config, pointers, batch);
    const double fitSeconds = now() - start;
    std::vector<float> lo(size_t(config.inputs), -0.5f), hi(size_t(config.inputs), 0.5f);
    const std::vector<float> nodes = mdnet::haltonPoints(config.inputs, 256, lo, hi);
    Image network(w, h), oracle(w, h);
    for (size_t p = 0; p < pixels.size(); ++p) {
      if (atSamples && !pixels[p].empty()) {
        // The network at the pixel's own samples' points, each remodulated by its own albedo
        // and emission: no product of means where albedo and lighting change together.
        glm::dvec3 sum(0.0);
        for (const Traced& t : pixels[p])
          sum +=
              glm::dvec3((directSpp > 0 ? vec3(0.0f) : t.emission) +
                         (t.albedo + epsilon) * mdnet::predict(nets[p * perPixel], config, t.in));
        network.pixels[p] = vec3(sum / double(pixels[p].size()));
      } else {
        vec3 f(0.0f);
        for (size_t o = 0; o < perPixel; ++o)
          f += (perPixel > 1 ? share[p * perPixel + o] : 1.0f) *
               mdnet::average(nets[p * perPixel + o], config, nodes);
        network.pixels[p] = emission.pixels[p] + (albedo.pixels[p] + epsilon) * f;
      }
      const vec3 dn = network.pixels[p] - reference.pixels[p],
                 db = box.pixels[p] - reference.pixels[p];
      oracle.pixels[p] = glm::dot(dn, dn) < glm::dot(db, db) ? network.pixels[p] : box.pixels[p];
    }
    std::printf("%s at %dx%d, %d spp, %d inputs (%s), %d hidden, %d epochs, radius %d%s\n",
                scenePath.c_str(), w, h, spp, config.inputs,
                lens && time ? "offset, lens, time, light chart"
                : lens       ? "offset, lens, light chart"
                : time       ? "offset, time, light chart"
                             : "offset, light chart",
                hidden, epochs, radius, own ? "" : ", neighbours' samples only");
    std::printf("trace %.1f s, fit %.1f s (%.2f ms a pixel of CPU)\n", traceSeconds, fitSeconds,
                fitSeconds * 2e3 / double(nets.size()));
    const double boxMse = mse(box, reference);
    std::printf("box        MSE %.4e\n", boxMse);
    std::printf("network    MSE %.4e (%.2fx box)\n", mse(network, reference),
                mse(network, reference) / boxMse);
    std::printf("oracle     MSE %.4e (%.2fx box): the better of the two per pixel\n",
                mse(oracle, reference), mse(oracle, reference) / boxMse);
    if (!bpPath.empty()) {
      const Image bp = readImage(bpPath);
      Image both(w, h);
      for (size_t p = 0; p < pixels.size(); ++p) {
        const vec3 dn = network.pixels[p] - reference.pixels[p],
                   db = bp.pixels[p] - reference.pixels[p];
        both.pixels[p] = glm::dot(dn, dn) < glm::dot(db, db) ? network.pixels[p] : bp.pixels[p];
      }
      std::printf("other      MSE %.4e (%.2fx box): %s\n", mse(bp, reference),
                  mse(bp, reference) / boxMse, bpPath.c_str());
      std::printf("oracle     MSE %.4e (%.2fx box): the better of it and the network per pixel\n",
                  mse(both, reference), mse(both, reference) / boxMse);
    }
    if (!outPath.empty()) writeImage(outPath, network);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_bench_mdnet_scene: %s\n", e.what());
    return 1;
  }
  return 0;
}
