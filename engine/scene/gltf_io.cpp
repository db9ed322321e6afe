#include "scene/gltf_io.h"

#include "core/constants.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_compression.h"
#include "scene/gltf_file.h"
#include "scene/gltf_material_layers.h"
#include "scene/gltf_morph.h"
#include "scene/gltf_node_objects.h"
#include "scene/gltf_skin.h"
#include "scene/gltf_textures.h"

#include "scene/mesh_io.h"
#include "scene/tangents.h"

#include <tiny_gltf.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <tuple>

namespace penumbra {
namespace {

using namespace gltf;
namespace fs = std::filesystem;

// ---- the conversion -------------------------------------------------------------------------

class Converter {
 public:
  Converter(const std::string& path, const tinygltf::Model& model, const GltfOptions& options,
            const ImagesNotRead& imagesNotRead, GltfData& out)
      : path_(path), model_(model), options_(options), imagesNotRead_(imagesNotRead), out_(out) {}

  void materials() {
    for (size_t i = 0; i < model_.materials.size(); ++i) {
      materialUvSets_.clear();
      out_.materials.push_back(material(i));
      std::vector<std::string> warnings;
      uvSets_.push_back(materialUvSet(materialUvSets_, warnings));
      for (const std::string& w : warnings) warn(w);
    }
  }

  // Reads every animation's translation, rotation and scale channels, and settles the shutter
  // interval: from the frame time (default: the animations' start) for shutterSeconds.
  void animations() {
    tracks_.assign(model_.nodes.size(), {});
    weightTracks_.assign(model_.nodes.size(), std::nullopt);
    double start = INFINITY;
    for (size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& animation = model_.animations[a];
      for (size_t c = 0; c < animation.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = animation.channels[c];
        const std::string where = indexed("animations", a) + "." + indexed("channels", c);
        if (channel.target_node < 0 || size_t(channel.target_node) >= model_.nodes.size())
          fail(path_, where + ".target.node",
               "node " + std::to_string(channel.target_node) + " does not exist");
        if (channel.target_path == "weights") {
          const size_t targets = morphTargetCount(model_, channel.target_node);
          if (targets == 0) {
            warn(where + ": animates the weights of a node without morph targets");
            continue;
          }
          auto& track = weightTracks_[size_t(channel.target_node)];
          track = readWeightsTrack(path_, model_, animation, channel, targets, where);
          start = std::min(start, track->times.front());
          continue;
        }
        if (!model_.nodes[size_t(channel.target_node)].matrix.empty())
          fail(path_, where,
               "animates " + indexed("nodes", size_t(channel.target_node)) +
                   ", which has a matrix (glTF animates only translation, rotation and scale)");
        Track track = readTrack(path_, model_, animation, channel, where);
        start = std::min(start, track.times.front());
        tracks_[size_t(channel.target_node)].push_back(std::move(track));
      }
    }
    const bool any = std::isfinite(start);
    out_.frameTime = options_.frameTime ? *options_.frameTime : (any ? start : 0.0);
    out_.shutterSeconds = options_.shutterSeconds;
    if (!std::isfinite(out_.frameTime) || !(out_.shutterSeconds >= 0) ||
        !std::isfinite(out_.shutterSeconds))
      fail(path_, "", "the frame time and shutter must be finite, the shutter not negative");
    animating_ = any && options_.animate && out_.shutterSeconds > 0;
  }

  // Walks the scene's node tree from its roots.
  void nodes(const std::string& cameraName) {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const size_t scene =
          model_.defaultScene >= 0 && size_t(model_.defaultScene) < model_.scenes.size()
              ? size_t(model_.defaultScene)
              : 0;
      roots = model_.scenes[scene].nodes;
    } else {
      // No scene: every node that is no other node's child is a root.
      std::vector<char> child(model_.nodes.size(), 0);
      for (const tinygltf::Node& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = 1;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!child[i]) roots.push_back(int(i));
    }
    onPath_.assign(model_.nodes.size(), 0);
    for (int root : roots) visit(root, {mat4(1.0f)}, "scenes.nodes");
    std::vector<std::string> warnings;
    out_.hasCamera = pickCamera(path_, model_, cameraNodes_, cameraName, out_.camera, warnings);
    for (const std::string& w : warnings) warn(w);
  }

