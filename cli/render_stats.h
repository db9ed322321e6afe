// What `render --stats` records of a progressive method's run, all asked of the method's
// descriptor and snapshot: the method, its algorithm and preset, its counts and phases, every
// parameter of its table, its own figures (Snapshot::stats) and histograms of the maps the
// report shows.
#pragma once

#include "methods/method.h"
#include "methods/snapshot.h"

#include <nlohmann/json.hpp>

#include <string>

namespace penumbra {

// The record of one run. `preset`: the one given (empty: the descriptor's default preset, if it
// has one); `memoryBytes`: the method's per-pixel state.
nlohmann::json methodRunStats(const MethodSpec& spec, const std::string& preset,
                              const Snapshot& snap, size_t memoryBytes);
// The record of one round (from a snapshot without the reconstruction): its counts and the
// method's numeric figures.
nlohmann::json roundStats(const Snapshot& snap);
// Every parameter of the configuration under its JSON key, typed as the table says.
nlohmann::json configJson(const MethodConfig& config);

}  // namespace penumbra
