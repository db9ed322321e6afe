// libFuzzer target for the PLY reader (ASCII and both binary byte orders): any input must
// load or raise a SceneError.
#include "scene/mesh_io.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  try {
    penumbra::loadPly(penumbra::fuzz::writeInput("input.ply", data, size));
  } catch (const penumbra::SceneError&) {
  }
  return 0;
}
