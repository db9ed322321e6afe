// The BP-network training kernel for SSE, 4 lanes: the baseline every x86-64 CPU runs, used
// where AVX2 + FMA are missing. It gets the project's default instruction-set flags.
#include <immintrin.h>

#include <cstdint>

#include "methods/bp/network.h"

#define PENUMBRA_BP_LANES 4

namespace penumbra::bpnet_sse {

#include "methods/bp/network_kernel.inc"

}  // namespace penumbra::bpnet_sse
