// Draco mesh decoding behind a plain interface, built as a shared library of its own
// (penumbra_draco): Debian's libdraco.a carries its own copies of tinygltf and stb_image, which
// must not stand in for the system ones the rest of Penumbra links. The library links the
// archive with its symbols hidden and exports only decodeDraco. Internal to the glTF reader
// (scene/gltf_compression.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::gltf {

// One attribute to read from a Draco mesh: its unique id in the Draco data, and the glTF
// component type (5120-5126) and component count (1-4) to convert every point's value to.
struct DracoAttribute {
  uint32_t uniqueId = 0;
  int componentType = 0;
  int components = 0;
  std::vector<unsigned char> bytes;  // out: the values, point after point, tightly packed
};

// What decodeDraco read: the triangles' corners (3 per face) and the number of points.
struct DracoMesh {
  std::vector<uint32_t> indices;
  size_t points = 0;
};

// Decodes `size` bytes of Draco mesh data into `mesh`, and each of `attributes` (those whose
// id the data has, converted to their type). Returns what went wrong (empty on success): data
// that does not decode, or an attribute id the data does not have.
__attribute__((visibility("default"))) std::string decodeDraco(
    const unsigned char* data, size_t size, DracoMesh& mesh,
    std::vector<DracoAttribute>& attributes);

}  // namespace penumbra::gltf
