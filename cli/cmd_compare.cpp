// `penumbra compare`: renders one scene with several methods under the fair-comparison
// protocol of ALGORITHM.md §11 (same integrator, same LD sampler, fixed seeds, equal kept
// spp or equal wall time) and writes the report (report/report.h): report.html,
// report.md, results.json, results.csv, curves.csv and the images. Every run also gets a
// time-to-quality curve, measured at checkpoints during the run (see runOnce).
//
// A method entry is NAME[:MODIFIER...][@SPP]: NAME one of methodNames(); modifiers
// `paper`, `tuned` (BP presets) and `raw` (the estimate before reconstruction, e.g. the
// paper's "ours, sampling only"); @SPP overrides --spp for that entry (the "LD at 64 spp"
// of E3). Examples: ld,gem,bp:tuned,ld@64.
#include "cli/commands.h"
#include "cli/compare.h"
#include "cli/method_options.h"
#include "cli/scene_options.h"
#include "core/image_io.h"
#include "core/large_pages.h"
#include "eval/metrics.h"
#include "eval/reference.h"
#include "methods/factory.h"
#include "methods/render.h"
#include "report/report.h"
#include "trace/integrator.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

namespace penumbra {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

int parsePositive(const std::string& what, const std::string& text) {
  size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || v < 1)
    throw CommandError(what + ": expected a positive whole number, got '" + text + "'");
  return v;
}

}  // namespace

namespace {

// What an entry's modifiers may be, for messages: "raw for any method; consistent, paper, tuned
// for bp; filtered for ld; NAME=VALUE for any of the method's parameters".
std::string modifierHelp(const MethodRegistry& registry) {
  std::string text = "raw for any method";
  for (const std::string& name : registry.names()) {
    std::string presets;
    for (const auto& [m, p] : registry.presetsOf(name))
      presets += (presets.empty() ? "" : ", ") + p->name;
    if (!presets.empty()) text += "; " + presets + " for " + name;
  }
  return text + "; NAME=VALUE for any of the method's parameters";
}

}  // namespace

std::vector<Entry> parseEntries(const std::string& list, int defaultSpp,
                                const MethodRegistry& registry) {
  std::vector<Entry> entries;
  std::set<std::string> labels;
  if (!list.empty() && list.back() == ',')
    throw CommandError("--methods: empty entry in '" + list + "'");
  for (const std::string& item : split(list, ',')) {
    if (item.empty()) throw CommandError("--methods: empty entry in '" + list + "'");
    Entry e;
    e.label = item;
    std::string body = item;
    e.spp = defaultSpp;
    if (const size_t at = body.find('@'); at != std::string::npos) {
      e.spp = parsePositive("--methods: " + item, body.substr(at + 1));
      body = body.substr(0, at);
    }
    const auto parts = split(body, ':');
    e.name = parts.empty() ? "" : parts[0];
    if (!registry.find(e.name))
      throw CommandError("--methods: unknown method '" + e.name + "' in '" + item +
                         "' (expected one of: " + registry.nameList() + ")");
    for (size_t i = 1; i < parts.size(); ++i) {
      if (parts[i] == "raw")
        e.raw = true;
      else if (registry.find(e.name, parts[i]))
        e.preset = parts[i];
      else if (parts[i].find('=') != std::string::npos)
        e.settings.push_back(parts[i]);
      else
        throw CommandError("--methods: unknown modifier '" + parts[i] + "' in '" + item + "' (" +
                           modifierHelp(registry) + ")");
    }
    e.method = registry.find(e.name, e.preset);
    // Checked here against the method's table, so a typo fails before any rendering.
    MethodConfig check = e.method->defaults();
    for (const std::string& setting : e.settings)
      applyParamSetting(check, setting, "--methods: " + item);
    if (!labels.insert(e.label).second)
      throw CommandError("--methods: '" + e.label + "' is listed twice");
    entries.push_back(e);
  }
  if (entries.empty()) throw CommandError("--methods: no method given");
  return entries;
}

RunShape compareShape(const CompareFlags& flags, const Scene& scene) {
  RunShape shape = RunShape::batch(scene.settings.spp);
  flags.run.apply(shape);
  if (const std::string problem = shape.validate(); !problem.empty()) throw CommandError(problem);
  return shape;
}

