// `penumbra compare` on a farm (docs/farm.md): --plan DIR writes one task per (entry, seed) as
// a complete `penumbra compare ... --task-entry LABEL --task-seed S` command, and a finishing
// `compare ... --collect DIR`; a task writes its run (task.json, its image and, for the first
// seed, the method's maps) into its folder; --collect reads them all and writes the report a
// local compare with the same arguments writes (the measured times aside: they are the nodes').
#include "cli/commands.h"
#include "cli/compare.h"
#include "cli/json_file.h"
#include "cli/plan.h"
#include "core/image_io.h"
#include "eval/metrics.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <thread>

namespace penumbra {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// JSON has no infinities or NaN: those numbers are written as strings.
Json number(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
}
double number(const Json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.is_string() ? j.get<std::string>() : "nan";
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  return std::numeric_limits<double>::quiet_NaN();
}

Json runToJson(const report::MethodRun& r) {
  Json j;
  j["seed"] = r.seed;
  j["metrics"] = {{"mse", number(r.metrics.mse)},
                  {"rel_mse", number(r.metrics.relMse)},
                  {"tone_mapped_mse", number(r.metrics.toneMappedMse)},
                  {"psnr", number(r.metrics.psnr)},
                  {"max_abs_error", number(r.metrics.maxAbsError)},
                  {"non_finite", r.metrics.nonFinite}};
  j["kept_spp"] = number(r.keptSpp);
  j["traced_spp"] = number(r.tracedSpp);
  j["seconds"] = number(r.seconds);
  j["phases"] = {{"trace", number(r.trace)},
                 {"train", number(r.train)},
                 {"select", number(r.select)},
                 {"reconstruct", number(r.reconstruct)},
                 {"network", number(r.network)}};
  j["curve"] = Json::array();
  for (const report::CurvePoint& p : r.curve)
    j["curve"].push_back({{"checkpoint", p.checkpoint},
                          {"seconds", number(p.seconds)},
                          {"mse", number(p.mse)},
                          {"rel_mse", number(p.relMse)},
                          {"tone_mapped_mse", number(p.toneMappedMse)},
                          {"kept_spp", number(p.keptSpp)}});
  return j;
}

report::MethodRun runFromJson(const Json& j) {
  report::MethodRun r;
  r.seed = j.at("seed").get<uint64_t>();
  const Json& m = j.at("metrics");
  r.metrics.mse = number(m.at("mse"));
  r.metrics.relMse = number(m.at("rel_mse"));
  r.metrics.toneMappedMse = number(m.at("tone_mapped_mse"));
  r.metrics.psnr = number(m.at("psnr"));
  r.metrics.maxAbsError = number(m.at("max_abs_error"));
  r.metrics.nonFinite = m.at("non_finite").get<size_t>();
  r.keptSpp = number(j.at("kept_spp"));
  r.tracedSpp = number(j.at("traced_spp"));
  r.seconds = number(j.at("seconds"));
  const Json& ph = j.at("phases");
  r.trace = number(ph.at("trace"));
  r.train = number(ph.at("train"));
  r.select = number(ph.at("select"));
  r.reconstruct = number(ph.at("reconstruct"));
  r.network = number(ph.at("network"));
  for (const Json& p : j.at("curve"))
    r.curve.push_back({p.at("checkpoint").get<int>(), number(p.at("seconds")), number(p.at("mse")),
                       number(p.at("rel_mse")), number(p.at("tone_mapped_mse")),
                       number(p.at("kept_spp"))});
  return r;
}

// A map's values as an image (one channel: in all three), exact in a float EXR.
Image mapImage(const SnapshotMap& map, int width, int height) {
  Image image(width, height);
  const size_t c = map.channels();
  for (size_t p = 0; p < image.pixels.size(); ++p)
    image.pixels[p] = c == 3 ? vec3(map.values[3 * p], map.values[3 * p + 1], map.values[3 * p + 2])
                             : vec3(map.values[p]);
  return image;
}

std::string hostName() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string("unknown");
}

