// The BP method's slot allocation, slice order and candidate choice.
#include "methods/bp/candidates.h"

#include "methods/bp/paper.h"
#include "methods/bp/state.h"
#include "methods/bp/trainer.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::bp {

namespace {

// Order in which a pixel's slices receive this round's samples: with warping, C's own
// sample, then B's sample mirrored into C, then the other slices; a partial group (the
// budget's remainder) takes a prefix. Each entry: (target slice, mirrored-from or -1).
std::vector<std::pair<int, int>> slotOrder(const SliceChoice& choice, int slicesPerPixel) {
  std::vector<std::pair<int, int>> order;
  if (choice.warp && choice.b >= 0) {
    order.push_back({choice.c, -1});
    order.push_back({choice.c, choice.b});
    for (int s = 0; s < slicesPerPixel; ++s)
      if (s != choice.b && s != choice.c) order.push_back({s, -1});
  } else {
    for (int s = 0; s < slicesPerPixel; ++s) order.push_back({s, -1});
  }
  return order;
}

// Starts draw `index` of pixel (px, py) with its image offset placed at local position
// (from the sampler's own offset) inside `target`, mirrored from `mirrorFrom` when >= 0.
CameraSample drawCandidate(const BpState& state, PixelSampler& sampler, int px, int py,
                           uint32_t index, int target, int mirrorFrom) {
  sampler.startSample(px, py, index);
  CameraSample cs = sampler.cameraSample(state.prepared.usesLens, state.prepared.usesTime);
  glm::vec2 local(cs.imageX - float(px), cs.imageY - float(py));
  const int S = state.config.slicesPerSide;
  if (mirrorFrom >= 0) local = mirrorIntoSlice(local, mirrorFrom, target, S);
  const glm::vec2 offset = sliceToPixel(local, target, S);
  // Offsets stay inside the pixel even where float rounding reaches 1.
  cs.imageX = float(px) + std::min(offset.x, 0x1.fffffep-1f);
  cs.imageY = float(py) + std::min(offset.y, 0x1.fffffep-1f);
  return cs;
}

}  // namespace

std::vector<uint32_t> allocateSlots(std::span<const uint32_t> order, size_t pixelCount,
                                    uint64_t budget, int slotsPerPixel) {
  std::vector<uint32_t> slots(pixelCount, 0);
  if (order.empty() || budget == 0) return slots;
  const uint64_t perPass = uint64_t(order.size()) * slotsPerPixel;
  const uint64_t passes = budget / perPass;
  uint64_t rest = budget - passes * perPass;
  for (uint32_t p : order) {
    uint64_t n = passes * slotsPerPixel;
    const uint64_t extra = std::min<uint64_t>(rest, slotsPerPixel);
    n += extra;
    rest -= extra;
    slots[p] = uint32_t(n);
  }
  return slots;
}

uint64_t samplePixel(BpState& state, const BpPaperConfig& config, uint32_t p, uint32_t slotCount,
                     const SliceChoice& choice, PixelSampler& sampler, PathCounters& counters,
                     uint64_t& nonFinite) {
  const PreparedScene& prepared = state.prepared;
  const int px = int(p % state.width), py = int(p / state.width);
  PixelState& pixel = state.pixel(p);
  const auto order = slotOrder(choice, state.slicesPerPixel);
  uint64_t used = 0;
  std::vector<float> sliceValues;
  float x[kMaxNetInputs];
  auto stored = [&](const CameraSample& cs, vec3 L) {
    return makeStoredSample(cs, px, py, L, state.tone, config.slicesPerSide);
  };
  // Only the inspected pixel records its candidates, and only one thread samples a pixel.
  const bool record = int64_t(p) == state.inspected;
  std::vector<InspectedCandidate>& recorded = state.inspectedCandidates;
  auto recordCandidate = [&](const CameraSample& cs, float value, double score, int target,
                             int from) {
    if (!record) return;
    recorded.push_back(
        {cs.imageX - float(px), cs.imageY - float(py), value, float(score), target, from, false});
  };
  for (uint32_t slot = 0; slot < slotCount; ++slot) {
    const auto [target, from] = order[slot % order.size()];
    sliceValues.clear();
    for (const StoredSample& s : state.store.reservoirs[p])
      if (s.slice == target) sliceValues.push_back(s.value);
    const bool score = config.outlierRemoval && !sliceValues.empty();
    const int candidates = score ? config.candidates : 1;

    if (config.candidateMode == CandidateMode::Traced || !score) {
      // (B): trace every candidate, keep the one closest to the slice (eq. 16).
      bool have = false;
      double best = 0.0;
      StoredSample bestSample{};
      size_t bestRecord = recorded.size();
      for (int c = 0; c < candidates; ++c) {
        const CameraSample cs = drawCandidate(state, sampler, px, py, pixel.drawn++, target, from);
        const vec3 L = traceRadiance(prepared, cs, sampler, counters);
        ++pixel.traced;
        if (!isFinite(L)) {
          ++nonFinite;
          continue;
        }
        const StoredSample s = stored(cs, L);
        const double sc = candidateScore(sliceValues, s.value, config.candidateEpsilon);
        if (!have || sc < best) {
          have = true;
          best = sc;
          bestSample = s;
          bestRecord = recorded.size();
        }
        recordCandidate(cs, s.value, sc, target, from);
      }
      if (have) state.store.keep(p, bestSample, state.tone);
      if (record && have) recorded[bestRecord].kept = true;
      ++used;  // a slot whose candidates were all non-finite is spent and dropped
      continue;
    }
    // (A): score candidates by the network's prediction, trace only the best.
    double best = 0.0;
    uint32_t bestIndex = 0;
    for (int c = 0; c < candidates; ++c) {
      const uint32_t index = pixel.drawn++;
      const CameraSample cs = drawCandidate(state, sampler, px, py, index, target, from);
      networkInputs(config.network.inputs, cs.imageX - px - 0.5f, cs.imageY - py - 0.5f, cs.lensU,
                    cs.lensV, cs.time, x);
      const float v = luminance(predict(state.nets[p], config.network, x));
      const double sc = candidateScore(sliceValues, v, config.candidateEpsilon);
      if (c == 0 || sc < best) {
        best = sc;
        bestIndex = index;
      }
      recordCandidate(cs, v, sc, target, from);
    }
    const size_t predictedFirst = recorded.size() - (record ? candidates : 0);
    const CameraSample cs = drawCandidate(state, sampler, px, py, bestIndex, target, from);
    const vec3 L = traceRadiance(prepared, cs, sampler, counters);
    ++pixel.traced;
    if (!isFinite(L)) {
      ++nonFinite;
      ++used;
      continue;
    }
    const StoredSample s = stored(cs, L);
    double mean = 0.0;
    for (float v : sliceValues) mean += v;
    mean /= double(sliceValues.size());
    if (std::abs(s.value - mean) / (mean + config.candidateEpsilon) > config.outlierTau) {
      ++state.counters.rejected;
      continue;
    }
    state.store.keep(p, s, state.tone);
    if (record) recorded[predictedFirst + (bestIndex + candidates - pixel.drawn)].kept = true;
    ++used;
  }
  return used;
}

}  // namespace penumbra::bp
