// The BP method's per-pixel sums, slice statistics and sample reservoirs.
#include "methods/bp/pixel_store.h"

#include "core/rng.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace penumbra::bp {

namespace {
// Keeps the reservoirs' random stream apart from the method's others.
constexpr uint64_t kReservoirSalt = 0x7265736572766fULL;
}  // namespace

StoredSample makeStoredSample(const CameraSample& cs, int px, int py, vec3 radiance,
                              const ToneMap& tone, int slicesPerSide) {
  StoredSample s;
  const float ox = cs.imageX - float(px), oy = cs.imageY - float(py);
  s.dx = ox - 0.5f;
  s.dy = oy - 0.5f;
  s.u = cs.lensU;
  s.v = cs.lensV;
  s.t = cs.time;
  s.radiance = radiance;
  s.value = tone.value(radiance);
  s.slice = uint8_t(sliceOf(ox, oy, slicesPerSide));
  return s;
}

void PixelStore::resize(size_t pixelCount) {
  pixels.resize(pixelCount);
  reservoirs.resize(pixelCount);
  slices.resize(pixelCount * slicesPerPixel);
  sliceSumL.resize(pixelCount * slicesPerPixel, glm::dvec3(0.0));
}

void PixelStore::keep(size_t p, const StoredSample& s, const ToneMap& tone) {
  PixelState& state = pixels[p];
  ++state.kept;
  state.sumL += glm::dvec3(s.radiance);
  state.sumT += glm::dvec3(tone.apply(s.radiance));
  slices[p * slicesPerPixel + s.slice].add(s.value, histogramLevels);
  sliceSumL[p * slicesPerPixel + s.slice] += glm::dvec3(s.radiance);
  std::vector<StoredSample>& reservoir = reservoirs[p];
  if (reservoir.size() < reservoirLimit) {
    if (reservoir.size() == reservoir.capacity())
      reservoir.reserve(std::min(reservoirLimit, std::max<size_t>(8, 2 * reservoir.size())));
    reservoir.push_back(s);
    return;
  }
  // Reservoir sampling (Algorithm R): the kept set is a uniform subsample of all.
  Pcg32 rng(hashValues(seed, p, kReservoirSalt), state.kept);
  const uint64_t j = (uint64_t(rng.nextUint()) * state.kept) >> 32;
  if (j < reservoirLimit) reservoir[j] = s;
}

vec3 PixelStore::estimate(size_t p, bool stratified) const {
  const PixelState& s = pixels[p];
  if (s.kept == 0) return vec3(0.0f);
  if (!stratified) return vec3(s.sumL / double(s.kept));
  glm::dvec3 sum(0.0);
  int nonEmpty = 0;
  for (int i = 0; i < slicesPerPixel; ++i) {
    const uint32_t n = slices[p * slicesPerPixel + i].count;
    if (n == 0) continue;
    sum += sliceSumL[p * slicesPerPixel + i] / double(n);
    ++nonEmpty;
  }
  return vec3(sum / double(nonEmpty));
}

Image PixelStore::estimateImage(int width, int height, bool stratified) const {
  Image image(width, height);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t p = range.begin(); p < range.end(); ++p)
                        image.pixels[p] = estimate(p, stratified);
                    });
  return image;
}

size_t PixelStore::memoryBytes() const {
  size_t bytes = pixels.capacity() * sizeof(PixelState) +
                 reservoirs.capacity() * sizeof(std::vector<StoredSample>) +
                 slices.capacity() * sizeof(SliceStats) + sliceSumL.capacity() * sizeof(glm::dvec3);
  for (const auto& r : reservoirs) bytes += r.capacity() * sizeof(StoredSample);
  return bytes;
}

}  // namespace penumbra::bp
