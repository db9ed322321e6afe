#include "cli/scene_options.h"

#include "cli/commands.h"
#include "scene/scene_loader.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

namespace penumbra {

namespace {
std::vector<float> parseNumbers(const std::string& flag, const std::string& text, size_t count,
                                char separator) {
  std::vector<float> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, separator)) {
    try {
      size_t used = 0;
      const float v = std::stof(item, &used);
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
      values.push_back(v);
    } catch (const std::exception&) {
      values.clear();
      break;
    }
  }
  if (values.size() != count) {
    const std::string form = count == 3 ? "x,y,z" : (separator == 'x' ? "WxH" : "a,b");
    throw CommandError(flag + ": expected " + form + ", got '" + text + "'");
  }
  return values;
}

vec3 parseVec3(const std::string& flag, const std::string& text) {
  const auto v = parseNumbers(flag, text, 3, ',');
  return {v[0], v[1], v[2]};
}
}  // namespace

void addSceneOptions(CLI::App& c, SceneOptions& o) {
  c.add_option("scene", o.scenePath,
               "Scene file: a .json scene (docs/scene-format.md), a glTF 2.0 .gltf or .glb, or a "
               ".obj with its .mtl")
      ->required()
      ->check(CLI::ExistingFile);
  c.add_option("--size", o.size, "Image size WxH, e.g. 512x512 (default: the scene's render size)");
  c.add_option("--max-depth", o.maxDepth,
               "Maximum path depth: 0 = emitters only, 1 = direct light, ...")
      ->check(CLI::Range(0, 1024));
  c.add_option("--camera", o.camera,
               "glTF scenes: view through the camera of this node or camera name (default: the "
               "first camera; the flags below still override it)");
  c.add_option("--frame-time", o.frameTime,
               "glTF scenes: seconds into the animation at which the shutter opens (default: the "
               "animation's start)")
      ->check(CLI::Range(-1e9, 1e9));
  c.add_option("--shutter-seconds", o.shutterSeconds,
               "glTF scenes: how long the shutter stays open, in seconds of the animation (default "
               "1/48; 0 freezes it)")
      ->check(CLI::Range(0.0, 1e6));
  c.add_option("--eye", o.eye, "Camera position x,y,z");
  c.add_option("--look-at", o.lookAt, "Point the camera looks at, x,y,z");
  c.add_option("--up", o.up, "Camera up vector x,y,z");
  c.add_option("--fov", o.fov, "Vertical field of view in degrees")
      ->check(CLI::Range(0.01f, 179.9f));
  c.add_option("--lens-radius", o.lensRadius,
               "Thin-lens aperture radius in scene units; 0 = pinhole")
      ->check(CLI::Range(0.0f, 1e6f));
  c.add_option("--focus-distance", o.focusDistance,
               "Distance to the plane in focus; 0 = distance to the look-at point")
      ->check(CLI::Range(0.0f, 1e9f));
  c.add_option("--shutter", o.shutter,
               "Shutter interval open,close in scene time [0,1], e.g. 0,1; 0,0 freezes motion");
  c.add_option("--env", o.environment,
               "Environment map lighting the scene (equirectangular .exr or .hdr; top row up), or "
               "'none' to turn off the scene's (a glTF or OBJ file with no lights gets a built-in "
               "one)");
  c.add_option("--env-strength", o.environmentStrength, "Multiplies the environment's radiance")
      ->check(CLI::Range(0.0f, 1e6f));
  c.add_option("--env-rotation", o.environmentRotation,
               "Turns the environment about +y, in degrees (right-hand rule: +x towards -z)")
      ->check(CLI::Range(-1e6f, 1e6f));
  c.add_option("--texture-budget", o.textureBudgetMb,
               "Megabytes the image textures may take; past it the largest are halved (their "
               "finest mip level dropped) until they fit, with a warning; 0: no limit (default " +
                   std::to_string(SceneLoadOptions::kDefaultTextureBudgetBytes / 1000000) + ")")
      ->check(CLI::Range(0.0, 1e7));
  c.add_flag("--transparent", o.transparent,
             "Camera rays that leave the scene see nothing (no environment, no background); an "
             "EXR or PNG output gets an alpha channel saying where the scene is");
}

