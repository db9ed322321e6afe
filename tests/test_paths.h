// Where tests find shipped files and where they write their outputs, and the shipped
// scenes at a test size.
#pragma once

#include "methods/progressive.h"
#include "trace/integrator.h"

#include <memory>
#include <string>

namespace penumbra::test {

std::string sourcePath(const std::string& relative);  // path under the repository root
std::string outputPath(const std::string& name);      // path under the build's test output dir

// scenes/<name>.json at size x size pixels, ready to trace.
std::unique_ptr<PreparedScene> shippedScene(const std::string& name, int size);

// Runs the method's rounds until it is done (a failure past `maxRounds`) and returns the
// final snapshot, reconstruction included.
std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method, int maxRounds = 1000);

}  // namespace penumbra::test
