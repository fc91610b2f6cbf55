// Admission control for CPU-bound work (renders, scene parsing): at most `concurrency` requests work
// at once, at most `queue_limit` wait behind them in arrival order, and anything beyond is refused at
// once (the caller answers 503 + Retry-After) instead of queueing without bound. A waiter gives up at
// its CancelToken's deadline. Admitted work runs on the caller's thread (an httplib connection
// thread), renders on one of RenderWorkers' (render_workers.hpp) while the caller waits; the
// connection pool is sized larger than concurrency + queue so /livez still answers.
#pragma once

#include "render/core/cancel.hpp"

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

namespace rr::server {

struct GateLoad {
  size_t running = 0;
  size_t queued = 0;
  size_t concurrency = 0;
  size_t queue_limit = 0;
  bool closed = false;
  bool saturated() const { return running >= concurrency && queued >= queue_limit; }
};

class RenderGate {
 public:
  enum class Admission {
    admitted,
    saturated,  // every slot busy and the queue full: refused without waiting
    expired,    // waited in the queue until the token's deadline
    closed,     // draining: no new work is taken
    aborted,    // the drain bound ran out while waiting
  };

  RenderGate(size_t concurrency, size_t queue_limit);
  RenderGate(const RenderGate&) = delete;
  RenderGate& operator=(const RenderGate&) = delete;

  // Waits for a slot. When admitted, `token` is registered so abort() can cancel the work, and the
  // caller must call leave(token) when done (GateSlot does).
  Admission enter(CancelToken& token);
  void leave(CancelToken& token);

  void close();  // refuse new work; queued and running work goes on
  void abort();  // cancel running work and turn queued waiters away (the drain bound ran out)
  // Waits until nothing runs or waits, or until `until`; true when idle.
  bool wait_idle(std::chrono::steady_clock::time_point until);
  GateLoad load() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  const size_t concurrency_;
  const size_t queue_limit_;
  std::deque<uint64_t> queue_;  // tickets, oldest first
  uint64_t next_ticket_ = 0;
  std::vector<CancelToken*> running_;
  bool closed_ = false;
  bool aborted_ = false;
};

// Leaves the gate on destruction when admitted.
class GateSlot {
 public:
  GateSlot(RenderGate& gate, CancelToken& token) : gate_(gate), token_(token), admission_(gate.enter(token)) {}
  ~GateSlot() {
    if (admission_ == RenderGate::Admission::admitted) gate_.leave(token_);
  }
  GateSlot(const GateSlot&) = delete;
  GateSlot& operator=(const GateSlot&) = delete;
  RenderGate::Admission admission() const { return admission_; }

 private:
  RenderGate& gate_;
  CancelToken& token_;
  RenderGate::Admission admission_;
};

}  // namespace rr::server
