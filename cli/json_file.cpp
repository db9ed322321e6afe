#include "cli/json_file.h"

#include "core/image_io.h"

#include <fstream>

namespace penumbra {

void writeJson(const std::string& path, const nlohmann::json& j) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) throw ImageIoError(path + ": cannot write");
  });
}

}  // namespace penumbra
