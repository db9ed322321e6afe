// Draco encoding for gltf_compression_test.cpp, built as a shared library of its own
// (penumbra_test_draco) for the reason scene/draco_decode.h gives: libdraco.a's copies of
// tinygltf and stb_image stay hidden inside it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::test {

struct DracoEncoded {
  std::string bytes;                  // the Draco mesh data
  uint32_t positionId = 0, uvId = 0;  // the attributes' unique ids in it
  size_t points = 0, faces = 0;       // what a decoder reads back (the encoder may merge points)
};

// Triangles with a position and a uv per corner (3 indices a triangle into both lists),
// positions quantised to 16 bits and uvs to 14.
__attribute__((visibility("default"))) DracoEncoded encodeDraco(
    const std::vector<std::array<float, 3>>& positions,
    const std::vector<std::array<float, 2>>& uvs, const std::vector<uint32_t>& indices);

}  // namespace penumbra::test
