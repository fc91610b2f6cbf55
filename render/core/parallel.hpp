// A fork-join loop for one render: `threads` threads (the caller is one of them) take tasks in
// increasing order from an atomic counter until none is left. Each task runs on exactly one thread,
// so tasks that write disjoint data (screen tiles) give the same result for any thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace rr {

// Calls fn(task, worker) for every task in [0, count), worker in [0, threads); returns when all are
// done. fn must not throw (a render's core asserts its invariants instead).
template <class Fn>
void parallel_for(unsigned threads, size_t count, Fn&& fn) {
  threads = unsigned(std::max<size_t>(1, std::min<size_t>(threads, count)));
  std::atomic<size_t> next{0};
  auto work = [&](unsigned worker) {
    for (size_t task = next++; task < count; task = next++) fn(task, worker);
  };
  std::vector<std::jthread> helpers;
  helpers.reserve(threads - 1);
  for (unsigned w = 1; w < threads; ++w) helpers.emplace_back(work, w);
  work(0);
}  // the jthreads join here

}  // namespace rr
