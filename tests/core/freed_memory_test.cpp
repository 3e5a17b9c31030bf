#include "slamprep/core/freed_memory.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
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

}  // namespace
}  // namespace slamprep
#endif
