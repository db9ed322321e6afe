// What `render --stats` records of a progressive method's run, all asked of the method's
// descriptor and snapshot: the method, its algorithm and preset, its counts and phases, every
// parameter of its table, its own figures (Snapshot::stats) and histograms of the maps the
// report shows.
#pragma once

#include "methods/method.h"
#include "methods/snapshot.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace penumbra {

// The record of one run. `preset`: the one given (empty: the descriptor's default preset, if it
// has one); `memoryBytes`: the method's per-pixel state.
nlohmann::json methodRunStats(const MethodSpec& spec, const std::string& preset,
                              const Snapshot& snap, size_t memoryBytes);
// The record of one round (from a snapshot without the reconstruction): its counts and the
// method's numeric figures.
nlohmann::json roundStats(const Snapshot& snap);
// Every parameter of a table under its JSON key, typed as the table says: a method's
// configuration, or the run's shape.
template <typename Config>
nlohmann::json paramsJson(const std::vector<Param<Config>>& params, const Config& config) {
  nlohmann::json j = nlohmann::json::object();
  for (const Param<Config>& p : params) {
    const std::string key = p.jsonKey();
    switch (p.kind) {
      case ParamKind::Int:
        j[key] = int64_t(p.get(config));
        break;
      case ParamKind::Float:  // as the flag would be written: 0.05, not 0.0500000007
        j[key] = std::strtod(formatParam(p, config).c_str(), nullptr);
        break;
      case ParamKind::Flag:
        j[key] = p.get(config) != 0;
        break;
      case ParamKind::Choice:
        j[key] = formatParam(p, config);
        break;
      case ParamKind::FloatList: {
        std::vector<double> values;
        for (float v : p.getList(config))
          values.push_back(std::strtod(formatBound(v).c_str(), nullptr));
        j[key] = values;
        break;
      }
    }
  }
  return j;
}

}  // namespace penumbra
