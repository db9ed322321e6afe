// An allocator for the large per-pixel arrays (the film): blocks of 2 MiB or more are aligned
// to 2 MiB and advised as transparent huge pages (madvise(MADV_HUGEPAGE), where the kernel
// allows them), so that filling a new array takes one page fault per 2 MiB instead of one per
// 4 KiB. A 1280x720 film is 160 MB: about 40,000 faults, a tenth of a second on two cores, at
// every camera move, without it. Smaller blocks, and kernels without huge pages, get plain
// memory. The values are unchanged; only their pages differ.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace penumbra {

inline constexpr size_t kLargePageBytes = size_t(2) << 20;

template <typename T>
struct LargePageAllocator {
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
    // Rounded up to whole huge pages, as aligned_alloc requires a multiple of the alignment.
    const size_t rounded = (bytes + kLargePageBytes - 1) / kLargePageBytes * kLargePageBytes;
    void* p = std::aligned_alloc(kLargePageBytes, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: a refusal leaves plain pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t) { std::free(p); }

  template <typename U>
  bool operator==(const LargePageAllocator<U>&) const {
    return true;
  }
};

}  // namespace penumbra