  void warnAboutTheRest() {
    if (texturesHalved_ > 0) {
      size_t after = 0;
      for (const TextureImage& image : out_.images) after += image.byteSize();
      warn(textureBudgetWarning(fullTextureBytes_, options_.textureBudgetBytes, after,
                                texturesHalved_));
    }
    if (!model_.animations.empty() && !options_.animate)
      warn("animations: shown at the frame time, without motion blur (an included file)");
    for (const std::string& e : model_.extensionsUsed)
      if (!supportedExtension(e)) warn("extension " + e + " is not supported and is ignored");
    for (const std::string& e : model_.extensionsRequired)
      if (!supportedExtension(e))
        warn("extension " + e +
             " is required by the file but not supported: the picture may be wrong");
  }

 private:
  // Samples of a transform over the shutter: one (it does not move) or kSamples, evenly
  // spread from the frame time to the frame time plus the shutter.
  using Samples = std::vector<mat4>;
  static constexpr int kSamples = kMotionSamples;

  static bool supportedExtension(const std::string& e) {
    return e == "KHR_materials_emissive_strength" || e == "KHR_materials_transmission" ||
           e == "KHR_materials_specular" || e == "KHR_materials_clearcoat" ||
           e == "KHR_materials_ior" || e == "KHR_materials_volume" || e == "KHR_materials_unlit" ||
           e == "KHR_materials_sheen" || e == "KHR_materials_anisotropy" ||
           e == "KHR_materials_iridescence" || e == "KHR_materials_pbrSpecularGlossiness" ||
           e == "KHR_lights_punctual" || e == "KHR_texture_transform" ||
           e == "KHR_mesh_quantization" || e == "EXT_mesh_gpu_instancing" || e == kWebpExtension ||
           isMeshCompression(e);
  }

  void warn(const std::string& message) {
    if (warned_.insert(message).second) out_.warnings.push_back(message);
  }

