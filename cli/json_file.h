// JSON records the commands write: render's statistics, reference and shard records, plans,
// the viewer's report.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace penumbra {

// Writes `j` to `path` indented, atomically (a temporary file renamed into place), so that a
// failed write leaves no half-written record. Throws ImageIoError naming the file.
void writeJson(const std::string& path, const nlohmann::json& j);

}  // namespace penumbra
