#pragma once
// Fewer page faults: freed memory kept for the next allocation instead of being returned to the
// kernel, so a process that runs one simulation after another (`bench`, the benchmarks) touches
// fresh pages only once; and a run's large logs on huge pages, so that a single run's fresh
// memory takes few faults. On this project's 2-core VMs a first touch of a 4 KiB page costs about
// 20 us (the paravirtual fault path): a figure-eight simulation re-faulted its scans' memory for
// 20 % of its time (docs/notebook.md, "Physics real-time factor").

#include <cstddef>

namespace slamprep {

/// glibc: no trimming of the heap's top and large blocks from the heap rather than fresh mmaps
/// (up to glibc's 32 MiB limit). Peak memory is unchanged; it is only not handed back early.
/// Call once, early in main(); a no-op elsewhere than glibc.
void keepFreedMemory();

/// The next `bytes` of allocations on transparent huge pages: fresh memory then takes one page
/// fault per 2 MiB instead of one per 4 KiB. glibc, with keepFreedMemory()'s thresholds: blocks of
/// that size are taken from the heap, advised MADV_HUGEPAGE and freed again, so the allocations
/// that follow are cut from them. Needs the kernel's THP mode "madvise" or "always"; memory
/// already touched keeps its pages; a no-op elsewhere than glibc on Linux.
void backNextAllocationsWithHugePages(std::size_t bytes);

}  // namespace slamprep