  static double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension,
                                const char* key, double fallback) {
    const auto it = extensions.find(extension);
    if (it == extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
  }

  // A texture of the file as one of ours, converted as `texels` say, its factor applied at
  // lookup; an image used twice the same way is converted once, and a texture used twice with
  // the same factor is one texture. -1 for coverage from an image without alpha.
  int texture(const tinygltf::TextureInfo& info, const std::string& where, Texels texels,
              vec3 factor, std::optional<vec3> offset = std::nullopt) {
    return texture(info.index, info.texCoord, info.extensions, where, texels, factor, offset);
  }

  int texture(int index, int texCoord, const tinygltf::ExtensionMap& extensions,
              const std::string& where, Texels texels, vec3 factor,
              std::optional<vec3> offset = std::nullopt) {
    if (index < 0) return -1;
    if (size_t(index) >= model_.textures.size())
      fail(path_, where, "texture " + std::to_string(index) + " does not exist");
    const tinygltf::Texture& gltfTexture = model_.textures[size_t(index)];
    const std::string textureWhere = indexed("textures", size_t(index));
    const int source = textureSource(path_, model_, gltfTexture, textureWhere);
    if (source < 0 || size_t(source) >= model_.images.size()) {
      // An image only in an extension's format: left out, the factor alone is used.
      for (const char* e : kImageFormatExtensions)
        if (gltfTexture.extensions.count(e)) {
          warn(textureWhere + ": its image is only in " + e +
               "'s format, which is not read: the texture is left out (its factor is used)");
          return -1;
        }
      fail(path_, where, "its texture has no image");
    }
    const auto notRead = imagesNotRead_.find(source);
    if (notRead != imagesNotRead_.end()) {
      warn(textureWhere + ": " + indexed("images", size_t(source)) + " is " + notRead->second +
           ", which is not read: the texture is left out (its factor is used)");
      return -1;
    }
    Texture t;
    t.kind = Texture::Kind::Image;
    t.factor = factor;
    t.hasOffset = offset.has_value();
    t.offset = offset.value_or(vec3(0.0f));
    if (gltfTexture.sampler >= 0) {
      if (size_t(gltfTexture.sampler) >= model_.samplers.size())
        fail(path_, where, "sampler " + std::to_string(gltfTexture.sampler) + " does not exist");
      const tinygltf::Sampler& sampler = model_.samplers[size_t(gltfTexture.sampler)];
      const std::string at = indexed("samplers", size_t(gltfTexture.sampler));
      t.wrap.u = wrapMode(path_, sampler.wrapS, at + ".wrapS");
      t.wrap.v = wrapMode(path_, sampler.wrapT, at + ".wrapT");
      t.wrap.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    textureTransform(path_, extensions, where, t, texCoord);
    materialUvSets_.push_back({where, texCoord});
    const TextureKey key{
        source,
        int(texels),
        {factor.x, factor.y, factor.z, float(int(t.wrap.u)), float(int(t.wrap.v)),
         float(t.wrap.nearest), t.uvLinear[0][0], t.uvLinear[0][1], t.uvLinear[1][0],
         t.uvLinear[1][1], t.uvOffset.x, t.uvOffset.y, t.offset.x, t.offset.y, t.offset.z}};
    const auto known = textureIds_.find(key);
    if (known != textureIds_.end()) return known->second;
    const auto imageKey = std::make_pair(source, int(texels));
    auto image = imageIds_.find(imageKey);
    if (image == imageIds_.end()) {
      TextureImage converted =
          imageFromGltf(path_, model_.images[size_t(source)], size_t(source), texels);
      const int id = converted.empty() ? -1 : int(out_.images.size());
      if (!converted.empty()) {
        fullTextureBytes_ += converted.byteSize();
        out_.images.push_back(std::move(converted));
        if (options_.textureBudgetBytes > 0)
          texturesHalved_ += fitTexturesToBudget(out_.images, options_.textureBudgetBytes);
      }
      image = imageIds_.emplace(imageKey, id).first;
    }
    int id = -1;
    if (image->second >= 0) {
      t.imageIndex = image->second;
      out_.textures.push_back(t);
      id = int(out_.textures.size() - 1);
    }
    textureIds_[key] = id;
    return id;
  }

  Material material(size_t index) {
    const std::string where = indexed("materials", index);
    gltf::Glossiness glossiness;
    const tinygltf::Material m =
        asMetallicRoughness(path_, model_.materials[index], where, glossiness);
    Material out;
    out.name = m.name.empty() ? where : m.name;
    out.type = Material::Type::Pbr;
    const auto& pbr = m.pbrMetallicRoughness;
    vec3 base(1.0f);
    float alpha = 1.0f;
    if (pbr.baseColorFactor.size() >= 3)
      base = vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                  float(pbr.baseColorFactor[2]));
    if (pbr.baseColorFactor.size() == 4) alpha = float(pbr.baseColorFactor[3]);
    if (!std::isfinite(base.x + base.y + base.z + alpha))
      fail(path_, where + ".pbrMetallicRoughness.baseColorFactor", "not finite");
    out.albedo = glm::clamp(base, vec3(0.0f), vec3(1.0f));
    out.albedoTexture =
        texture(pbr.baseColorTexture, where + ".baseColorTexture", Texels::Color, out.albedo);
    out.metallic = std::clamp(float(pbr.metallicFactor), 0.0f, 1.0f);
    out.roughness = std::max(std::clamp(float(pbr.roughnessFactor), 0.0f, 1.0f), 0.02f);
    out.transmission = std::clamp(float(extensionNumber(m.extensions, "KHR_materials_transmission",
                                                        "transmissionFactor", 0.0)),
                                  0.0f, 1.0f);
    out.ior = float(extensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5));
    if (!(out.ior >= 1.0f && out.ior < 10.0f)) out.ior = 1.5f;
    out.metallicRoughnessTexture =
        texture(pbr.metallicRoughnessTexture, where + ".metallicRoughnessTexture", Texels::Data,
                vec3(1.0f));
    // Specular-glossiness: roughness 1 - glossiness x the texture's alpha (metallic stays 0).
    if (const gltf::Glossiness& g = glossiness; g.texture.index >= 0) {
      out.metallicRoughnessTexture = texture(g.texture, where + ".specularGlossinessTexture",
                                             Texels::Alpha, vec3(-g.factor), vec3(1.0f));
      if (out.metallicRoughnessTexture >= 0) out.roughness = 1.0f;
    }
    const auto layerTexture = [&](int index, int texCoord, const tinygltf::ExtensionMap& e,
                                  const std::string& field, Texels texels) {
      return texture(index, texCoord, e, field, texels, vec3(1.0f));
    };
    readMaterialLayers(path_, m, where, out, layerTexture);
    if (m.normalTexture.index >= 0) {
      out.normalTexture =
          texture(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions,
                  where + ".normalTexture", Texels::Data, vec3(1.0f));
      out.normalScale = std::isfinite(m.normalTexture.scale) ? float(m.normalTexture.scale) : 1.0f;
    }
    if (m.occlusionTexture.index >= 0)
      warn(where + ": occlusionTexture is ignored (a path tracer computes occlusion)");
    // MASK: holes below the cutoff; BLEND: the coverage is the chance that a ray stops.
    if (m.alphaMode == "MASK" || m.alphaMode == "BLEND") {
      out.alpha = std::clamp(alpha, 0.0f, 1.0f);
      if (m.alphaMode == "MASK")
        out.alphaCutoff =
            std::isfinite(m.alphaCutoff) ? std::max(float(m.alphaCutoff), 0.0f) : 0.5f;
      else
        out.alphaBlend = true;
      out.alphaTexture =
          texture(pbr.baseColorTexture, where + ".baseColorTexture", Texels::Alpha, vec3(1.0f));
      // Fully covered: nothing to test.
      if (out.alphaBlend && out.alpha >= 1.0f && out.alphaTexture < 0) out.alphaBlend = false;
    }
    if (m.emissiveFactor.size() == 3) {
      const float strength = float(extensionNumber(m.extensions, "KHR_materials_emissive_strength",
                                                   "emissiveStrength", 1.0));
      out.emission = glm::max(
          vec3(float(m.emissiveFactor[0]), float(m.emissiveFactor[1]), float(m.emissiveFactor[2])) *
              std::max(strength, 0.0f),
          vec3(0.0f));
      if (!std::isfinite(out.emission.x + out.emission.y + out.emission.z))
        fail(path_, where + ".emissiveFactor", "not finite");
    }
    if (out.isEmissive())
      out.emissionTexture =
          texture(m.emissiveTexture, where + ".emissiveTexture", Texels::Color, vec3(1.0f));
    return out;
  }

