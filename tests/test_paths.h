// Where tests find shipped files and where they write their outputs.
#pragma once

#include <string>

namespace penumbra::test {

std::string sourcePath(const std::string& relative);  // path under the repository root
std::string outputPath(const std::string& name);      // path under the build's test output dir

}  // namespace penumbra::test
