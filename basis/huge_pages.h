// Transparent huge pages for large arrays read at random addresses (the transport build's
// direction grid, the frames' interleaved projector radiances): one TLB entry covers 2 MB
// instead of 4 kB, so such reads stop missing the TLB as well as the cache. Where the kernel's
// THP setting is "madvise" (Debian's default) memory gets huge pages only when asked, before its
// pages are first touched. A hint: no effect on values, none where THP is off or unsupported.
#pragma once

#include <cstddef>
#include <vector>

namespace zbrdf {

// Asks for huge pages on the 2 MB-aligned pages inside [data, data + bytes), whose contents the
// caller is about to overwrite (madvise MADV_HUGEPAGE on Linux; nothing elsewhere). Pages already
// touched there are first given back (MADV_DONTNEED; they read as zeros after), so that they too
// come back as huge pages when next touched: the allocator hands out memory the process touched
// before, since it keeps what is freed (basis/freed_memory.h).
void AdviseHugePagesDiscardingContents(void* data, size_t bytes);

// Gives back to the system the whole pages inside [data, data + bytes), whose contents the
// caller no longer needs (MADV_DONTNEED on Linux: they read as zeros if touched again; nothing
// elsewhere).
void DiscardPages(void* data, size_t bytes);

// *v emptied, with room for n elements in memory allocated afresh and advised, not yet touched.
template <typename T>
void ReserveInHugePages(std::vector<T>* v, size_t n) {
  std::vector<T>().swap(*v);
  v->reserve(n);
  AdviseHugePagesDiscardingContents(v->data(), n * sizeof(T));
}

// *v = n copies of value, in memory allocated afresh and advised before it is filled.
template <typename T>
void AssignInHugePages(std::vector<T>* v, size_t n, const T& value) {
  ReserveInHugePages(v, n);
  v->assign(n, value);
}

// *v = n default-constructed elements in memory allocated afresh and advised. For a type whose
// default constructor writes nothing (simulate/transport_row.h's TransportEntry) no page is
// touched here: the caller's writes touch them first, on as many threads as fill them.
template <typename T>
void ResizeInHugePages(std::vector<T>* v, size_t n) {
  ReserveInHugePages(v, n);
  v->resize(n);
}

// *v cut to its first n elements in place (n <= size), and the memory of its capacity past them
// given back (DiscardPages): for an array reserved for the most it could hold, filled with less.
template <typename T>
void ShrinkInPlace(std::vector<T>* v, size_t n) {
  v->resize(n);
  DiscardPages(v->data() + n, (v->capacity() - n) * sizeof(T));
}

}  // namespace zbrdf
