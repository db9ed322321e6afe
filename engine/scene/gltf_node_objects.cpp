#include "scene/gltf_node_objects.h"

#include "core/constants.h"
#include "scene/gltf_accessors.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace penumbra::gltf {

PunctualLight readPunctualLight(const std::string& path, const tinygltf::Model& model,
                                const tinygltf::Node& node, const glm::mat4& world,
                                const std::string& where) {
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
  // A directional light has no range; for the others it is in world units, which the node's
  // scale does not change (KHR_lights_punctual).
  if (out.kind != PunctualLight::Kind::Directional && light.range > 0) {
    if (!std::isfinite(light.range)) fail(path, lightWhere + ".range", "not finite");
    out.range = float(light.range);
  }
  return out;
}

std::vector<glm::mat4> readInstances(const std::string& path, const tinygltf::Model& model,
                                     const tinygltf::Node& node, const std::string& where) {
  const auto it = node.extensions.find("EXT_mesh_gpu_instancing");
  if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("attributes"))
    return {};
  const std::string field = where + ".extensions.EXT_mesh_gpu_instancing.attributes";
  const tinygltf::Value& attributes = it->second.Get("attributes");
  if (!attributes.IsObject()) fail(path, field, "must be an object");
  static const char* const kNames[3] = {"TRANSLATION", "ROTATION", "SCALE"};
  std::optional<AccessorReader> readers[3];
  size_t count = 0;
  for (int a = 0; a < 3; ++a) {
    if (!attributes.Has(kNames[a])) continue;
    const tinygltf::Value& index = attributes.Get(kNames[a]);
    if (!index.IsInt()) fail(path, field + "." + kNames[a], "must be an accessor index");
    readers[a].emplace(path, model, index.GetNumberAsInt(), field + "." + kNames[a]);
    const int components = a == 1 ? 4 : 3;
    if (readers[a]->components() != components)
      fail(path, readers[a]->where(), std::string("must be VEC") + char('0' + components));
    if (count != 0 && readers[a]->count() != count)
      fail(path, field, "the attributes must have as many instances each");
    count = readers[a]->count();
  }
  // Each instance copies the mesh: as many as the node instances a file may have.
  constexpr size_t kMaxInstances = size_t(1) << 20;
  if (count > kMaxInstances)
    fail(path, field, "more than " + std::to_string(kMaxInstances) + " instances");
  std::vector<glm::mat4> instances(count, glm::mat4(1.0f));
  for (size_t i = 0; i < count; ++i) {
    const auto get = [&](int a, int c) { return readers[a]->get(i, c); };
    glm::dmat4 m(1.0);
    if (readers[0]) m = glm::translate(m, glm::dvec3(get(0, 0), get(0, 1), get(0, 2)));
    if (readers[1]) {
      const glm::dquat q(get(1, 3), get(1, 0), get(1, 1), get(1, 2));
      const double length = glm::length(q);
      if (!(length > 0.0) || !std::isfinite(length))
        fail(path, readers[1]->where(),
             "instance " + std::to_string(i) + "'s rotation is not a quaternion");
      m = m * glm::mat4_cast(q / length);
    }
    if (readers[2]) m = glm::scale(m, glm::dvec3(get(2, 0), get(2, 1), get(2, 2)));
    instances[i] = glm::mat4(m);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(instances[i][c][r]))
          fail(path, field, "instance " + std::to_string(i) + "'s transform is not finite");
  }
  return instances;
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
    if (camera.type != "perspective" && camera.type != "orthographic") {
      warnings.push_back(indexed("cameras", size_t(node.camera)) + ": " + camera.type +
                         " cameras are not supported");
      continue;
    }
    if (camera.type == "orthographic" &&
        !(camera.orthographic.ymag != 0.0 && std::isfinite(camera.orthographic.ymag))) {
      warnings.push_back(indexed("cameras", size_t(node.camera)) +
                         ": an orthographic camera's ymag must be a finite number other than 0; "
                         "the camera is left out");
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
         "no camera named '" + name + "' (there are: " + (list.empty() ? "none" : list) + ")");
  }
  if (!chosen) return false;
  const tinygltf::Node& node = model.nodes[size_t(chosen->first)];
  const tinygltf::Camera& camera = model.cameras[size_t(node.camera)];
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
  if (camera.type == "orthographic") {
    // ymag is half the view's height; the image's aspect sets its width (as xmag would).
    out.orthographicHeight = float(2.0 * std::abs(camera.orthographic.ymag));
    return true;
  }
  const double degrees = camera.perspective.yfov * 180.0 / kPiD;
  out.vfovDegrees = degrees > 0.01 && degrees < 179.9 ? float(degrees) : 40.0f;
  return true;
}

}  // namespace penumbra::gltf
