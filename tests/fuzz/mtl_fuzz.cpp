// libFuzzer target for the MTL reader: a fixed OBJ that uses every material of the fuzzed
// library `input.mtl`; any input must load or raise a SceneError.
#include "scene/mesh_io.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  static const std::string obj = penumbra::fuzz::writeInput(
      "uses_input.obj",
      "mtllib input.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 2\n");
  penumbra::fuzz::writeInput("input.mtl", data, size);
  try {
    penumbra::loadObj(obj);
  } catch (const penumbra::SceneError&) {
  }
  return 0;
}
