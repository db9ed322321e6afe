// An allocator for the large per-pixel arrays (the film, the reconstruction's planes): blocks
// of 2 MiB or more are mapped on their own, aligned to 2 MiB and advised as transparent huge
// pages (madvise(MADV_HUGEPAGE), where the kernel allows them), so that filling a new array
// takes one page fault per 2 MiB instead of one per 4 KiB. A 1280x720 film is 160 MB: about
// 40,000 faults, a tenth of a second on two cores, at every camera move, without it. A freed
// block is kept for the next array of its size, within the peak of the blocks in use (see
// giveLargeBlock). Smaller blocks, and kernels without huge pages, get plain memory. The values
// are unchanged; only their pages differ.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

namespace penumbra {

inline constexpr size_t kLargePageBytes = size_t(2) << 20;

// A block of `bytes` (a multiple of kLargePageBytes), aligned to 2 MiB and advised as huge
// pages: one freed earlier of the same size (giveLargeBlock) if one is kept, else a new mapping.
// Throws std::bad_alloc.
void* takeLargeBlock(size_t bytes);
// Frees a block from takeLargeBlock. It is kept for reuse while the blocks in use and the kept
// ones together stay within the most in use at once since the last returnFreedMemory: the
// reconstruction makes and frees the same planes every round, and a new mapping costs the
// kernel's clearing of every page (17% of a 1280x720 reconstruction's cycles). Kept blocks
// never raise the peak of mapped blocks above that of the blocks in use.
void giveLargeBlock(void* block, size_t bytes);

// The bytes of large blocks kept for reuse, in use, and the most in use at once since the last
// returnFreedMemory (for tests and reports).
struct LargeBlockBytes {
  size_t kept = 0, inUse = 0, mostInUse = 0;
};
LargeBlockBytes largeBlockBytes();

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
    return static_cast<T*>(takeLargeBlock(roundedBytes(bytes)));
  }
  void deallocate(T* p, size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kLargePageBytes)
      std::free(p);
    else
      giveLargeBlock(p, roundedBytes(bytes));
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

// Gives what is free inside malloc's heaps back to the system (malloc_trim): called once a
// replaced method is freed, so that its smaller vectors do not stay resident beside its
// successor's. Its large blocks stay kept: the successor's film and planes take them.
void trimMallocHeaps();

// Gives all freed memory back to the system: the large blocks kept for reuse, then
// trimMallocHeaps. Called when a render has no more work (a batch's last picture, a session
// that pauses or finishes).
void returnFreedMemory();

}  // namespace penumbra