  uint32_t defaultMaterial() {
    if (defaultMaterial_ < 0) {
      Material m;
      m.name = "default";
      m.albedo = vec3(0.8f);
      out_.materials.push_back(m);
      defaultMaterial_ = int(out_.materials.size() - 1);
    }
    return uint32_t(defaultMaterial_);
  }

  Samples localSamples(const tinygltf::Node& node, size_t index) const {
    if (tracks_.empty() || tracks_[index].empty()) return {localTransform(path_, node, index)};
    Samples samples;
    for (double t : sampleTimes())
      samples.push_back(animatedLocal(path_, node, index, tracks_[index], t));
    return samples;
  }

  // When the shutter's samples are taken: at the frame time, or over the shutter when animating.
  std::vector<double> sampleTimes() const {
    if (!animating_) return {out_.frameTime};
    std::vector<double> times(kSamples);
    for (int j = 0; j < kSamples; ++j)
      times[size_t(j)] = out_.frameTime + out_.shutterSeconds * double(j) / double(kSamples - 1);
    return times;
  }

  // A node's world transform samples found up its chain of parents (a skin's joints: they need
  // not be visited before the mesh they pose).
  const Samples& worldOf(int index) {
    if (worlds_.empty()) {
      worlds_.resize(model_.nodes.size());
      parents_.assign(model_.nodes.size(), -1);
      resolving_.assign(model_.nodes.size(), 0);
      for (size_t n = 0; n < model_.nodes.size(); ++n)
        for (int c : model_.nodes[n].children)
          if (c >= 0 && size_t(c) < parents_.size() && parents_[size_t(c)] < 0)
            parents_[size_t(c)] = int(n);
    }
    Samples& world = worlds_[size_t(index)];
    if (!world.empty()) return world;
    if (resolving_[size_t(index)])
      fail(path_, indexed("nodes", size_t(index)), "is its own ancestor");
    resolving_[size_t(index)] = 1;
    const Samples local = localSamples(model_.nodes[size_t(index)], size_t(index));
    const Samples parent =
        parents_[size_t(index)] < 0 ? Samples{mat4(1.0f)} : worldOf(parents_[size_t(index)]);
    world.resize(std::max(parent.size(), local.size()));
    for (size_t j = 0; j < world.size(); ++j)
      world[j] = parent[std::min(j, parent.size() - 1)] * local[std::min(j, local.size() - 1)];
    resolving_[size_t(index)] = 0;
    return world;
  }

