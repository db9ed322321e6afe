// Compressed glTF meshes for gltf_io.cpp: KHR_draco_mesh_compression (Draco, as Blender's and
// glTF-Transform's exporters write it) and EXT_meshopt_compression / KHR_meshopt_compression
// (meshoptimizer's gltfpack). Both are decoded once, on load, into plain accessors, so the rest
// of the reader sees an uncompressed file. Errors name the file and the element. Internal to
// the glTF reader.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <utility>
#include <vector>

namespace penumbra::gltf {

// What stubCompressedData gave placeholder data for tinygltf to read.
struct CompressionStubs {
  // Meshopt fallback buffers (no data of their own: every view of theirs is decoded from a
  // compressed view), by index, with their size as the JSON gave it.
  std::vector<std::pair<size_t, size_t>> fallbacks;
  // Index accessors of Draco primitives that had no buffer view (tinygltf refuses one).
  std::vector<int> dracoIndices;
  bool empty() const { return fallbacks.empty() && dracoIndices.empty(); }
};

// Rewrites the JSON of a file that uses mesh compression so that tinygltf reads it: each meshopt
// fallback buffer with no URI gets a one-byte data: URI (tinygltf refuses a buffer without data,
// or copies a .glb's binary chunk into it), and each Draco primitive's index accessor without a
// buffer view gets the Draco data's view. Returns what it stubbed, for decodeCompressedMeshes;
// nothing (and `json` untouched) for a file without either. `binary`: the JSON of a .glb, whose
// first buffer is its binary chunk.
CompressionStubs stubCompressedData(const std::string& path, std::string& json, bool binary);

// A .glb's bytes with its JSON chunk replaced by `json` (padded with spaces); the other chunks
// as they were.
std::string replaceGlbJson(const std::string& glb, const std::string& json);

// Decodes the model's compressed meshes in place: every meshopt-compressed buffer view into
// its fallback buffer (sized as `stubs` says), then every Draco-compressed primitive into a
// new buffer that its attribute and index accessors then read. Throws SceneError naming the
// file and the buffer view or primitive on data that does not decode or does not match its
// accessors.
void decodeCompressedMeshes(const std::string& path, tinygltf::Model& model,
                            const CompressionStubs& stubs);

// Whether decodeCompressedMeshes decodes the extension.
bool isMeshCompression(const std::string& extension);

}  // namespace penumbra::gltf