std::string taskFolder(const std::string& plan, size_t task) {
  return (fs::path(plan) / "runs" / std::to_string(task)).string();
}

}  // namespace

void writeComparePlan(const CompareFlags& flags, const std::vector<Entry>& entries) {
  if (flags.referencePath.empty())
    throw CommandError(
        "--plan needs --reference: render one first (`penumbra reference SCENE --plan DIR "
        "--shards N` shards it too)");
  const std::string dir = fs::absolute(flags.plan).lexically_normal().string();
  const auto absolute = [](const std::string& p) {
    return shellQuote(fs::absolute(p).lexically_normal().string());
  };
  const std::vector<std::string> kept = argumentsWithout(
      {"--plan", "--out", "--reference", "--collect", "--task-entry", "--task-seed"},
      {"-q", "--quiet"}, flags.scene.scenePath);
  std::string common = shellQuote(executablePath()) + " compare";
  for (const std::string& a : kept)
    if (a != "compare") common += " " + shellQuote(a);
  common += " --reference " + absolute(flags.referencePath);
  std::vector<std::string> tasks;
  for (const Entry& e : entries)
    for (int s = 0; s < flags.seeds; ++s)
      tasks.push_back(common + " --task-entry " + shellQuote(e.label) + " --task-seed " +
                      std::to_string(flags.firstSeed + uint64_t(s)) + " --out " +
                      shellQuote(taskFolder(dir, tasks.size())) + " -q");
  const std::string collect =
      common + " --collect " + shellQuote(dir) + " --out " + absolute(flags.outDir);
  writePlan(dir, "compare", tasks, {collect});
  // What a local compare with these arguments would have run: the report's command line.
  std::string local = "penumbra";
  for (const std::string& a : argumentsWithout({"--plan"}, {}, "")) local += " " + a;
  Json extra;
  extra["compare_command"] = local;
  extra["reference"] = flags.referencePath;  // as given, for the report
  writeJson((fs::path(dir) / "compare.json").string(), extra);
  if (!flags.quiet)
    std::printf(
        "%s: %zu tasks (tasks.txt: %zu entries x %d seeds), then the report into %s "
        "(finish.txt)\n",
        dir.c_str(), tasks.size(), entries.size(), flags.seeds, flags.outDir.c_str());
}

void runCompareTask(const CompareFlags& flags, const std::vector<Entry>& entries,
                    const PreparedScene& prepared) {
  if (flags.referencePath.empty()) throw CommandError("--task-entry needs --reference");
  if (!flags.taskSeed) throw CommandError("--task-entry needs --task-seed");
  const Entry* entry = nullptr;
  for (const Entry& e : entries)
    if (e.label == flags.taskEntry) entry = &e;
  if (!entry) throw CommandError("--task-entry: '" + flags.taskEntry + "' is not in --methods");
  CompareFlags given = flags;  // --reference is given: read and checked, never rendered
  std::string unused;
  const Image reference = loadOrRenderReference(given, prepared, unused);
  CompareTask task = runTask(flags, *entry, *flags.taskSeed, prepared, reference);
  fs::create_directories(fs::path(flags.outDir) / "maps");
  writeImage((fs::path(flags.outDir) / "image.exr").string(), task.image);
  Json j;
  j["kind"] = "penumbra-compare-task";
  j["entry"] = entry->label;
  j["run"] = runToJson(task.run);
  j["host"] = hostName();
  j["threads"] =
      flags.threads > 0 ? flags.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  j["maps"] = Json::array();
  for (const SnapshotMap& map : task.maps) {
    const std::string file = std::string("maps/") + map.id.name() + ".exr";
    writeImage((fs::path(flags.outDir) / file).string(),
               mapImage(map, reference.width, reference.height));
    j["maps"].push_back({{"id", map.id.name()},
                         {"label", map.label},
                         {"file", file},
                         {"kind", int(map.legend.kind)},
                         {"min", map.legend.minValue},
                         {"max", map.legend.maxValue},
                         {"categories", map.legend.categories},
                         {"units", map.legend.units}});
  }
  // Written last, atomically: a task folder with task.json is complete.
  writeJson((fs::path(flags.outDir) / "task.json").string(), j);
}

