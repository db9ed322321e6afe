// The denoiser's block sweep for the baseline (SSE4.2 of x86-64-v2).
#include "methods/recon/sweep.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace penumbra::recon::detail::sweep_sse {
namespace {

#include "methods/recon/sweep_kernels.inc"

}  // namespace

#include "methods/recon/sweep_block.inc"

}  // namespace penumbra::recon::detail::sweep_sse
