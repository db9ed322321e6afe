// libFuzzer target for one image reader, chosen at build time by PENUMBRA_FUZZ_EXT (".exr",
// ".png" or ".pfm"): any input must decode or raise an ImageIoError.
#include "core/image_io.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 16) return 0;
  try {
    penumbra::readImage(
        penumbra::fuzz::writeInput(std::string("input") + PENUMBRA_FUZZ_EXT, data, size));
  } catch (const penumbra::ImageIoError&) {
  }
  return 0;
}
