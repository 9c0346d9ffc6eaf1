// A minimal parallel loop over an index range for the hot loops over pixels and directions.
#pragma once

#include <cstdint>
#include <functional>

namespace zbrdf {

// Number of worker threads: $ZBRDF_THREADS if set (>= 1), else the hardware concurrency.
int WorkerThreads();

// Calls body(begin, end) on disjoint chunks covering [0, count), from up to WorkerThreads()
// threads, chunks handed out dynamically (grain: chunk size). The first exception thrown by a
// body is rethrown after all threads have stopped. Deterministic results require that each
// index's work depends only on the index, not on the chunking.
void ParallelFor(int64_t count, int64_t grain, const std::function<void(int64_t, int64_t)>& body);

}  // namespace zbrdf