namespace {
// Prints the scene's warnings from the `first` on, one line each.
void printWarnings(const Scene& scene, size_t first = 0) {
  for (size_t i = first; i < scene.warnings.size(); ++i)
    std::fprintf(stderr, "warning: %s\n", scene.warnings[i].c_str());
}

void applyEnvironmentOptions(const SceneOptions& o, Scene& scene) {
  if (!o.environment.empty()) {
    try {
      const size_t warningsBefore = scene.warnings.size();
      replaceEnvironment(scene, o.environment);
      printWarnings(scene, warningsBefore);
    } catch (const SceneError& error) {
      throw CommandError(std::string("--env ") + error.what());
    }
  }
  Environment& e = scene.environment;
  if ((o.environmentStrength || o.environmentRotation) && !e.present())
    throw CommandError(std::string(o.environmentStrength ? "--env-strength" : "--env-rotation") +
                       ": " + scene.sourcePath +
                       " has no environment to change (give one with "
                       "--env FILE)");
  if (o.environmentStrength) e.strength = *o.environmentStrength;
  if (o.environmentRotation) e.rotationDegrees = *o.environmentRotation;
  scene.transparent = scene.transparent || o.transparent;
  if (e.builtin)
    std::fprintf(stderr,
                 "note: %s has no lights of its own: the built-in studio environment lights it "
                 "(--env none turns it off, --env FILE gives another)\n",
                 scene.sourcePath.c_str());
}
}  // namespace

Scene loadSceneWithOptions(const SceneOptions& o) {
  SceneLoadOptions load;
  load.camera = o.camera;
  load.frameTime = o.frameTime;
  if (o.textureBudgetMb) load.textureBudgetBytes = size_t(*o.textureBudgetMb * 1e6);
  if (o.shutterSeconds) {
    const std::string ext = std::filesystem::path(o.scenePath).extension().string();
    if (ext != ".gltf" && ext != ".glb")
      throw CommandError("--shutter-seconds: only a glTF scene has an animation; use --shutter");
    load.shutterSeconds = *o.shutterSeconds;
  }
  Scene scene = loadScene(o.scenePath, load);
  printWarnings(scene);
  if (!o.size.empty()) {
    const auto wh = parseNumbers("--size", o.size, 2, 'x');
    if (wh[0] < 1 || wh[1] < 1 || wh[0] > 16384 || wh[1] > 16384 || wh[0] != std::floor(wh[0]) ||
        wh[1] != std::floor(wh[1]))
      throw CommandError("--size: expected whole numbers between 1 and 16384, got '" + o.size +
                         "'");
    scene.settings.width = int(wh[0]);
    scene.settings.height = int(wh[1]);
  }
  if (o.maxDepth) scene.settings.maxDepth = *o.maxDepth;
  Camera& cam = scene.camera;
  if (!o.eye.empty()) cam.eye = parseVec3("--eye", o.eye);
  if (!o.lookAt.empty()) cam.lookAt = parseVec3("--look-at", o.lookAt);
  if (!o.up.empty()) cam.up = parseVec3("--up", o.up);
  if (o.fov) {  // a field of view asks for a perspective camera
    cam.vfovDegrees = *o.fov;
    cam.orthographicHeight = 0.0f;
  }
  if (o.lensRadius) cam.lensRadius = *o.lensRadius;
  if (o.focusDistance) cam.focusDistance = *o.focusDistance;
  if (!o.shutter.empty()) {
    const auto s = parseNumbers("--shutter", o.shutter, 2, ',');
    if (!(s[0] >= 0 && s[1] <= 1 && s[0] <= s[1]))
      throw CommandError("--shutter: expected open,close with 0 <= open <= close <= 1, got '" +
                         o.shutter + "'");
    cam.shutterOpen = s[0];
    cam.shutterClose = s[1];
  }
  applyEnvironmentOptions(o, scene);
  return scene;
}

std::array<int, 4> parseRegion(const std::string& text, int fullW, int fullH) {
  int x = 0, y = 0, w = 0, h = 0;
  char c1 = 0, c2 = 0, c3 = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c%d%c%d%c", &x, &c1, &y, &c2, &w, &c3, &h, &extra) != 7 ||
      c1 != ',' || c2 != ',' || c3 != ',')
    throw CommandError("--region: expected x,y,w,h in pixels, got '" + text + "'");
  if (w < 1 || h < 1 || x < 0 || y < 0 || x > fullW - w || y > fullH - h)
    throw CommandError("--region: " + text + " does not fit the " + std::to_string(fullW) + "x" +
                       std::to_string(fullH) +
                       " image (x,y >= 0, w,h >= 1, x+w <= width, "
                       "y+h <= height)");
  return {x, y, w, h};
}

}  // namespace penumbra
