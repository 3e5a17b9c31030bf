#include "slamprep/core/freed_memory.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

// Under AddressSanitizer malloc is the sanitizer's, not glibc's: nothing to test there.
#if defined(__SANITIZE_ADDRESS__)
#define SLAMPREP_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SLAMPREP_ASAN 1
#endif
#endif

#if defined(__GLIBC__) && !defined(SLAMPREP_ASAN)
#include <malloc.h>

namespace slamprep {
namespace {

// 8 MiB in 24 KiB blocks (a simulated scan's size) freed again: with the default thresholds
// glibc hands the heap's top back to the kernel (keepcost at most 128 KiB); kept, most of the
// 8 MiB stays at the top for the next run (6.5 MiB here).
TEST(FreedMemory, FreedBlocksStayInTheProcess) {
  keepFreedMemory();
  constexpr std::size_t kBlock = 24 << 10, kBlocks = 8 * 1024 / 24;
  {
    std::vector<std::unique_ptr<char[]>> blocks;
    for (std::size_t i = 0; i < kBlocks; ++i) blocks.push_back(std::make_unique<char[]>(kBlock));
  }
  EXPECT_GE(mallinfo2().keepcost, kBlock * kBlocks / 2);
}

/// The process's anonymous memory on transparent huge pages (/proc/self/smaps_rollup), bytes.
std::size_t anonHugePageBytes() {
  std::ifstream rollup("/proc/self/smaps_rollup");
  std::string key;
  std::size_t kib = 0;
  while (rollup >> key) {
    if (key == "AnonHugePages:" && rollup >> kib) return kib << 10;
  }
  return 0;
}

/// The kernel's THP mode lets a process ask for huge pages ("[always]" or "[madvise]").
bool hugePagesOnRequest() {
  std::ifstream enabled("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string modes((std::istreambuf_iterator<char>(enabled)), {});
  return modes.find("[always]") != std::string::npos ||
         modes.find("[madvise]") != std::string::npos;
}

// 48 MiB in scan-sized blocks, touched, after asking for huge pages for them: where the kernel
// allows it they lie on huge pages (all but the ends of the two advised blocks and memory the
// heap held already, so at least half); where it does not, on none.
TEST(FreedMemory, NextAllocationsOnHugePages) {
  keepFreedMemory();
  constexpr std::size_t kBlock = 24 << 10, kBytes = 48 << 20;
  const std::size_t before = anonHugePageBytes();
  backNextAllocationsWithHugePages(kBytes);
  std::vector<std::unique_ptr<char[]>> blocks;
  for (std::size_t i = 0; i < kBytes / kBlock; ++i)
    blocks.push_back(std::make_unique<char[]>(kBlock));
  const std::size_t gained = anonHugePageBytes() - before;
  if (hugePagesOnRequest()) {
    EXPECT_GE(gained, kBytes / 2);
  } else {
    EXPECT_EQ(gained, 0U);
  }
}

}  // namespace
}  // namespace slamprep
#endif
