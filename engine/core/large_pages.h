// An allocator for the large per-pixel arrays (the film, the reconstruction's planes): blocks
// of 2 MiB or more are mapped on their own, aligned to 2 MiB and advised as transparent huge
// pages (madvise(MADV_HUGEPAGE), where the kernel
// allows them), so that filling a new array takes one page fault per 2 MiB instead of one per
// 4 KiB. A 1280x720 film is 160 MB: about 40,000 faults, a tenth of a second on two cores, at
// every camera move, without it. Smaller blocks, and kernels without huge pages, get plain
// memory. The values are unchanged; only their pages differ.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

namespace penumbra {

inline constexpr size_t kLargePageBytes = size_t(2) << 20;

template <typename T>
struct LargePageAllocator {
  static size_t roundedBytes(size_t bytes) {
    return (bytes + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
  }

  using value_type = T;
  LargePageAllocator() = default;
  template <typename U>
  LargePageAllocator(const LargePageAllocator<U>&) {}

  T* allocate(size_t n) {
    if (n > size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes < kLargePageBytes) {
      if (void* p = std::malloc(bytes > 0 ? bytes : 1)) return static_cast<T*>(p);
      throw std::bad_alloc();
    }
    // Mapped directly rather than taken from malloc's heap, so that freeing a block gives its
    // pages back at once: a reconstruction makes and frees its planes band after band, and
    // huge pages kept in the heap between them raised a 1920x1080 reconstruction's peak by
    // 200 bytes per pixel. The mapping is 2 MiB larger than the block, then cut to a block
    // aligned to 2 MiB (the kernel backs only aligned 2 MiB ranges with huge pages).
    const size_t rounded = roundedBytes(bytes);
    void* mapped = mmap(nullptr, rounded + kLargePageBytes, PROT_READ | PROT_WRITE,
                        MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t start = reinterpret_cast<uintptr_t>(mapped);
    const uintptr_t aligned = (start + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
    if (aligned > start) munmap(mapped, aligned - start);
    if (const size_t tail = start + kLargePageBytes - aligned; tail > 0)
      munmap(reinterpret_cast<void*>(aligned + rounded), tail);
    void* p = reinterpret_cast<void*>(aligned);
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: a refusal leaves plain pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kLargePageBytes)
      std::free(p);
    else
      munmap(p, roundedBytes(bytes));
  }

  template <typename U>
  bool operator==(const LargePageAllocator<U>&) const {
    return true;
  }
};

// A vector whose blocks of 2 MiB or more are huge pages: for per-pixel arrays that are made
// afresh every round (the reconstruction's planes and maps), whose first touch would otherwise
// cost one page fault per 4 KiB.
template <typename T>
using LargeVector = std::vector<T, LargePageAllocator<T>>;

// Gives the memory freed inside malloc's heaps back to the system (malloc_trim): called once a
// replaced method is freed, so that its pages do not stay resident beside its successor's.
void returnFreedMemory();

}  // namespace penumbra
