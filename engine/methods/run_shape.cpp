#include "methods/run_shape.h"

namespace penumbra {

RunShape RunShape::batch(int spp, uint64_t seed) {
  RunShape s;
  s.spp = spp;
  s.seed = seed;
  return s;
}

RunShape RunShape::progressive(int roundSpp, uint64_t seed, int spp) {
  RunShape s;
  s.openEnded = true;
  s.roundSpp = roundSpp;
  s.seed = seed;
  s.spp = spp;
  return s;
}

const ParamTable<RunShape>& runShapeParams() {
  static const ParamTable<RunShape> table = [] {
    constexpr unsigned all = kRenderCommand | kViewCommand | kCompareCommand | kReferenceCommand;
    constexpr unsigned runs = kRenderCommand | kViewCommand;
    ParamTable<RunShape> t;
    t.group("Run")
        .integer<uint64_t>("seed", "seed",
                           "Random seed: the image after each round depends only on it",
                           [](auto& s) -> auto& { return s.seed; }, 0, 9007199254740992.0, {0, 1e6})
        .field()
        .scope(runs | kReferenceCommand)
        .integer("spp", "target spp",
                 "Samples per pixel: a batch's budget, or where open-ended rounds stop (0: never; "
                 "default: the scene's render.spp, the viewer's 0)",
                 [](auto& s) -> auto& { return s.spp; }, 0, 1 << 24, {0, 4096})
        .field()
        .scope(all)
        .integer(
            "round-spp", "spp per round",
            "Open-ended rounds (the viewer, a time limit or noise threshold, equal time): kept "
            "samples per pixel each round adds",
            [](auto& s) -> auto& { return s.roundSpp; }, 1, 1024, {1, 16})
        .scope(runs | kCompareCommand)
        .choice<SamplerKind>("sampler", "sampler",
                             "Sample generator: ld (scrambled (0,2)-sequence) or independent",
                             [](auto& s) -> auto& { return s.sampler; }, {"ld", "independent"})
        .scope(runs | kCompareCommand)
        .real<double>(
            "time-limit", "time limit s",
            "Stop after the round in which this many seconds have passed (0: none; open-ended "
            "rounds, --spp, when given, still caps them). Such a run need not be deterministic",
            [](auto& s) -> auto& { return s.timeLimit; }, 0, 1e9, {0, 600})
        .field()
        .scope(runs)
        .real(
            "noise-threshold", "noise threshold",
            "Stop once the image's mean estimated relMSE (of the filtered image, for a method that "
            "filters) is below this (0: none); pixels below it get no more samples. Methods that "
            "estimate their error only",
            [](auto& s) -> auto& { return s.noiseThreshold; }, 0, 1e9, {0, 1})
        .field()
        .scope(runs);
    return t;
  }();
  return table;
}

std::string RunShape::validate() const {
  if (std::string problem = checkParams(runShapeParams().params(), *this); !problem.empty())
    return problem;
  if (!openEnded && spp < 1) return "--spp must be at least 1";
  return {};
}

}  // namespace penumbra
