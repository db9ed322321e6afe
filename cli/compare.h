// `penumbra compare`'s pieces that its farm mode shares (cmd_compare.cpp, compare_farm.cpp):
// the flags, the --methods entries, one run of one entry and seed (a task), and putting the
// tasks' results together into the report's methods. A local compare runs every task in turn;
// `compare --plan DIR` writes them as commands for a farm, and `compare --collect DIR` builds
// the same report from their results (docs/farm.md).
#pragma once

#include "cli/method_options.h"
#include "cli/run_options.h"
#include "cli/scene_options.h"
#include "core/image.h"
#include "methods/factory.h"
#include "report/report.h"
#include "trace/integrator.h"

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace penumbra {

struct CompareFlags {
  SceneOptions scene;
  MethodOptions method;
  RunOptions run;  // --spp, --round-spp, --sampler (seeds and equal time are compare's own)
  std::string methods = "ld,ld:filtered,fdiv,fuzzy,gem,bp:tuned,bp";
  std::string referencePath, outDir, title;
  std::vector<std::string> crops;
  int seeds = 5;
  uint64_t firstSeed = 1;
  double equalTime = 0;
  bool noCurve = false;
  int referenceSpp = 4096;
  int threads = 0;
  float exposure = 0;
  bool quiet = false;
  std::string commandLine;
  // The farm (compare_farm.cpp): write the tasks into a folder; collect their results from
  // one; or run one task (an entry's label and a seed) into --out.
  std::string plan, collect, taskEntry;
  std::optional<uint64_t> taskSeed;
};

struct Entry {
  std::string label;
  std::string name;
  const MethodDescriptor* method = nullptr;  // the descriptor its name and preset give
  std::string preset;                        // NAME:PRESET; empty: the flags' --preset, if any
  bool raw = false;
  std::vector<std::string> settings;  // "name=value" of the method's parameter table
  int spp = 0;
};

// The reference the methods are measured against: the given file (checked against the render's
// size), or one rendered (low discrepancy, same integrator) into --out so that the next
// comparison can reuse it; `note` says where a rendered one came from.
Image loadOrRenderReference(CompareFlags& flags, const PreparedScene& prepared, std::string& note);

// Parses --methods against the methods of `registry`; throws CommandError naming the entry.
std::vector<Entry> parseEntries(const std::string& list, int defaultSpp,
                                const MethodRegistry& registry = builtinMethods());
// The run's shape of every entry: the scene's spp and the run flags given.
RunShape compareShape(const CompareFlags& flags, const Scene& scene);

// What the report says of an entry: its method, preset and changed settings.
std::string describeEntry(const CompareFlags& flags, const Entry& e);
// The method spec of entry `e` for one seed, from `base` (compareShape); throws CommandError on
// a bad setting.
MethodSpec entrySpec(const CompareFlags& flags, const Entry& e, const RunShape& base,
                     uint64_t seed);

// One seed of one entry: the run as measured (its speckle share left for assembleResults),
// the image its user gets, and (first seed only) the method's maps.
struct CompareTask {
  report::MethodRun run;
  Image image;
  std::vector<SnapshotMap> maps;
};
CompareTask runTask(const CompareFlags& flags, const Entry& e, uint64_t seed,
                    const PreparedScene& prepared, const Image& reference);

// The report's methods from every entry's tasks (tasks[entry][seed], seeds in order): speckle
// shares against the first entry's, the first seed's image and maps. Moves the images out.
std::vector<report::MethodResult> assembleResults(const CompareFlags& flags,
                                                  const std::vector<Entry>& entries,
                                                  std::vector<std::vector<CompareTask>>& tasks,
                                                  const Image& reference);

// The farm (compare_farm.cpp, docs/farm.md). --plan DIR: the tasks' commands and the
// collecting one; needs --reference.
void writeComparePlan(const CompareFlags& flags, const std::vector<Entry>& entries);
// --task-entry LABEL --task-seed S: one task, its results into --out.
void runCompareTask(const CompareFlags& flags, const std::vector<Entry>& entries,
                    const PreparedScene& prepared);
// --collect DIR: every task's results (a CommandError names a missing one and its command);
// returns the report's methods, and sets the tasks' largest thread count, the local command
// line the plan stands for, the reference's path as it was given, and the hosts the tasks ran
// on.
std::vector<report::MethodResult> collectCompare(const CompareFlags& flags,
                                                 const std::vector<Entry>& entries,
                                                 const Image& reference, int& threads,
                                                 std::string& commandLine,
                                                 std::string& referenceAsGiven,
                                                 std::set<std::string>& hosts);

}  // namespace penumbra
