// The denoiser's block sweep for AVX2 (8 lanes); CMake gives this file -mavx2, sweep.cpp calls it
// only when the CPU has AVX2.
#include "methods/recon/sweep.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace penumbra::recon::detail::sweep_avx2 {
namespace {

#include "methods/recon/sweep_kernels.inc"

}  // namespace

#include "methods/recon/sweep_block.inc"

}  // namespace penumbra::recon::detail::sweep_avx2
