// Command-line options shared by every command that loads a scene (render, view, reference,
// compare): image size, depth, camera and environment overrides. The samples per pixel are the
// run's (run_options.h), whose default is the scene's render.spp.
#pragma once

#include "scene/scene.h"

#include <CLI/CLI.hpp>

#include <array>
#include <optional>
#include <string>

namespace penumbra {

struct SceneOptions {
  std::string scenePath;
  std::string size;  // "WxH"
  std::optional<int> maxDepth;
  std::string eye, lookAt, up, shutter;
  std::string camera;                    // glTF: which of the file's cameras
  std::optional<double> frameTime;       // glTF: seconds into the animation
  std::optional<double> shutterSeconds;  // glTF: how long the shutter stays open
  std::optional<float> fov, lensRadius, focusDistance;
  std::string environment;  // --env: a map's file, or "none"
  std::optional<float> environmentStrength, environmentRotation;
  bool transparent = false;
  std::optional<double> textureBudgetMb;  // --texture-budget
};

void addSceneOptions(CLI::App& command, SceneOptions& options);
// Loads the scene and applies the overrides; throws CommandError/SceneError naming the flag or
// file. The scene's warnings (features of a glTF file that are not rendered) go to stderr,
// one line each, and so does a note when the built-in environment lights it.
Scene loadSceneWithOptions(const SceneOptions& options);

// --region x,y,w,h of a fullWidth x fullHeight image, as {x, y, w, h}; throws CommandError
// naming the flag when it is malformed or does not fit.
std::array<int, 4> parseRegion(const std::string& text, int fullWidth, int fullHeight);

}  // namespace penumbra
