#include "basis/huge_pages.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace zbrdf {

void AdviseHugePagesDiscardingContents(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
  if (end <= begin) return;
  void* const range = reinterpret_cast<void*>(begin);
  // Failure (THP off, an old kernel) leaves ordinary pages: nothing to report. The range lies
  // inside the caller's block, so the allocator's own bookkeeping around it is never discarded.
  ::madvise(range, end - begin, MADV_HUGEPAGE);
  ::madvise(range, end - begin, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

void DiscardPages(void* data, size_t bytes) {
#if defined(__linux__)
  const uintptr_t page = static_cast<uintptr_t>(::sysconf(_SC_PAGESIZE));
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + page - 1) & ~(page - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(page - 1);
  if (end <= begin) return;
  ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace zbrdf
