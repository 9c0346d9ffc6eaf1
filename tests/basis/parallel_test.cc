#include "basis/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace zbrdf {
namespace {
namespace ZBRDF_TEST_FILE_ID {

// Each index in exactly one chunk, chunks disjoint, within [0, count) and at most grain long,
// for any grain and thread count (one thread included).
TEST(ParallelFor, CoversEveryIndexOnce) {
  for (int max_threads : {1, 2, 3, 8}) {
    for (int64_t grain : {1, 7, 1000}) {
      const int64_t count = 1001;
      std::vector<std::atomic<int>> hits(count);
      ParallelFor(count, grain, max_threads, [&](int64_t begin, int64_t end) {
        ASSERT_LE(0, begin);
        ASSERT_LT(begin, end);
        ASSERT_LE(end, count);
        ASSERT_LE(end - begin, grain) << "threads " << max_threads;  // bodies size buffers by it
        for (int64_t i = begin; i < end; ++i) ++hits[i];
      });
      for (int64_t i = 0; i < count; ++i) {
        ASSERT_EQ(hits[i].load(), 1) << "index " << i << ", grain " << grain << ", threads "
                                     << max_threads;
      }
    }
  }
}

TEST(ParallelFor, UsesAtMostMaxThreadsAndOneRunsOnTheCaller) {
  std::mutex mutex;
  std::set<std::thread::id> threads;
  ParallelFor(64, 1, 1, [&](int64_t, int64_t) {
    std::lock_guard<std::mutex> lock(mutex);
    threads.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(threads, std::set<std::thread::id>{std::this_thread::get_id()});
  threads.clear();
  ParallelFor(64, 1, 3, [&](int64_t, int64_t) {
    std::lock_guard<std::mutex> lock(mutex);
    threads.insert(std::this_thread::get_id());
  });
  EXPECT_LE(threads.size(), 3u);
}

TEST(ParallelFor, TheFirstExceptionIsRethrownAfterTheWorkersStop) {
  std::atomic<int> calls{0};
  EXPECT_THROW(ParallelFor(100, 1, 4,
                           [&](int64_t begin, int64_t) {
                             ++calls;
                             if (begin == 10) throw std::runtime_error("item 10");
                           }),
               std::runtime_error);
  EXPECT_LE(calls.load(), 100);
  EXPECT_GE(calls.load(), 11);  // items are handed out in order: 0..10 at least
}

TEST(ParallelForEach, AnItemReturningFalseStopsItsThread) {
  std::vector<int> ran;
  ParallelForEach(10, 1, [&](int64_t i) {
    ran.push_back(static_cast<int>(i));
    return i != 3;
  });
  EXPECT_EQ(ran, (std::vector<int>{0, 1, 2, 3}));
  std::atomic<int> count{0};
  ParallelForEach(50, 4, [&](int64_t) {
    ++count;
    return true;
  });
  EXPECT_EQ(count.load(), 50);
  // Two threads, each stopping at its first item: two items run, not ten.
  count = 0;
  ParallelForEach(10, 2, [&](int64_t) {
    ++count;
    return false;
  });
  EXPECT_EQ(count.load(), 2);
}

}  // namespace ZBRDF_TEST_FILE_ID
}  // namespace
}  // namespace zbrdf
