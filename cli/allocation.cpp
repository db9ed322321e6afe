// The `penumbra` executable's allocation (cli/allocation.h); the benchmarks that time what it
// does call it too.
#include "cli/allocation.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace penumbra {

void configureAllocation() {
#if defined(__GLIBC__)
  // Every block of 128 KiB or more is its own mapping, returned to the system when freed. By
  // default glibc raises this threshold to the largest block freed so far (up to 32 MiB), so
  // the per-pixel planes of a large image (a reconstruction's bands, a snapshot's maps) are
  // then carved from the heap and stay resident after they are freed: measured on the asset
  // scene at 1920x1080, the headless view's peak fell from 1,098,240 to 1,022,132 KiB with a
  // fixed threshold, and the window's soak (bench/soak.sh --asset) stopped growing after
  // warm-up (13 % without it). The price is a page fault per 4 KiB of every such block, at
  // every picture (bench/restart_bench.cpp times it).
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

}  // namespace penumbra
