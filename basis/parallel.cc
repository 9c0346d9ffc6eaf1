#include "basis/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace zbrdf {

int WorkerThreads() {
  if (const char* env = std::getenv("ZBRDF_THREADS")) {
    const int n = std::atoi(env);
    if (n >= 1) return std::min(n, 256);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

void ParallelFor(int64_t count, int64_t grain,
                 const std::function<void(int64_t, int64_t)>& body) {
  ParallelFor(count, grain, WorkerThreads(), body);
}

namespace {

// Chunks [begin, min(count, begin + grain)) handed out dynamically to `threads` threads (the
// caller is one); a thread whose chunk returns false takes no more. The first exception stops
// every thread and is rethrown once they have all stopped.
void RunChunks(int64_t count, int64_t grain, int threads,
               const std::function<bool(int64_t, int64_t)>& chunk) {
  std::atomic<int64_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&]() {
    while (true) {
      const int64_t begin = next.fetch_add(grain);
      if (begin >= count) return;
      try {
        if (!chunk(begin, std::min(count, begin + grain))) return;
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(count);
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace

void ParallelFor(int64_t count, int64_t grain, int max_threads,
                 const std::function<void(int64_t, int64_t)>& body) {
  if (count <= 0) return;
  grain = std::max<int64_t>(1, grain);
  const int threads = static_cast<int>(
      std::min<int64_t>(std::clamp(max_threads, 1, 256), (count + grain - 1) / grain));
  // Chunks of at most grain items on one thread too: bodies size buffers by it (a single chunk
  // of count items overflowed the HDR merge's stack blocks with ZBRDF_THREADS=1).
  RunChunks(count, grain, threads, [&](int64_t begin, int64_t end) {
    body(begin, end);
    return true;
  });
}

void ParallelForEach(int64_t count, int max_threads, const std::function<bool(int64_t)>& item) {
  if (count <= 0) return;
  const int threads = static_cast<int>(std::min<int64_t>(std::clamp(max_threads, 1, 256), count));
  // Items one at a time; a thread whose item returns false takes no more.
  RunChunks(count, 1, threads, [&](int64_t begin, int64_t) { return item(begin); });
}

}  // namespace zbrdf
