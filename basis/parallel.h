// A minimal parallel loop over an index range: the hot loops over pixels and directions, and the
// coarse loops of batch commands over whole materials.
#pragma once

#include <cstdint>
#include <functional>

namespace zbrdf {

// Number of worker threads: $ZBRDF_THREADS if set (>= 1), else the hardware concurrency.
int WorkerThreads();

// Calls body(begin, end) on disjoint chunks covering [0, count), from up to WorkerThreads()
// threads, chunks handed out dynamically (grain: chunk size; every chunk has at most grain items,
// also on one thread, so a body may size stack buffers by it). The first exception thrown by a
// body is rethrown after all threads have stopped. Deterministic results require that each
// index's work depends only on the index, not on the chunking.
void ParallelFor(int64_t count, int64_t grain, const std::function<void(int64_t, int64_t)>& body);

// The same from at most max_threads threads (clamped to [1, 256]), whatever WorkerThreads()
// says: for a loop whose items are whole jobs (materials of a batch, each capture and fit itself
// parallel inside), where the caller decides how many run at once.
void ParallelFor(int64_t count, int64_t grain, int max_threads,
                 const std::function<void(int64_t, int64_t)>& body);

// item(i) for each i in [0, count), items handed out one at a time to at most max_threads
// threads: for loops whose items are whole jobs (the materials of a batch). A thread whose item
// returns false takes no more items (it was interrupted, or could not write its output); the
// others go on.
void ParallelForEach(int64_t count, int max_threads, const std::function<bool(int64_t)>& item);

}  // namespace zbrdf
