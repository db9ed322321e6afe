// Where tests find shipped files and where they write their outputs, and the shipped
// scenes at a test size.
#pragma once

#include "methods/progressive.h"
#include "methods/render.h"
#include "scene/scene.h"
#include "trace/integrator.h"

#include <filesystem>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace penumbra::test {

inline const float kNaN = std::numeric_limits<float>::quiet_NaN();
inline const float kInf = std::numeric_limits<float>::infinity();

std::string sourcePath(const std::string& relative);  // path under the repository root
std::string outputPath(const std::string& name);      // path under the build's test output dir

// scenes/<name>.json at size x size pixels, ready to trace.
std::unique_ptr<PreparedScene> shippedScene(const std::string& name, int size);

// Runs the method's rounds until it is done (a failure past `maxRounds`) and returns the
// final snapshot, reconstruction included.
std::shared_ptr<Snapshot> runToEnd(ProgressiveMethod& method, int maxRounds = 1000);

// A scene from JSON text, as if read from ./test.json.
Scene sceneFrom(const std::string& json);

// A batch render of the scene (RenderOptions' defaults otherwise).
RenderResult renderScene(Scene scene, int spp, SamplerKind sampler = SamplerKind::Independent,
                         uint64_t seed = 11);

// A fresh, empty folder for the running test: <gtest's temp dir>/<prefix>_<suite>_<test>.
std::filesystem::path freshFolder(const std::string& prefix);

// A whole file's bytes ("" when it cannot be read), and a text's lines.
std::string readFile(const std::filesystem::path& path);
// Writes a file under the build's test output dir (outputPath), its folders included; returns
// its path.
std::string writeOutput(const std::string& name, const std::string& contents);
std::vector<std::string> lines(const std::string& text);

// Mean squared error of an image against a clean one, over pixels and channels.
double mse(std::span<const glm::vec3> image, std::span<const glm::vec3> clean);

// Expects each component of a and b to agree within the tolerance.
void expectNear(glm::vec3 a, glm::vec3 b, float tolerance = 1e-5f);

// The values of the snapshot's map `id` (the test fails when it has none).
const std::vector<float>& mapOf(const Snapshot& snapshot, MapId id);

}  // namespace penumbra::test
