// Command-line options shared by every command that loads a scene (render, and the
// view/reference/compare commands to come): image size, spp, depth and camera overrides.
#pragma once

#include "scene/scene.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace penumbra {

struct SceneOptions {
  std::string scenePath;
  std::string size;  // "WxH"
  std::optional<int> spp, maxDepth;
  std::string eye, lookAt, up, shutter;
  std::optional<float> fov, lensRadius, focusDistance;
};

void addSceneOptions(CLI::App& command, SceneOptions& options);
// Loads the scene and applies the overrides; throws CommandError/SceneError naming the flag or
// file.
Scene loadSceneWithOptions(const SceneOptions& options);

}  // namespace penumbra