  void visit(int index, const Samples& parent, const std::string& from) {
    if (index < 0 || size_t(index) >= model_.nodes.size())
      fail(path_, from, "node " + std::to_string(index) + " does not exist");
    if (onPath_[size_t(index)]) fail(path_, indexed("nodes", size_t(index)), "is its own ancestor");
    // A node may be reached along many paths (instancing); a small file whose nodes list the
    // same child twice, level after level, would reach it 2^depth times.
    if (++visits_ > kMaxNodeInstances)
      fail(path_, "",
           "more than " + std::to_string(kMaxNodeInstances) +
               " node instances (a child listed many times over)");
    onPath_[size_t(index)] = 1;
    const tinygltf::Node& node = model_.nodes[size_t(index)];
    const Samples local = localSamples(node, size_t(index));
    Samples world(std::max(parent.size(), local.size()));
    for (size_t j = 0; j < world.size(); ++j)
      world[j] = parent[std::min(j, parent.size() - 1)] * local[std::min(j, local.size() - 1)];
    const std::string where = indexed("nodes", size_t(index));
    if (node.mesh >= 0 && node.skin >= 0) {
      // Posed by its joints; the node's own transform is ignored, as glTF says.
      const gltf::SkinPose pose = poseSkin(
          path_, model_, node.skin, [&](int n) -> const Samples& { return worldOf(n); },
          where + ".skin");
      addMesh(node.mesh, world, where,
              {&pose, morphWeights(model_, node, weightTracks_[size_t(index)], sampleTimes())});
    } else if (node.mesh >= 0) {
      const Deform morph{nullptr,
                         morphWeights(model_, node, weightTracks_[size_t(index)], sampleTimes())};
      const std::vector<mat4> instances = readInstances(path_, model_, node, where);
      if (instances.empty()) addMesh(node.mesh, world, where, morph);
      for (const mat4& instance : instances) {  // EXT_mesh_gpu_instancing: before the node's
        Samples placed = world;
        for (mat4& m : placed) m = m * instance;
        addMesh(node.mesh, placed, where, morph);
      }
    }
    // Cameras and lights are placed where they are when the shutter opens.
    if (node.camera >= 0) cameraNodes_.push_back({index, world.front()});
    if (node.extensions.count("KHR_lights_punctual"))
      out_.lights.push_back(readPunctualLight(path_, model_, node, world.front(), where));
    for (int child : node.children) visit(child, world, where + ".children");
    onPath_[size_t(index)] = 0;
  }

  // A mesh instance: into the static mesh when it does not move, else one mesh per primitive
  // with as many time steps as its motion needs.
  // How a mesh instance's vertices are placed besides its node's transform: a skin's pose
  // (which replaces that transform) and morph weights, each one per time step, or one when
  // still.
  struct Deform {
    const gltf::SkinPose* skin = nullptr;
    std::vector<std::vector<float>> morph;  // [step][target]; empty: none
  };

