#include "scene/gltf_node_objects.h"

#include "core/constants.h"
#include "scene/gltf_accessors.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::gltf {

PunctualLight readPunctualLight(const std::string& path, const tinygltf::Model& model,
                                const tinygltf::Node& node, const glm::mat4& world,
                                const std::string& where, std::string* warning) {
  double index = -1.0;
  const auto it = node.extensions.find("KHR_lights_punctual");
  if (it != node.extensions.end() && it->second.IsObject() && it->second.Has("light") &&
      it->second.Get("light").IsNumber())
    index = it->second.Get("light").GetNumberAsDouble();
  if (!(index >= 0 && index < double(model.lights.size())))
    fail(path, where + ".extensions.KHR_lights_punctual.light",
         "light " + number(index) + " does not exist");
  const tinygltf::Light& light = model.lights[size_t(index)];
  const std::string lightWhere =
      "extensions.KHR_lights_punctual." + indexed("lights", size_t(index));
  PunctualLight out;
  out.name = light.name.empty() ? lightWhere : light.name;
  if (light.type == "point")
    out.kind = PunctualLight::Kind::Point;
  else if (light.type == "spot")
    out.kind = PunctualLight::Kind::Spot;
  else if (light.type == "directional")
    out.kind = PunctualLight::Kind::Directional;
  else
    fail(path, lightWhere + ".type", "unknown light type '" + light.type + "'");
  vec3 color(1.0f);
  if (light.color.size() == 3)
    color = vec3(float(light.color[0]), float(light.color[1]), float(light.color[2]));
  out.intensity = glm::max(color, vec3(0.0f)) * std::max(float(light.intensity), 0.0f);
  if (!std::isfinite(out.intensity.x + out.intensity.y + out.intensity.z))
    fail(path, lightWhere + ".intensity", "not finite");
  out.position = vec3(world * glm::vec4(0, 0, 0, 1));
  const vec3 direction = vec3(world * glm::vec4(0, 0, -1, 0));
  const float length = glm::length(direction);
  if (!(length > 0.0f) || !std::isfinite(length + out.position.x + out.position.y + out.position.z))
    fail(path, where, "the light's transform is degenerate");
  out.direction = direction / length;
  if (out.kind == PunctualLight::Kind::Spot) {
    const double inner = std::clamp(light.spot.innerConeAngle, 0.0, 1.5707963267948966);
    const double outer = std::clamp(light.spot.outerConeAngle, inner, 1.5707963267948966);
    out.cosInner = float(std::cos(inner));
    out.cosOuter = float(std::cos(outer));
  }
  if (light.range > 0 && warning)
    *warning = lightWhere + ": range is ignored (light falls off with the square of the distance)";
  return out;
}

bool pickCamera(const std::string& path, const tinygltf::Model& model,
                const std::vector<std::pair<int, glm::mat4>>& cameraNodes, const std::string& name,
                Camera& out, std::vector<std::string>& warnings) {
  std::vector<std::string> names;
  const std::pair<int, glm::mat4>* chosen = nullptr;
  for (const auto& entry : cameraNodes) {
    const tinygltf::Node& node = model.nodes[size_t(entry.first)];
    if (node.camera < 0 || size_t(node.camera) >= model.cameras.size())
      fail(path, indexed("nodes", size_t(entry.first)) + ".camera", "camera does not exist");
    const tinygltf::Camera& camera = model.cameras[size_t(node.camera)];
    if (camera.type != "perspective") {
      warnings.push_back(indexed("cameras", size_t(node.camera)) + ": " + camera.type +
                         " cameras are not supported");
      continue;
    }
    const std::string label = node.name.empty() ? camera.name : node.name;
    names.push_back(label.empty() ? indexed("cameras", size_t(node.camera)) : label);
    if (chosen) continue;
    if (name.empty() || name == node.name || name == camera.name) chosen = &entry;
  }
  if (!name.empty() && !chosen) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    fail(path, "",
         "no perspective camera named '" + name +
             "' (there are: " + (list.empty() ? "none" : list) + ")");
  }
  if (!chosen) return false;
  const tinygltf::Node& node = model.nodes[size_t(chosen->first)];
  const tinygltf::PerspectiveCamera& p = model.cameras[size_t(node.camera)].perspective;
  const glm::mat4& world = chosen->second;
  const glm::vec3 eye = glm::vec3(world * glm::vec4(0, 0, 0, 1));
  const glm::vec3 forward = glm::vec3(world * glm::vec4(0, 0, -1, 0));
  const glm::vec3 up = glm::vec3(world * glm::vec4(0, 1, 0, 0));
  if (!(glm::length(forward) > 0.0f) || !(glm::length(glm::cross(forward, up)) > 0.0f) ||
      !std::isfinite(eye.x + eye.y + eye.z))
    fail(path, indexed("nodes", size_t(chosen->first)), "the camera's transform is degenerate");
  out.eye = eye;
  out.lookAt = eye + glm::normalize(forward);
  out.up = glm::normalize(up);
  const double degrees = p.yfov * 180.0 / kPiD;
  out.vfovDegrees = degrees > 0.01 && degrees < 179.9 ? float(degrees) : 40.0f;
  return true;
}

}  // namespace penumbra::gltf
