// How the `penumbra` executable allocates (cli/allocation.cpp): main calls
// configureAllocation first, and so do the benchmarks that time what `penumbra` does.
#pragma once

namespace penumbra {

// Fixes glibc's mmap threshold at 128 KiB (see the .cpp for why).
void configureAllocation();

}  // namespace penumbra