  // A mesh instance: into the static mesh when it does not move (nor its joints or morph
  // weights), else one mesh per primitive with as many time steps as its motion needs.
  void addMesh(int meshIndex, const Samples& world, const std::string& from, const Deform& deform) {
    if (size_t(meshIndex) >= model_.meshes.size())
      fail(path_, from, "mesh " + std::to_string(meshIndex) + " does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
    bool moves = false;
    for (const mat4& m : world) moves = moves || m != world.front();
    if (deform.skin) moves = deform.skin->moves();
    for (const std::vector<float>& w : deform.morph) moves = moves || w != deform.morph.front();
    const size_t last = kSamples - 1;
    const auto pick = [](const auto& samples, size_t at) {
      return samples[std::min(at, samples.size() - 1)];
    };
    // The samples every `stride` apart: the node's transforms into `steps`, the rest returned.
    gltf::SkinPose pose;
    const auto stepped = [&](size_t stride, Samples& steps) {
      Deform out;
      for (size_t at = 0; at <= last; at += stride) {
        steps.push_back(pick(world, at));
        if (deform.skin) pose.steps.push_back(pick(deform.skin->steps, at));
        if (!deform.morph.empty()) out.morph.push_back(pick(deform.morph, at));
      }
      if (deform.skin) out.skin = &pose;
      return out;
    };
    if (!moves) {
      Samples steps;
      const Deform still = stepped(kSamples, steps);
      for (size_t p = 0; p < mesh.primitives.size(); ++p)
        addPrimitive(mesh, size_t(meshIndex), p, steps, out_.mesh, anyNormals_, anyUvs_, anyColors_,
                     still);
      return;
    }
    float radius = 0;
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      const auto position = prim.attributes.find("POSITION");
      if (position == prim.attributes.end()) continue;
      const AccessorReader r(path_, model_, position->second, from);
      for (size_t v = 0; v < r.count() && r.components() == 3; ++v)
        radius =
            std::max(radius, float(glm::length(glm::dvec3(r.get(v, 0), r.get(v, 1), r.get(v, 2)))));
    }
    int segments = 1;
    if (deform.skin && deform.skin->steps.size() > 1) segments = deform.skin->segments(radius);
    if (!deform.skin && world.size() > 1) segments = motionSegments(world, radius);
    if (deform.morph.size() > 1) segments = std::max(segments, gltf::weightSegments(deform.morph));
    Samples steps;
    const Deform moving = stepped(last / size_t(segments), steps);
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      Mesh target;
      target.name =
          (model_.meshes[size_t(meshIndex)].name.empty() ? indexed("meshes", size_t(meshIndex))
                                                         : model_.meshes[size_t(meshIndex)].name);
      target.timeSteps = int(steps.size());
      bool normals = false, uvs = false, colors = false;
      addPrimitive(mesh, size_t(meshIndex), p, steps, target, normals, uvs, colors, moving);
      if (!target.indices.empty()) out_.animatedMeshes.push_back(std::move(target));
    }
  }

  // Appends one primitive to `target` (vertex time steps as many as `steps`; a target with
  // several steps receives one primitive only).
  void addPrimitive(const tinygltf::Mesh& mesh, size_t meshIndex, size_t p, const Samples& steps,
                    Mesh& target, bool& anyNormals, bool& anyUvs, bool& anyColors,
                    const Deform& deform) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string where = indexed("meshes", meshIndex) + "." + indexed("primitives", p);
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warn(where + ": points and lines are not rendered");
      return;
    }
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) fail(path_, where, "no POSITION attribute");
    const AccessorReader positions(path_, model_, position->second, where + ".POSITION");
    // Float, or integers (normalised or not) as KHR_mesh_quantization allows: the node's
    // transform scales them.
    if (positions.components() != 3) fail(path_, positions.where(), "POSITION must be VEC3");
    const size_t vertexCount = positions.count();
    if (vertexCount == 0) return;
    const size_t stepCount = steps.size();
    const gltf::SkinPose* skin = deform.skin;
    if (vertexCount * stepCount > kMaxVertices - totalVertices_)
      fail(path_, where,
           "the scene would have more than " + std::to_string(kMaxVertices) + " vertices");
    totalVertices_ += vertexCount * stepCount;
    std::optional<gltf::SkinWeights> weights;
    if (skin) weights.emplace(path_, model_, prim, vertexCount, skin->jointCount(), where);
    std::optional<gltf::MorphTargets> morph;
    if (!prim.targets.empty() && !deform.morph.empty())
      morph.emplace(path_, model_, prim, vertexCount, deform.morph, where);
    // Attribute a (0: position, 1: normal, 2: tangent) of vertex v morphed as at step s.
    const auto morphed = [&](int a, size_t s, size_t v, vec3 value) {
      return morph ? morph->displaced(a, v, value, deform.morph[s]) : value;
    };
    // Vertex v's transform at step s: the node's, or the blend of its joints', blended once
    // per vertex and step for the positions, normals and tangents alike.
    std::vector<mat4> blended;
    size_t blendedStep = stepCount;
    const auto transform = [&](size_t s, size_t v) -> const mat4& {
      if (!weights) return steps[s];
      if (blendedStep != s) {
        blended.resize(vertexCount);
        for (size_t k = 0; k < vertexCount; ++k) blended[k] = weights->matrix(k, skin->steps[s]);
        blendedStep = s;
      }
      return blended[v];
    };
    const bool mirrored = glm::determinant(glm::mat3(transform(0, 0))) < 0.0f;

    const uint32_t base = target.vertexCount;
    const auto accessorOf = [&](const char* name) {
      const auto it = prim.attributes.find(name);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    // Positions and normals per step (step-major: a target with steps holds this primitive only).
    const int normalAccessor = accessorOf("NORMAL");
    for (size_t s = 0; s < stepCount; ++s) {
      for (size_t v = 0; v < vertexCount; ++v) {
        const vec3 p = morphed(0, s, v,
                               vec3(float(positions.get(v, 0)), float(positions.get(v, 1)),
                                    float(positions.get(v, 2))));
        const glm::vec4 pw = transform(s, v) * glm::vec4(p, 1.0f);
        if (!std::isfinite(pw.x + pw.y + pw.z))
          fail(path_, positions.where(), "non-finite position");
        target.positions.push_back(vec3(pw));
      }
      const glm::mat3 nodeNormals = glm::inverseTranspose(glm::mat3(transform(s, 0)));
      appendAttribute(
          target, normalAccessor, where + ".NORMAL", vertexCount, 3, target.normals, anyNormals,
          [&](const AccessorReader& r, size_t v) {
            const glm::mat3 m =
                weights ? glm::inverseTranspose(glm::mat3(transform(s, v))) : nodeNormals;
            return m * morphed(1, s, v,
                               vec3(float(r.get(v, 0)), float(r.get(v, 1)), float(r.get(v, 2))));
          });
    }
    if (stepCount == 1)  // a moving primitive's normal maps take its triangles' frames
      appendAttribute(target, accessorOf("TANGENT"), where + ".TANGENT", vertexCount, 4,
                      target.tangents, anyTangents_, [&](const AccessorReader& r, size_t v) {
                        const glm::vec4 t(
                            morphed(2, 0, v, vec3(r.get(v, 0), r.get(v, 1), r.get(v, 2))),
                            r.get(v, 3));
                        return transformTangent(glm::mat3(transform(0, v)), t);
                      });
    // The uv set its material's textures read (0 without a material or textures).
    const int uvSet = prim.material >= 0 && size_t(prim.material) < uvSets_.size()
                          ? uvSets_[size_t(prim.material)]
                          : 0;
    const std::string uvName = "TEXCOORD_" + std::to_string(uvSet);
    appendAttribute(target, accessorOf(uvName.c_str()), where + "." + uvName, vertexCount, 2,
                    target.uvs, anyUvs, [&](const AccessorReader& r, size_t v) {
                      // glTF's v runs down the image; ours runs up.
                      return vec2(float(r.get(v, 0)), 1.0f - float(r.get(v, 1)));
                    });
    // Vertex colours (linear, RGB or RGBA: the alpha is not read) multiply the base colour;
    // primitives without are white.
    appendAttribute(
        target, accessorOf("COLOR_0"), where + ".COLOR_0", vertexCount, 3, target.colors, anyColors,
        [&](const AccessorReader& r, size_t v) {
          return glm::max(vec3(float(r.get(v, 0)), float(r.get(v, 1)), float(r.get(v, 2))),
                          vec3(0.0f));
        },
        vec3(1.0f), 4);
    target.vertexCount += uint32_t(vertexCount);

    const std::vector<uint32_t> order = readIndices(path_, model_, prim, vertexCount, where);
    if (order.size() > 3 * (kMaxVertices - totalTriangles_))
      fail(path_, where,
           "the scene would have more than " + std::to_string(kMaxVertices) + " triangles");
    uint32_t materialId;
    if (prim.material >= 0) {
      if (size_t(prim.material) >= model_.materials.size())
        fail(path_, where + ".material",
             "material " + std::to_string(prim.material) + " does not exist");
      materialId = uint32_t(prim.material);
    } else {
      materialId = defaultMaterial();
    }
    const auto triangle = [&](uint32_t a, uint32_t b, uint32_t c) {
      if (a == b || b == c || a == c) return;  // degenerate strip joints
      if (mirrored) std::swap(b, c);
      target.indices.insert(target.indices.end(), {base + a, base + b, base + c});
      target.materialIds.push_back(materialId);
      ++totalTriangles_;
    };
    if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
      if (order.size() % 3 != 0)
        fail(path_, where,
             std::to_string(order.size()) + " indices is not a whole number of triangles");
      for (size_t k = 0; k + 2 < order.size(); k += 3)
        triangle(order[k], order[k + 1], order[k + 2]);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t k = 0; k + 2 < order.size(); ++k)
        k % 2 == 0 ? triangle(order[k], order[k + 1], order[k + 2])
                   : triangle(order[k + 1], order[k], order[k + 2]);
    } else {
      for (size_t k = 1; k + 1 < order.size(); ++k) triangle(order[0], order[k], order[k + 1]);
    }
  }

  // Appends an optional per-vertex attribute; once one primitive has it, every vertex gets a
  // value (zeros for primitives without, and for the vertices before).
  // `missing` is the value of those vertices (and of a non-finite one); an accessor of
  // `components`, or of `alsoComponents` when that is not 0, is read.
  template <typename T, typename Read>
  void appendAttribute(const Mesh& target, int accessor, const std::string& where,
                       size_t vertexCount, int components, std::vector<T>& values, bool& any,
                       Read&& read, T missing = T(0.0f), int alsoComponents = 0) {
    const bool has = accessor >= 0;
    if (!has && !any) return;
    if (has && !any) {
      values.assign(target.vertexCount, missing);
      any = true;
    }
    if (!has) {
      values.resize(values.size() + vertexCount, missing);
      return;
    }
    const AccessorReader r(path_, model_, accessor, where);
    if ((r.components() != components &&
         (alsoComponents == 0 || r.components() != alsoComponents)) ||
        r.count() != vertexCount)
      fail(path_, r.where(),
           "expected " + std::to_string(vertexCount) + " VEC" + std::to_string(components) +
               (alsoComponents ? " or VEC" + std::to_string(alsoComponents) : std::string()) +
               " values");
    for (size_t v = 0; v < vertexCount; ++v) {
      const T value = read(r, v);
      bool finite = true;
      for (int c = 0; c < T::length(); ++c) finite = finite && std::isfinite(value[c]);
      values.push_back(finite ? value : missing);
    }
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  const GltfOptions& options_;
  const ImagesNotRead& imagesNotRead_;
  GltfData& out_;
  std::vector<char> onPath_;
  std::vector<Samples> worlds_;  // worldOf's
  std::vector<int> parents_;
  std::vector<char> resolving_;
  std::vector<std::pair<int, mat4>> cameraNodes_;
  std::vector<std::vector<Track>> tracks_;                       // per node
  std::vector<std::optional<gltf::WeightsTrack>> weightTracks_;  // per node
  bool animating_ = false;                                       // motion blur over the shutter
  std::set<std::string> warned_;
  std::vector<gltf::UvSetUse> materialUvSets_;  // the texture references of the material read
  std::vector<int> uvSets_;                     // per material, the uv set its textures read
  // A texture of ours: the image, its conversion, and its factor, wrap modes and uv transform.
  using TextureKey = std::tuple<int, int, std::array<float, 15>>;
  std::map<TextureKey, int> textureIds_;
  std::map<std::pair<int, int>, int> imageIds_;  // (source, texels) -> out_.images; -1: none
  int defaultMaterial_ = -1;
  size_t visits_ = 0, totalVertices_ = 0, totalTriangles_ = 0;
  // Bounds on what instancing can multiply a small file into (about 2 GB of vertices).
  static constexpr size_t kMaxNodeInstances = size_t(1) << 20;
  static constexpr size_t kMaxVertices = size_t(1) << 26;
  bool anyNormals_ = false, anyUvs_ = false, anyColors_ = false, anyTangents_ = false;
  size_t fullTextureBytes_ = 0;  // the images as converted, before the budget halved any
  int texturesHalved_ = 0;
};

}  // namespace

