// libFuzzer target for the glTF reader (our URI check, tinygltf, then the conversion of nodes,
// accessors, materials and cameras): an input that starts like a .glb is read as one, anything
// else as a .gltf. Any input must load or raise a SceneError.
#include "scene/gltf_io.h"
#include "tests/fuzz/fuzz_file.h"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  try {
    penumbra::loadGltf(penumbra::fuzz::writeInput(binary ? "input.glb" : "input.gltf", data, size));
  } catch (const penumbra::SceneError&) {
  }
  return 0;
}
