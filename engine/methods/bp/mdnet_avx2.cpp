// The mdnet lane-group kernel for AVX2 + FMA, 8 lanes. CMake gives this file its
// instruction-set flags; mdnet.cpp calls it only when the CPU has them.
#include "methods/bp/mdnet.h"

#define MDNET_LANES 8

namespace penumbra::mdnet::kernel_avx2 {
using ::penumbra::mdnet::detail::Group;
#include "methods/bp/mdnet_kernel.inc"
}  // namespace penumbra::mdnet::kernel_avx2

void penumbra::mdnet::detail::trainGroupAvx2(const Group& group) { kernel_avx2::trainGroup(group); }
#undef MDNET_LANES
