// The worker pool (see front_workers.hpp).
#include "server/front_workers.hpp"

#include <algorithm>

namespace rr::server {

WorkerPool::WorkerPool(size_t max_pending, ConnectionFront::Answer answer, std::function<FrontAnswer()> failed,
                       std::function<void()> wake)
    : max_pending_(max_pending), answer_(std::move(answer)), failed_(std::move(failed)), wake_(std::move(wake)) {}

WorkerPool::~WorkerPool() { stop(); }

void WorkerPool::start(size_t threads) {
  for (size_t i = 0; i < std::max<size_t>(1, threads); ++i) threads_.emplace_back([this] { run(); });
}

bool WorkerPool::submit(uint64_t id, FrontRequest& request) {
  {
    std::lock_guard lock(jobs_mutex_);
    if (jobs_.size() >= max_pending_) return false;
    jobs_.push_back({id, std::move(request)});
  }
  jobs_ready_.notify_one();
  return true;
}

std::vector<WorkerPool::Done> WorkerPool::take_done() {
  std::vector<Done> ready;
  std::lock_guard lock(done_mutex_);
  ready.swap(done_);
  return ready;
}

size_t WorkerPool::pending() const {
  std::lock_guard lock(jobs_mutex_);
  return jobs_.size();
}

void WorkerPool::stop() {
  {
    std::lock_guard lock(jobs_mutex_);
    stopping_ = true;
    jobs_.clear();
  }
  jobs_ready_.notify_all();
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
}

void WorkerPool::run() {
  for (;;) {
    uint64_t id = 0;
    FrontAnswer result;
    {
      std::unique_lock lock(jobs_mutex_);
      jobs_ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;
      Job job = std::move(jobs_.front());
      jobs_.pop_front();
      lock.unlock();
      id = job.id;
      try {
        result = answer_(job.request);
      } catch (...) {
        result = failed_();
      }
    }  // the request's bytes are freed before `then`, which may return free memory to the OS
    auto then = std::move(result.then);
    {
      std::lock_guard lock(done_mutex_);
      done_.push_back({id, std::move(result)});
    }
    wake_();
    if (then) then();
  }
}

}  // namespace rr::server
