// The render pool behind parallel_for: every task runs exactly once on a worker number below the
// thread count, whatever the count of tasks and threads; loops nest and run from several threads
// at once (as concurrent renders do) without losing or repeating a task.
#include "render/core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace rr {
namespace {

// Runs one loop and checks its tasks: each ran once, on a worker below `threads`.
void check_loop(unsigned threads, size_t count) {
  std::vector<std::atomic<int>> runs(count);
  std::atomic<bool> bad_worker{false};
  parallel_for(threads, count, [&](size_t task, unsigned worker) {
    if (worker >= std::max(1u, threads)) bad_worker = true;
    ++runs[task];
  });
  EXPECT_FALSE(bad_worker) << threads << " threads, " << count << " tasks";
  for (size_t t = 0; t < count; ++t)
    ASSERT_EQ(runs[t].load(), 1) << "task " << t << " of " << count << ", " << threads << " threads";
}

TEST(Parallel, EveryTaskRunsOnceOnAWorkerBelowTheThreadCount) {
  for (unsigned threads : {0u, 1u, 2u, 3u, 8u, 17u}) {
    for (size_t count : {size_t{0}, size_t{1}, size_t{2}, size_t{7}, size_t{1000}}) check_loop(threads, count);
  }
  EXPECT_LE(pool_threads(), size_t{max_pool_threads});
  EXPECT_GE(pool_threads(), size_t{16});  // 17 participants: the caller and 16 pool threads
}

TEST(Parallel, AllowedWorkersReallyShareTheTasks) {
  // With tasks that wait for each other, two participants must run at once or this never ends.
  std::atomic<int> arrived{0};
  parallel_for(2, 2, [&](size_t, unsigned) {
    ++arrived;
    while (arrived.load() < 2) std::this_thread::yield();
  });
  EXPECT_EQ(arrived.load(), 2);
}

TEST(Parallel, NestedLoopsAndLoopsFromSeveralThreadsAllComplete) {
  std::atomic<size_t> total{0};
  auto nested = [&] {
    parallel_for(4, 16, [&](size_t, unsigned) { parallel_for(3, 50, [&](size_t, unsigned) { ++total; }); });
  };
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c) callers.emplace_back(nested);
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(total.load(), size_t{4 * 16 * 50});
}

}  // namespace
}  // namespace rr
