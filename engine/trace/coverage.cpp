#include "trace/coverage.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace penumbra {

std::vector<float> cameraCoverage(const PreparedScene& prepared, int raysPerSide) {
  const int w = prepared.scene.settings.width, h = prepared.scene.settings.height;
  const int n = std::max(1, raysPerSide);
  std::vector<float> alpha(size_t(w) * size_t(h), 0.0f);
  tbb::parallel_for(0, h, [&](int y) {
    enableFlushToZero();
    for (int x = 0; x < w; ++x) {
      int hits = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          // Stratum (i, j) of the pixel; the lens and the shutter walk the strata in other
          // orders, so that the rays spread over all five dimensions.
          CameraSample cs;
          cs.imageX = float(x) + (float(i) + 0.5f) / float(n);
          cs.imageY = float(y) + (float(j) + 0.5f) / float(n);
          cs.lensU = (float(j) + 0.5f) / float(n);
          cs.lensV = (float((i + j) % n) + 0.5f) / float(n);
          cs.time = (float(j * n + i) + 0.5f) / float(n * n);
          Hit hit;
          if (prepared.accel->intersect(generateRay(prepared.camera, cs), 0.0f, INFINITY, hit))
            ++hits;
        }
      alpha[size_t(y) * size_t(w) + size_t(x)] = float(hits) / float(n * n);
    }
  });
  return alpha;
}

}  // namespace penumbra