// Reads task `index` of the plan: its run, image and maps.
CompareTask readCompareTask(const std::string& plan, size_t index, const std::string& label,
                            uint64_t seed, const Image& reference, const MethodRegistry& methods,
                            std::set<std::string>& hosts, int& threads) {
  const std::string dir = taskFolder(plan, index);
  const std::string path = (fs::path(dir) / "task.json").string();
  std::ifstream in(path);
  if (!in)
    throw CommandError(path + ": missing: task " + std::to_string(index) + " (" + label +
                       ", seed " + std::to_string(seed) + ") has not finished; its command is " +
                       "line " + std::to_string(index + 1) + " of " + plan + "/tasks.txt");
  CompareTask task;
  try {
    const Json j = Json::parse(in);
    if (j.value("kind", "") != "penumbra-compare-task" || j.value("entry", "") != label)
      throw CommandError(path + ": not the task of " + label);
    task.run = runFromJson(j.at("run"));
    if (task.run.seed != seed)
      throw CommandError(path + ": seed " + std::to_string(task.run.seed) + ", expected " +
                         std::to_string(seed));
    hosts.insert(j.value("host", "unknown"));
    threads = std::max(threads, j.value("threads", 0));
    task.image = readImage((fs::path(dir) / "image.exr").string());
    for (const Json& m : j.at("maps")) {
      SnapshotMap map;
      const auto id = methods.mapByName(m.at("id").get<std::string>());
      if (!id) throw CommandError(path + ": unknown map '" + m.at("id").get<std::string>() + "'");
      map.id = *id;
      map.label = m.at("label").get<std::string>();
      map.legend.kind = ColorMapKind(m.at("kind").get<int>());
      map.legend.minValue = m.at("min").get<float>();
      map.legend.maxValue = m.at("max").get<float>();
      map.legend.categories = m.at("categories").get<std::vector<std::string>>();
      map.legend.units = m.at("units").get<std::string>();
      const Image values = readImage((fs::path(dir) / m.at("file").get<std::string>()).string());
      for (const vec3& v : values.pixels) {
        map.values.push_back(v.x);
        if (map.channels() == 3) map.values.insert(map.values.end(), {v.y, v.z});
      }
      task.maps.push_back(std::move(map));
    }
  } catch (const Json::exception& e) {
    throw CommandError(path + ": " + e.what());
  }
  if (task.image.width != reference.width || task.image.height != reference.height)
    throw CommandError(dir + "/image.exr: not the reference's size");
  return task;
}

std::vector<report::MethodResult> collectCompare(const CompareFlags& flags,
                                                 const std::vector<Entry>& entries,
                                                 const Image& reference, int& threads,
                                                 std::string& commandLine,
                                                 std::string& referenceAsGiven,
                                                 std::set<std::string>& hosts) {
  const std::string plan = flags.collect;
  std::ifstream in((fs::path(plan) / "compare.json").string());
  if (!in) throw CommandError(plan + ": no compare.json (not a compare plan)");
  try {
    const Json j = Json::parse(in);
    commandLine = j.at("compare_command").get<std::string>();
    referenceAsGiven = j.at("reference").get<std::string>();
  } catch (const Json::exception& e) {
    throw CommandError(plan + "/compare.json: " + e.what());
  }
  std::vector<std::vector<CompareTask>> tasks(entries.size());
  size_t index = 0;
  for (size_t i = 0; i < entries.size(); ++i)
    for (int s = 0; s < flags.seeds; ++s, ++index)
      tasks[i].push_back(readCompareTask(plan, index, entries[i].label,
                                         flags.firstSeed + uint64_t(s), reference,
                                         *flags.method.registry, hosts, threads));
  return assembleResults(flags, entries, tasks, reference);
}

}  // namespace penumbra
