// The BP-network training kernel for AVX-512 (F, VL, DQ), 16 lanes. CMake gives this file its
// instruction-set flags; network.cpp calls it only when the CPU has them.
#include <immintrin.h>

#include <cstdint>

#include "methods/bp/network.h"

#define PENUMBRA_BP_LANES 16

namespace penumbra::bpnet_avx512 {

#include "methods/bp/network_kernel.inc"

}  // namespace penumbra::bpnet_avx512
