// The mdnet lane-group kernel with the baseline x86-64 vectors (SSE2, 4 lanes).
#include "methods/bp/mdnet.h"

#define MDNET_LANES 4

namespace penumbra::mdnet::kernel_sse {
using ::penumbra::mdnet::detail::Group;
#include "methods/bp/mdnet_kernel.inc"
}  // namespace penumbra::mdnet::kernel_sse

void penumbra::mdnet::detail::trainGroupSse(const Group& group) { kernel_sse::trainGroup(group); }
#undef MDNET_LANES