GltfData loadGltf(const std::string& path, const std::string& cameraName) {
  GltfOptions options;
  options.camera = cameraName;
  return loadGltf(path, options);
}

GltfData loadGltf(const std::string& path, const GltfOptions& options) {
  const std::string ext = fs::path(path).extension().string();
  const bool binary = ext == ".glb" || ext == ".GLB";
  // Released once tinygltf has its own copy of the buffers (a .glb's can be most of the file).
  std::string bytes = readFileBytes(path);
  std::vector<std::string> imageUris;
  std::string json = jsonText(path, bytes, binary);
  const std::vector<std::string> files = checkUris(path, json, imageUris);
  // Compressed meshes leave data out that tinygltf insists on: stubbed here, decoded after. Data
  // URIs of image types tinygltf does not know are relabelled.
  const CompressionStubs stubs = stubCompressedData(path, json, binary);
  const bool relabelled = relabelDataUris(json);
  if (!stubs.empty() || relabelled) bytes = binary ? replaceGlbJson(bytes, json) : json;
  std::string().swap(json);

  tinygltf::TinyGLTF loader;
  ImagesNotRead imagesNotRead;
  loader.SetImageLoader(loadGltfImage, &imagesNotRead);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = fs::path(path).parent_path().string();
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           unsigned(bytes.size()), base)
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                          base);
  std::string().swap(bytes);
  if (!ok || !err.empty()) {
    while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
    // tinygltf names a broken image by its index: add the file it was read from.
    const size_t at = err.find("images[");
    if (at != std::string::npos) {
      const size_t index = std::strtoul(err.c_str() + at + 7, nullptr, 10);
      if (index < imageUris.size() && !imageUris[index].empty())
        err += " (file '" + imageUris[index] + "')";
    }
    fail(path, "", err.empty() ? "cannot parse file" : err);
  }

  decodeCompressedMeshes(path, model, stubs);

  GltfData out;
  out.files = files;
  Converter convert(path, model, options, imagesNotRead, out);
  convert.materials();
  convert.animations();
  convert.nodes(options.camera);
  convert.warnAboutTheRest();
  out.mesh.name = fs::path(path).stem().string();
  if (out.mesh.indices.empty() && out.animatedMeshes.empty())
    fail(path, "", "no triangles in the scene");
  repairNormals(out.mesh);
  for (Mesh& mesh : out.animatedMeshes) repairNormals(mesh);
  return out;
}

}  // namespace penumbra
