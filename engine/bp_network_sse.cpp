// The BP-network training kernel for SSE (x86-64 baseline, 4 lanes); also the fallback on CPUs without AVX2+FMA. CMake gives this file its
// instruction-set flags; bp_network.cpp calls it only when the CPU has them.
#include <immintrin.h>

#include <cstdint>

#include "engine/bp_network.h"

#define PENUMBRA_BP_LANES 4

namespace penumbra::bpnet_sse {

#include "engine/bp_network_kernel.inc"

}  // namespace penumbra::bpnet_sse
