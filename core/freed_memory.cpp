#include "slamprep/core/freed_memory.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>  // defines __GLIBC__ on glibc
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#endif

namespace slamprep {
namespace {

#if defined(__GLIBC__)
constexpr int kMaxMmapThreshold = 32 << 20;  // glibc's DEFAULT_MMAP_THRESHOLD_MAX (64-bit)
#endif

#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
constexpr std::size_t kHugePage = 2 << 20;  // x86-64's and arm64's (4 KiB pages) PMD size

/// MADV_HUGEPAGE on the whole huge pages inside [begin, begin + bytes).
void adviseHugePagesInside(void* begin, std::size_t bytes) {
  const auto address = reinterpret_cast<std::uintptr_t>(begin);
  const std::uintptr_t first = (address + kHugePage - 1) / kHugePage * kHugePage;
  const std::uintptr_t last = (address + bytes) / kHugePage * kHugePage;
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}
#endif

}  // namespace

void keepFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, kMaxMmapThreshold);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

void backNextAllocationsWithHugePages(std::size_t bytes) {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
  // Blocks below the mmap threshold come from the heap and go back to it when freed.
  constexpr std::size_t kMaxBlock = kMaxMmapThreshold - 2 * kHugePage;
  std::vector<void*> blocks;
  for (std::size_t left = bytes; left > 0;) {
    const std::size_t advised = std::min(left, kMaxBlock);
    void* block = std::malloc(advised + kHugePage);  // a huge page more: room to align inside
    if (block == nullptr) break;
    blocks.push_back(block);
    adviseHugePagesInside(block, advised + kHugePage);
    left -= advised;
  }
  for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) std::free(*it);
#else
  (void)bytes;
#endif
}

}  // namespace slamprep
