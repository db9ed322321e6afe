// The mdnet lane-group kernel for AVX-512, 16 lanes. CMake gives this file its
// instruction-set flags; mdnet.cpp calls it only when the CPU has them.
#include "methods/bp/mdnet.h"

#define MDNET_LANES 16

namespace penumbra::mdnet::kernel_avx512 {
using ::penumbra::mdnet::detail::Group;
#include "methods/bp/mdnet_kernel.inc"
}  // namespace penumbra::mdnet::kernel_avx512

void penumbra::mdnet::detail::trainGroupAvx512(const Group& group) {
  kernel_avx512::trainGroup(group);
}
#undef MDNET_LANES