namespace {

report::Crop parseCrop(const std::string& text, int index, int width, int height) {
  const auto parts = split(text, ',');
  if (parts.size() != 4)
    throw CommandError("--crop: expected x,y,w,h in pixels, got '" + text + "'");
  report::Crop c;
  c.name = std::string(1, char('A' + index % 26));
  int v[4];
  for (int i = 0; i < 4; ++i) {
    size_t used = 0;
    try {
      v[i] = std::stoi(parts[size_t(i)], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != parts[size_t(i)].size())
      throw CommandError("--crop: expected x,y,w,h in pixels, got '" + text + "'");
  }
  c.x = v[0];
  c.y = v[1];
  c.w = v[2];
  c.h = v[3];
  if (c.x < 0 || c.y < 0 || c.w < 1 || c.h < 1 || c.x + c.w > width || c.y + c.h > height)
    throw CommandError("--crop " + text + ": outside the " + std::to_string(width) + "x" +
                       std::to_string(height) + " image");
  return c;
}

std::string elapsed(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

// ---- Time to quality ----------------------------------------------------------------------
// How a run's curve (report::CurvePoint) is measured; the report repeats it
// (report::detail::kCurveTimingNote):
//  - Checkpoints: in an equal-time run of T seconds at the times T/16 * 2^(k/2), k = 0..7 (the
//    last about 0.71 T); in an equal-spp run after the first round whose kept spp reaches 2^k,
//    k = 0, 1, ...; and the run's end (the run's final numbers). A round that passes several
//    checkpoints gives one point, the last of them.
//  - At a checkpoint: method->snapshot(true) and compareImages of the image the method's user
//    gets (reconstructed unless the entry is raw) against the reference. An equal-spp run
//    learns its kept spp after every round from a snapshot(false) probe.
//  - A point's time is the method's wall time less the time spent in the earlier
//    measurements (probes, checkpoint snapshots and their metrics): the checkpoint's own
//    snapshot counts, its reconstruction being part of what that image costs. The run's
//    seconds and reconstruct phase leave every measurement out.
//  - The equal-time deadline is on that own time: measuring extends the run, so every method
//    gets the same time for its own work.
// Without curves (--no-curve) nothing is measured before the end.

using Clock = std::chrono::steady_clock;

struct RunPlan {
  double equalTime = 0;  // seconds per run; 0: the spp budget
  bool curve = true;
  bool raw = false;  // the user's image is the raw estimate
  const Image* reference = nullptr;
};

struct RunOutcome {
  std::shared_ptr<Snapshot> snap;         // at the end
  std::vector<report::CurvePoint> curve;  // the checkpoints before the end
  double measuring = 0;                   // wall seconds spent measuring
  double measuringReconstruct = 0;        // the method's reconstruct time in those snapshots
};

constexpr int kTimeCheckpoints = 8;
double checkpointTime(double budget, int k) { return budget / 16 * std::exp2(k / 2.0); }

const Image& userImage(const Snapshot& snap, bool raw) {
  return raw || snap.reconstructed.empty() ? snap.raw : snap.reconstructed;
}

report::CurvePoint curvePoint(int checkpoint, double seconds, const ImageMetrics& metrics,
                              double keptSpp) {
  return {checkpoint, seconds, metrics.mse, metrics.relMse, metrics.toneMappedMse, keptSpp};
}

// Runs one method once: to its budget, or open-ended until `plan.equalTime` seconds of its own
// time, measuring its curve on the way (see above).
RunOutcome runOnce(const PreparedScene& prepared, const MethodSpec& spec, const RunPlan& plan) {
  auto method = makeMethod(prepared, spec);
  const auto start = Clock::now();
  const auto wall = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const double pixels = double(plan.reference->width) * plan.reference->height;
  RunOutcome out;
  double lastReconstruct = 0;
  // A snapshot taken to measure: its reconstruct time is noted, for the run to leave out.
  const auto measuringSnapshot = [&](bool reconstruct) {
    auto snap = method->snapshot(reconstruct);
    out.measuringReconstruct += snap->times.reconstruct - lastReconstruct;
    lastReconstruct = snap->times.reconstruct;
    return snap;
  };
  const auto checkpoint = [&](int k) {
    const double since = wall();
    const auto snap = measuringSnapshot(true);
    const ImageMetrics metrics = compareImages(userImage(*snap, plan.raw), *plan.reference);
    out.curve.push_back(
        curvePoint(k, snap->seconds - out.measuring, metrics, double(snap->keptSamples) / pixels));
    out.measuring += wall() - since;
  };
  int next = 0;  // the next checkpoint
  int guard = 0;
  while (!method->done() && guard++ < 1000000) {
    method->runRound(nullptr);
    const double own = wall() - out.measuring;
    if (plan.equalTime > 0 && own >= plan.equalTime) break;
    if (!plan.curve || method->done()) continue;  // the end is measured by the caller
    int k = next - 1;
    if (plan.equalTime > 0) {
      while (k + 1 < kTimeCheckpoints && checkpointTime(plan.equalTime, k + 1) <= own) ++k;
    } else {
      const double since = wall();
      const double kept = double(measuringSnapshot(false)->keptSamples) / pixels;
      out.measuring += wall() - since;
      while (kept >= std::exp2(k + 1)) ++k;
    }
    if (k >= next) checkpoint(k), next = k + 1;
  }
  out.snap = method->snapshot(true);
  returnFreedMemory();  // the reconstruction's planes, kept for a next round that is not coming
  return out;
}

}  // namespace

Image loadOrRenderReference(CompareFlags& flags, const PreparedScene& prepared, std::string& note) {
  const RenderSettings& settings = prepared.scene.settings;
  Image reference;
  if (flags.referencePath.empty()) {
    std::filesystem::create_directories(flags.outDir);
    flags.referencePath = (std::filesystem::path(flags.outDir) / "reference.exr").string();
    if (!flags.quiet)
      std::printf("no --reference: rendering %s at %d spp\n", flags.referencePath.c_str(),
                  flags.referenceSpp);
    std::fflush(stdout);
    const Reference ref = renderReference(prepared, flags.referenceSpp, 999, flags.threads);
    writeImage(flags.referencePath, ref.render.image);
    reference = ref.render.image;
    char text[160];
    std::snprintf(text, sizeof text, "rendered by compare at %d spp; its residual MSE %.3g",
                  flags.referenceSpp, ref.convergence.residualMse);
    note = text;
  } else {
    try {
      reference = readImage(flags.referencePath);
    } catch (const ImageIoError& e) {
      throw CommandError(std::string("--reference ") + e.what());
    }
  }
  if (reference.width != settings.width || reference.height != settings.height)
    throw CommandError("--reference " + flags.referencePath + " is " +
                       std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                       " but the render is " + std::to_string(settings.width) + "x" +
                       std::to_string(settings.height) + " (give --size)");
  return reference;
}

namespace {

// One entry of --methods over every seed: its runs' metrics, and the first seed's image and
// maps.
// Per pixel, the relative squared error against the reference (mean over channels).
std::vector<double> relativeSquaredErrors(const Image& image, const Image& reference) {
  double unused = 0;
  const Image e = errorImage(image, reference, unused);
  std::vector<double> v(e.pixels.size());
  for (size_t p = 0; p < v.size(); ++p) v[p] = e.pixels[p].x;
  return v;
}

// The 99.9th percentile of the finite values.
double percentile999(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return NAN;
  const size_t k = std::min(v.size() - 1, size_t(0.999 * double(v.size())));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// The configuration entry `e`'s preset gives, before the flags and settings.
MethodConfig entryBase(const Entry& e) {
  MethodConfig base = e.method->defaults();
  if (!e.preset.empty()) e.method->preset(e.preset)->apply(base);
  return base;
}

}  // namespace

MethodSpec entrySpec(const CompareFlags& flags, const Entry& e, const RunShape& base,
                     uint64_t seed) {
  RunShape shape = base;
  shape.seed = seed;
  shape.spp = e.spp;
  // Equal time: open-ended rounds until the time is up.
  if (flags.equalTime > 0) {
    shape.openEnded = true;
    shape.spp = 0;
  }
  MethodSpec spec{shape, flags.method.config(*e.method, e.preset)};
  for (const std::string& setting : e.settings)
    applyParamSetting(spec.config, setting, "--methods: " + e.label);
  if (e.raw) e.method->skipReconstruction(spec.config);
  if (const std::string problem = validate(spec); !problem.empty())
    throw CommandError("--methods: " + e.label + ": " + problem);
  return spec;
}

std::string describeEntry(const CompareFlags& flags, const Entry& e) {
  std::string description = e.method->description();
  const MethodDescriptor::Preset* named = e.method->defaultPreset();
  if (!e.preset.empty())
    description += ", " + e.preset + " preset";
  else if (named)
    description += ", " + named->name + " preset";
  if (e.raw) description += ", before reconstruction";
  const MethodSpec spec = entrySpec(flags, e, RunShape::batch(e.spp), flags.firstSeed);
  MethodConfig base = entryBase(e);
  if (e.raw) e.method->skipReconstruction(base);
  const std::string changes = describeChanges(spec.config, base);
  if (!changes.empty()) description += ", " + changes;
  return description;
}

CompareTask runTask(const CompareFlags& flags, const Entry& e, uint64_t seed,
                    const PreparedScene& prepared, const Image& reference) {
  const double pixels = double(reference.width) * reference.height;
  const MethodSpec spec = entrySpec(flags, e, compareShape(flags, prepared.scene), seed);
  // A method that shows no reconstruction is read raw.
  const bool useRaw = e.raw || !spec.method().abilities(spec.config).filters;
  const RunOutcome outcome =
      runOnce(prepared, spec, RunPlan{flags.equalTime, !flags.noCurve, useRaw, &reference});
  const std::shared_ptr<Snapshot>& snap = outcome.snap;
  CompareTask task;
  task.image = userImage(*snap, useRaw);
  report::MethodRun& run = task.run;
  run.seed = seed;
  run.metrics = compareImages(task.image, reference);
  run.keptSpp = double(snap->keptSamples) / pixels;
  run.tracedSpp = double(snap->tracedSamples) / pixels;
  run.seconds = snap->seconds - outcome.measuring;
  run.trace = snap->times.trace;
  run.train = snap->times.train;
  run.select = snap->times.select;
  run.reconstruct = snap->times.reconstruct - outcome.measuringReconstruct;
  run.network = snap->times.network;
  if (!flags.noCurve) {
    run.curve = outcome.curve;
    run.curve.push_back(
        curvePoint(report::kFinalCheckpoint, run.seconds, run.metrics, run.keptSpp));
  }
  if (!flags.quiet)
    std::printf("%-14s seed %llu: MSE %.4g, tone-mapped %.4g, %.1f kept spp, %.2f s\n",
                e.label.c_str(), static_cast<unsigned long long>(seed), run.metrics.mse,
                run.metrics.toneMappedMse, run.keptSpp, run.seconds);
  std::fflush(stdout);
  // The maps as the method published them (the report shows the first seed's); a raw image
  // was not filtered, so its filter-scale map does not describe it.
  if (seed == flags.firstSeed)
    for (const SnapshotMap& map : snap->maps)
      if (!(useRaw && map.id == maps::FilterScale)) task.maps.push_back(map);
  return task;
}

std::vector<report::MethodResult> assembleResults(const CompareFlags& flags,
                                                  const std::vector<Entry>& entries,
                                                  std::vector<std::vector<CompareTask>>& tasks,
                                                  const Image& reference) {
  // Speckles: per seed, the first entry's 99.9th percentile of the per-pixel relative squared
  // error is the limit every entry's share of pixels above it is counted against.
  std::vector<double> speckleLimits;
  std::vector<report::MethodResult> results;
  for (size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    report::MethodResult result;
    result.label = e.label;
    result.spp = e.spp;
    result.description = describeEntry(flags, e);
    for (size_t s = 0; s < tasks[i].size(); ++s) {
      CompareTask& task = tasks[i][s];
      const std::vector<double> errors = relativeSquaredErrors(task.image, reference);
      if (speckleLimits.size() <= s) speckleLimits.push_back(percentile999(errors));
      const double limit = speckleLimits[s];
      task.run.speckleShare =
          double(std::count_if(errors.begin(), errors.end(), [&](double x) { return x > limit; })) /
          double(errors.size());
      result.runs.push_back(task.run);
      if (s == 0) {
        result.image = std::move(task.image);
        result.maps = std::move(task.maps);
      }
    }
    results.push_back(std::move(result));
  }
  return results;
}

namespace {

// The one line a user wants: who wins, by how much.
void printWinner(const std::string& outDir, const report::CompareReport& r) {
  size_t best = 0;
  std::vector<double> mse;
  for (const auto& m : r.methods) {
    std::vector<double> v;
    for (const auto& run : m.runs) v.push_back(run.metrics.mse);
    mse.push_back(report::summarize(v).mean);
  }
  for (size_t i = 1; i < mse.size(); ++i)
    if (mse[i] < mse[best]) best = i;
  std::printf("%s/report.html: %s has the lowest MSE (%.4g, %.2fx of %s)\n", outDir.c_str(),
              r.methods[best].label.c_str(), mse[best], mse[0] > 0 ? mse[best] / mse[0] : 0.0,
              r.methods[0].label.c_str());
}

void run(CompareFlags flags) {
  if (!flags.referencePath.empty()) {
    const std::string ext = lowercaseExtension(flags.referencePath);
    if (ext != ".exr" && ext != ".pfm" && ext != ".hdr")
      throw CommandError("--reference " + flags.referencePath +
                         ": a reference must be linear (.exr, .pfm or .hdr), not an 8-bit image");
  }
  if (!flags.referencePath.empty() && !std::filesystem::exists(flags.referencePath))
    throw CommandError("--reference " + flags.referencePath +
                       ": no such file (render one with `penumbra reference " +
                       flags.scene.scenePath + " --spp 8192 -o " + flags.referencePath +
                       "`, or leave --reference out to have compare render one)");
  auto prepared = prepareScene(loadSceneWithOptions(flags.scene));
  const int spp = compareShape(flags, prepared->scene).spp;
  std::vector<Entry> entries = parseEntries(flags.methods, spp, *flags.method.registry);
  std::vector<const MethodDescriptor*> compared;
  for (Entry& e : entries) {
    // --preset applies to the entries of a method that has it and name none of their own.
    const MethodDescriptor* preset = flags.method.registry->find(e.name, flags.method.preset);
    if (e.preset.empty() && !flags.method.preset.empty() && preset) {
      e.preset = flags.method.preset;
      e.method = preset;
    }
    compared.push_back(e.method);
  }
  flags.method.requireRead(compared);
  if (!flags.plan.empty()) {
    for (const Entry& e : entries) describeEntry(flags, e);  // a bad setting fails here
    return writeComparePlan(flags, entries);
  }
  if (!flags.taskEntry.empty()) return runCompareTask(flags, entries, *prepared);
  std::string referenceNote;
  const Image reference = loadOrRenderReference(flags, *prepared, referenceNote);
  const int threads =
      flags.threads > 0 ? flags.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::unique_ptr<tbb::global_control> limit;
  if (flags.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(flags.threads));

  report::CompareReport r;
  r.title = std::filesystem::path(flags.scene.scenePath).stem().string();
  if (!flags.title.empty()) r.title = flags.title;
  r.scenePath = flags.scene.scenePath;
  r.referencePath = flags.referencePath;
  if (!referenceNote.empty()) r.referencePath += " (" + referenceNote + ")";
  r.mode = flags.equalTime > 0 ? "equal time (" + elapsed(flags.equalTime) + " per run)"
                               : "equal kept spp (" + std::to_string(spp) + ")";
  r.commandLine = flags.commandLine;
  r.threads = threads;
  r.reference = reference;
  r.exposure = flags.exposure;
  for (size_t i = 0; i < flags.crops.size(); ++i)
    r.crops.push_back(parseCrop(flags.crops[i], int(i), reference.width, reference.height));
  if (!flags.collect.empty()) {
    // The tasks ran elsewhere: their results, their thread count, and the local command.
    int taskThreads = 0;
    std::set<std::string> hosts;
    r.methods = collectCompare(flags, entries, reference, taskThreads, r.commandLine,
                               r.referencePath, hosts);
    r.threads = taskThreads;
    if (flags.equalTime > 0) {
      std::string names;
      for (const std::string& h : hosts) names += (names.empty() ? "" : ", ") + h;
      r.mode += ", on " + names;  // equal time depends on the nodes' speed
    }
  } else {
    std::vector<std::vector<CompareTask>> tasks(entries.size());
    for (size_t i = 0; i < entries.size(); ++i)
      for (int s = 0; s < flags.seeds; ++s)
        tasks[i].push_back(
            runTask(flags, entries[i], flags.firstSeed + uint64_t(s), *prepared, reference));
    r.methods = assembleResults(flags, entries, tasks, reference);
  }
  report::writeReport(flags.outDir, r);
  if (!flags.quiet) printWinner(flags.outDir, r);
}

}  // namespace

void registerCompareCommand(CLI::App& app) {
  auto flags = std::make_shared<CompareFlags>();
  CLI::App* c = app.add_subcommand(
      "compare",
      "Render a scene with several methods (fixed seeds, equal kept spp or equal time) and "
      "write DIR/report.html, report.md, results.json, results.csv and curves.csv (time to "
      "quality) against a reference");
  addSceneOptions(*c, flags->scene);
  addRunOptions(*c, flags->run, kCompareCommand, RunShape::batch(16),
                {{"spp", "the scene's render.spp"}});
  c->add_option("--methods", flags->methods,
                "Comma-separated NAME[:MODIFIER][@SPP]: NAME in ld, bp, fdiv, fuzzy, gem, "
                "cycles; modifiers consistent/paper/tuned (bp presets), filtered (ld with the "
                "consistent reconstruction), raw (before reconstruction); "
                "@SPP overrides --spp, e.g. ld,gem,bp:tuned,ld@64")
      ->capture_default_str();
  c->add_option("--reference", flags->referencePath,
                "Reference image (.exr), e.g. from `penumbra reference` (default: render one "
                "at --reference-spp into DIR/reference.exr)");
  c->add_option("--reference-spp", flags->referenceSpp,
                "Samples per pixel of the reference rendered when --reference is not given")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  c->add_option("--out", flags->outDir, "Output folder")->required();
  c->add_option("--seeds", flags->seeds, "Seeds per method (1, 2, ...); MSE is their mean")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  c->add_option("--first-seed", flags->firstSeed, "First seed")->capture_default_str();
  c->add_option("--equal-time", flags->equalTime,
                "Give every run this many seconds (open-ended rounds; the round in flight "
                "finishes) instead of equal kept spp")
      ->check(CLI::Range(0.0, 1e6));
  c->add_flag("--no-curve", flags->noCurve,
              "Measure no time-to-quality curve (no checkpoints during the runs, so no "
              "measuring overhead): results.json has empty curves, curves.csv only its header");
  c->add_option("--crop", flags->crops,
                "Region x,y,w,h to zoom into (repeatable); default: chosen where the methods "
                "differ most");
  c->add_option("--title", flags->title, "Report title (default: the scene's file name)");
  c->add_option("--threads", flags->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--exposure", flags->exposure, "Exposure in stops for the report's images")
      ->check(CLI::Range(-40.0f, 40.0f));
  c->add_option("--plan", flags->plan,
                "Write the runs as tasks for a farm into this folder instead of running them: "
                "tasks.txt (one command per method and seed) and finish.txt (--collect); needs "
                "--reference (docs/farm.md)");
  c->add_option("--collect", flags->collect,
                "Build the report from the results of the tasks of this plan folder (the "
                "arguments as for --plan)");
  c->add_option("--task-entry", flags->taskEntry,
                "Run one task of a plan: this --methods entry (with --task-seed), results into "
                "--out (written by --plan)");
  c->add_option("--task-seed", flags->taskSeed, "The seed of --task-entry");
  c->add_flag("-q,--quiet", flags->quiet, "No per-run lines or summary");
  addMethodOptions(*c, flags->method);
  c->callback([flags] {
    CompareFlags f = *flags;
    f.commandLine = commandLine();
    run(f);
  });
}

}  // namespace penumbra
