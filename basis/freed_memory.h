// Keeping freed memory for the process's next allocations.
//
// zbrdf's work allocates and frees large arrays over and over: a frame's electron rates, a
// transport row block, a fit's Jacobian, a prior's projection. By default glibc's allocator
// serves blocks from 128 kB up with fresh mmap() calls and returns them, and the top of its heap,
// to the kernel on free(), so every such array is paid for again in page faults: the kernel maps
// and zeroes each 4 kB page at first touch. On the 2-core VMs zbrdf is built and tested on, a page
// fault costs several microseconds (the hypervisor takes part in it), and a clean run of the test
// suite spent a quarter of its CPU time in the kernel (docs/bench.md, "Freed memory kept, a slow
// EXR header, pinned fuzz targets").
#pragma once

#if defined(__linux__)
#include <malloc.h>  // glibc's mallopt(); defines __GLIBC__ there
#endif

namespace zbrdf {

// Asks the C library's allocator to keep the memory this process frees for its later
// allocations (glibc: no mmap() per allocation, the heap's top trimmed only past 1 GB free),
// instead of handing it back to the kernel. Call it once, early in main(), before threads start;
// the zbrdf CLI, the test binaries and the benchmarks do. Changes no value a program computes,
// only how often the kernel is asked for memory: what a process frees stays resident until it
// exits (a full-resolution simulation's peak grew 5%), which suits short-lived commands such as
// zbrdf's, not a long-running server. Nothing where the C library is not glibc. Inline, so that
// binaries that link no zbrdf library (the source checks) can call it too.
inline void KeepFreedMemoryForReuse() {
#if defined(__GLIBC__) && defined(M_MMAP_MAX) && defined(M_TRIM_THRESHOLD)
  // glibc's malloc options (mallopt(3)), as GLIBC_TUNABLES=glibc.malloc.mmap_max=0:
  // glibc.malloc.trim_threshold=N would set them. Without mmap, a block too large for a thread's
  // arena comes from the main heap (brk), and glibc still falls back to mmap where brk fails. A
  // refused option leaves glibc's default, which is only slower: nothing to report.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // bytes of free memory at the heap's top kept (an int)
#endif
}

}  // namespace zbrdf
