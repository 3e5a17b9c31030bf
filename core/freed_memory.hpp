#pragma once
// Freed memory kept for the next allocation instead of being returned to the kernel: a process
// that runs one simulation after another (`bench`, the benchmarks) then touches fresh pages only
// once. On this project's 2-core VMs a first touch of a 4 KiB page costs about 20 us (the
// paravirtual fault path): a figure-eight simulation re-faulted its scans' memory for 20 % of its
// time (docs/notebook.md, "Physics real-time factor").

namespace slamprep {

/// glibc: no trimming of the heap's top and large blocks from the heap rather than fresh mmaps
/// (up to glibc's 32 MiB limit). Peak memory is unchanged; it is only not handed back early.
/// Call once, early in main(); a no-op elsewhere than glibc.
void keepFreedMemory();

}  // namespace slamprep
