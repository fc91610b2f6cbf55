// Fork-join loops for one render on a process-wide pool of persistent threads: `threads` participants
// (the caller is one of them) take tasks in increasing order from an atomic counter until none is
// left. Each task runs on exactly one participant, so tasks that write disjoint data (screen tiles)
// give the same result for any thread count. The pool's threads are made once, on first need, and
// shared by every render of the process, so a frame's passes spawn no threads.
#pragma once

#include <atomic>
#include <cstddef>
#include <type_traits>

namespace rr {

// One parallel loop as the pool sees it: a type-erased body and the loop's shared counters. It lives
// on the caller's stack for the length of the loop.
struct ParallelJob {
  void (*call)(void* body, size_t task, unsigned worker) = nullptr;
  void* body = nullptr;
  size_t count = 0;
  unsigned participants = 1;       // the caller plus at most participants - 1 pool threads
  std::atomic<size_t> next{0};     // the next task to take
  std::atomic<unsigned> slots{1};  // worker numbers handed out; the caller holds 0
  unsigned inside = 0;             // pool threads working on it (guarded by the pool's mutex)
};

// Runs `job` on the calling thread and up to job.participants - 1 pool threads; returns when every
// task is done and no pool thread still holds the job.
void run_parallel(ParallelJob& job);

// The pool's size: threads made so far (grows to the largest participants - 1 asked for, at most
// max_pool_threads).
size_t pool_threads();
constexpr unsigned max_pool_threads = 63;

// Calls fn(task, worker) for every task in [0, count), worker in [0, threads); returns when all are
// done. fn must not throw (a render's core asserts its invariants instead; callers that can throw
// catch inside fn).
template <class Fn>
void parallel_for(unsigned threads, size_t count, Fn&& fn) {
  if (count == 0) return;
  if (threads <= 1 || count == 1) {
    for (size_t task = 0; task < count; ++task) fn(task, 0u);
    return;
  }
  ParallelJob job;
  job.call = [](void* body, size_t task, unsigned worker) {
    (*static_cast<std::remove_reference_t<Fn>*>(body))(task, worker);
  };
  job.body = const_cast<void*>(static_cast<const void*>(&fn));
  job.count = count;
  job.participants = threads < count ? threads : unsigned(count);
  run_parallel(job);
}

}  // namespace rr
