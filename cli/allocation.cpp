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
  // The heaps below that threshold are trimmed only once their free top exceeds 64 MiB (by
  // default 128 KiB, or twice the mmap threshold): the reconstruction's per-tile blocks, made
  // and freed in every worker's arena, otherwise shrank the heaps and faulted them back in at
  // every picture. bench_restart on the asset's .glb at 1280x720: 452k page faults -> 42k
  // (with LargeVector's huge pages), reconstructions in rounds 4-5 from 1.28-1.38 s to
  // 0.70-0.74 s. A replaced method's freed blocks are given back at once all the same
  // (returnFreedMemory, core/large_pages.h).
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}

}  // namespace penumbra
