// libFuzzer target for the OBJ reader (strict checks, then tinyobjloader, then the mesh
// build): any input must load or raise a SceneError. A fixed MTL library, m.mtl, sits beside
// the input so that mtllib and usemtl lines reach the material mapping too.
#include "scene/mesh_io.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  static const bool ready = [] {
    penumbra::fuzz::writeInput("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nnewmtl b\nKe 1 1 1\n");
    return true;
  }();
  (void)ready;
  try {
    penumbra::loadObj(penumbra::fuzz::writeInput("input.obj", data, size));
  } catch (const penumbra::SceneError&) {
  }
  return 0;
}
