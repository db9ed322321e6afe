#include "trace/preview.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Image renderPreview(const PreparedScene& prepared, uint64_t seed, int block) {
  block = std::max(1, block);
  const int w = prepared.scene.settings.width, h = prepared.scene.settings.height;
  Image image(w, h);
  enableFlushToZero();
  PixelSampler sampler(SamplerKind::LowDiscrepancy, seed, 1);
  PathCounters counters;
  for (int y0 = 0; y0 < h; y0 += block) {
    for (int x0 = 0; x0 < w; x0 += block) {
      const int x1 = std::min(w, x0 + block), y1 = std::min(h, y0 + block);
      CameraSample cs;
      cs.imageX = 0.5f * float(x0 + x1);
      cs.imageY = 0.5f * float(y0 + y1);
      sampler.startSample(x0, y0, 0);
      vec3 L = traceRadiance(prepared, cs, sampler, counters);
      if (!isFinite(L)) L = vec3(0.0f);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) image.at(x, y) = L;
    }
  }
  return image;
}

}  // namespace penumbra
