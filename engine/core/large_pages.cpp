#include "core/large_pages.h"

#include <malloc.h>
#include <sys/mman.h>

#include <algorithm>
#include <mutex>

namespace penumbra {

namespace {

// The blocks kept for reuse, oldest first, and what is in use, under one lock: a
// reconstruction takes and gives a few hundred blocks, each of megabytes, so the lock is cheap
// beside filling one.
struct KeptBlocks {
  struct Block {
    void* start;
    size_t bytes;
  };
  std::mutex mutex;
  std::vector<Block> kept;
  size_t keptBytes = 0, inUseBytes = 0;
  size_t mostInUse = 0;  // the most in use at once since the last flush
};

KeptBlocks& keptBlocks() {
  static KeptBlocks* blocks = new KeptBlocks;  // never destroyed: freed from static destructors
  return *blocks;
}

void* mapAligned(size_t bytes) {
  // Mapped directly rather than taken from malloc's heap, so that dropping a block gives its
  // pages back at once: huge pages kept in malloc's heap raised a 1920x1080 reconstruction's
  // peak by 200 bytes per pixel. The mapping is 2 MiB larger than the block, then cut to a
  // block aligned to 2 MiB (the kernel backs only aligned 2 MiB ranges with huge pages).
  void* mapped = mmap(nullptr, bytes + kLargePageBytes, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED) throw std::bad_alloc();
  const uintptr_t start = reinterpret_cast<uintptr_t>(mapped);
  const uintptr_t aligned = (start + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
  if (aligned > start) munmap(mapped, aligned - start);
  if (const size_t tail = start + kLargePageBytes - aligned; tail > 0)
    munmap(reinterpret_cast<void*>(aligned + bytes), tail);
  void* p = reinterpret_cast<void*>(aligned);
  madvise(p, bytes, MADV_HUGEPAGE);  // advice only: a refusal leaves plain pages
  return p;
}

}  // namespace

void* takeLargeBlock(size_t bytes) {
  KeptBlocks& k = keptBlocks();
  std::vector<KeptBlocks::Block> dropped;
  {
    std::lock_guard lock(k.mutex);
    // The most recently kept block of this size: the likeliest to be in the cache still.
    for (size_t i = k.kept.size(); i-- > 0;)
      if (k.kept[i].bytes == bytes) {
        void* p = k.kept[i].start;
        k.kept.erase(k.kept.begin() + ptrdiff_t(i));
        k.keptBytes -= bytes;
        k.inUseBytes += bytes;
        k.mostInUse = std::max(k.mostInUse, k.inUseBytes);
        return p;
      }
    // A new mapping: first drop the oldest kept blocks (of other sizes) until the blocks
    // mapped stay within the most in use at once.
    k.inUseBytes += bytes;
    k.mostInUse = std::max(k.mostInUse, k.inUseBytes);
    size_t drop = 0;
    while (drop < k.kept.size() && k.inUseBytes + k.keptBytes > k.mostInUse)
      k.keptBytes -= k.kept[drop++].bytes;
    dropped.assign(k.kept.begin(), k.kept.begin() + ptrdiff_t(drop));
    k.kept.erase(k.kept.begin(), k.kept.begin() + ptrdiff_t(drop));
  }
  for (const KeptBlocks::Block& b : dropped) munmap(b.start, b.bytes);
  try {
    return mapAligned(bytes);
  } catch (...) {
    std::lock_guard lock(k.mutex);
    k.inUseBytes -= bytes;
    throw;
  }
}

void giveLargeBlock(void* block, size_t bytes) {
  KeptBlocks& k = keptBlocks();
  std::lock_guard lock(k.mutex);
  // What was in use, this block included, was within mostInUse: keeping it stays within too.
  k.inUseBytes -= bytes;
  k.kept.push_back({block, bytes});
  k.keptBytes += bytes;
}

LargeBlockBytes largeBlockBytes() {
  KeptBlocks& k = keptBlocks();
  std::lock_guard lock(k.mutex);
  return {k.keptBytes, k.inUseBytes, k.mostInUse};
}

void returnFreedMemory() {
  KeptBlocks& k = keptBlocks();
  std::vector<KeptBlocks::Block> dropped;
  {
    std::lock_guard lock(k.mutex);
    dropped.swap(k.kept);
    k.keptBytes = 0;
    k.mostInUse = k.inUseBytes;
  }
  for (const KeptBlocks::Block& b : dropped) munmap(b.start, b.bytes);
  trimMallocHeaps();
}

void trimMallocHeaps() {
  // Blocks freed inside malloc's heaps stay resident until the top of a heap holds more than
  // the trim threshold (64 MiB in `penumbra`, cli/allocation.cpp), so a replaced method's
  // smaller vectors would stay beside its successor's. It takes 1-7 ms at 1280x720 (the
  // asset's .glb, a drag), on the render thread, once per restart.
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

}  // namespace penumbra
