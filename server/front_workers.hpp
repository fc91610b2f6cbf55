// The connection front's worker pool: a fixed number of threads that turn complete requests into
// answers, fed by a queue of at most max_pending requests (beyond it the front refuses with 503, so
// nothing waits unseen). Answers go back to the event thread through a list and a wake-up call; the
// event thread owns every socket, a worker never touches one.
#pragma once

#include "server/connection_front.hpp"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rr::server {

class WorkerPool {
 public:
  struct Done {
    uint64_t id;  // the connection the answer belongs to
    FrontAnswer answer;
  };
  // `wake` is called (on a worker) each time an answer is ready; `failed` gives the answer when
  // `answer` throws.
  WorkerPool(size_t max_pending, ConnectionFront::Answer answer, std::function<FrontAnswer()> failed,
             std::function<void()> wake);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  void start(size_t threads);
  // Queues `request` for connection `id`; false (and `request` untouched) when max_pending wait already.
  bool submit(uint64_t id, FrontRequest& request);
  std::vector<Done> take_done();
  size_t pending() const;
  // Drops the queued requests, lets running ones finish and joins every thread.
  void stop();

 private:
  struct Job {
    uint64_t id;
    FrontRequest request;
  };
  void run();

  const size_t max_pending_;
  ConnectionFront::Answer answer_;
  std::function<FrontAnswer()> failed_;
  std::function<void()> wake_;
  std::vector<std::thread> threads_;
  mutable std::mutex jobs_mutex_;
  std::condition_variable jobs_ready_;
  std::deque<Job> jobs_;
  bool stopping_ = false;
  std::mutex done_mutex_;
  std::vector<Done> done_;
};

}  // namespace rr::server
