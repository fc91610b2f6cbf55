// RenderWorkers (see render_workers.hpp).
#include "server/render_workers.hpp"

#include <algorithm>

namespace rr::server {

RenderWorkers::RenderWorkers(size_t count) {
  for (size_t i = 0; i < std::max<size_t>(count, 1); ++i) {
    threads_.emplace_back([this] {
      for (;;) {
        std::function<void()> job;
        {
          std::unique_lock lock(mutex_);
          ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
          if (jobs_.empty()) return;  // stopping, nothing left
          job = std::move(jobs_.front());
          jobs_.pop_front();
        }
        job();  // a packaged task: what it throws goes to its caller
      }
    });
  }
}

RenderWorkers::~RenderWorkers() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void RenderWorkers::post(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  ready_.notify_one();
}

}  // namespace rr::server
