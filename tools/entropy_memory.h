// Allocator setting of the short, allocation-heavy subcommands (`entropy`, `decompose`): freed
// memory is kept for reuse instead of being returned to the kernel at once.
//
// glibc serves blocks of 128 KiB and more with fresh mmap'd pages (each first touch a page fault,
// zeroed by the kernel) and trims freed heap tops; sample entropy and the VMD allocate many
// N-sized buffers per mode, so at N = 20k a `decompose` run spent ~25% of its CPU time in page
// faults (docs/explanation/performance.md, "decompose whole process"). Blocks up to 32 MiB now come
// from the heap and up to 64 MiB of free heap is kept; larger blocks (the VMD of a long record)
// are still mapped and unmapped, so the peak memory of long records does not grow. Not glibc:
// nothing changes.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gyrocomp::cli {

inline void ReuseFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}

}  // namespace gyrocomp::cli
