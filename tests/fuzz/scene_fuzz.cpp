// libFuzzer target for the JSON scene parser: any input must either load or raise a
// SceneError; a crash, hang, leak or sanitizer report is a bug.
#include "scene/scene_loader.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    penumbra::parseSceneJson(text, "fuzz.json", "/nonexistent-fuzz-dir");
  } catch (const penumbra::SceneError&) {
  }
  return 0;
}
