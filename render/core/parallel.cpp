// The process-wide pool behind parallel_for (see parallel.hpp). Pool threads wait on one condition
// variable for queued jobs; a job stays queued while it has tasks left and free worker slots, so
// several renders running at once share the threads. The caller always works on its own job, so a
// loop finishes even when every pool thread is busy elsewhere (or inside a nested loop).
#include "render/core/parallel.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

namespace rr {

namespace {

void run_tasks(ParallelJob& job, unsigned worker) {
  for (size_t task = job.next++; task < job.count; task = job.next++) job.call(job.body, task, worker);
}

bool has_room(const ParallelJob& job) {
  return job.next.load(std::memory_order_relaxed) < job.count &&
         job.slots.load(std::memory_order_relaxed) < job.participants;
}

class Pool {
 public:
  ~Pool() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    work_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  void run(ParallelJob& job) {
    {
      std::lock_guard lock(mutex_);
      grow(job.participants - 1);
      queue_.push_back(&job);
    }
    if (job.participants == 2) {
      work_.notify_one();
    } else {
      work_.notify_all();
    }
    run_tasks(job, 0);
    std::unique_lock lock(mutex_);
    std::erase(queue_, &job);
    done_.wait(lock, [&] { return job.inside == 0; });
  }

  size_t size() {
    std::lock_guard lock(mutex_);
    return threads_.size();
  }

 private:
  void grow(unsigned wanted) {
    wanted = std::min(wanted, max_pool_threads);
    while (threads_.size() < wanted) threads_.emplace_back([this] { serve(); });
  }

  // Under the lock: the first queued job that can take another worker; exhausted jobs leave the queue.
  ParallelJob* pick() {
    for (auto it = queue_.begin(); it != queue_.end();) {
      if ((*it)->next.load(std::memory_order_relaxed) >= (*it)->count) {
        it = queue_.erase(it);
      } else if (has_room(**it)) {
        return *it;
      } else {
        ++it;
      }
    }
    return nullptr;
  }

  void serve() {
    std::unique_lock lock(mutex_);
    for (;;) {
      ParallelJob* job = nullptr;
      work_.wait(lock, [&] { return stopping_ || (job = pick()) != nullptr; });
      if (stopping_) return;
      const unsigned worker = job->slots++;
      ++job->inside;
      lock.unlock();
      if (worker < job->participants) run_tasks(*job, worker);
      lock.lock();
      if (--job->inside == 0) done_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable work_, done_;
  std::deque<ParallelJob*> queue_;
  std::vector<std::thread> threads_;
  bool stopping_ = false;
};

Pool& pool() {
  static Pool instance;
  return instance;
}

}  // namespace

void run_parallel(ParallelJob& job) { pool().run(job); }

size_t pool_threads() { return pool().size(); }

}  // namespace rr
