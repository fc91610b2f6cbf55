// The threads renders run on: as many as the render gate admits at once (render_gate.hpp). A render
// keeps buffers on its thread for the next one (the frame's depth and ids, the tile bins, the cull
// state, the lamps' fixture maps), so running every render on these few threads, rather than on
// whichever of the front's many connection threads took the request, finds those buffers made and
// their pages mapped after each thread's first render.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace rr::server {

class RenderWorkers {
 public:
  explicit RenderWorkers(size_t count);
  RenderWorkers(const RenderWorkers&) = delete;
  RenderWorkers& operator=(const RenderWorkers&) = delete;
  ~RenderWorkers();  // runs what is queued, then joins

  // Runs fn on one of the threads, waiting for it, and returns what it returns or throws what it
  // throws. Jobs start in the order they came.
  template <class F>
  auto run(F&& fn) -> decltype(fn()) {
    std::packaged_task<decltype(fn())()> task(std::forward<F>(fn));
    auto result = task.get_future();
    post([&task] { task(); });
    return result.get();
  }

 private:
  void post(std::function<void()> job);

  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace rr::server
