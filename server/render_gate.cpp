// RenderGate (see render_gate.hpp): one mutex, one condition variable, a FIFO of tickets. A waiter
// proceeds when its ticket is at the front and a slot is free, so admission follows arrival order.
#include "server/render_gate.hpp"

#include <algorithm>

namespace rr::server {

RenderGate::RenderGate(size_t concurrency, size_t queue_limit)
    : concurrency_(std::max<size_t>(1, concurrency)), queue_limit_(queue_limit) {}

RenderGate::Admission RenderGate::enter(CancelToken& token) {
  std::unique_lock lock(mutex_);
  if (closed_ || aborted_) return Admission::closed;
  if (running_.size() < concurrency_ && queue_.empty()) {
    running_.push_back(&token);
    return Admission::admitted;
  }
  if (queue_.size() >= queue_limit_) return Admission::saturated;
  const uint64_t ticket = next_ticket_++;
  queue_.push_back(ticket);
  bool ready = changed_.wait_until(
      lock, token.deadline, [&] { return aborted_ || (queue_.front() == ticket && running_.size() < concurrency_); });
  queue_.erase(std::find(queue_.begin(), queue_.end(), ticket));
  changed_.notify_all();  // the next ticket may be at the front now
  if (aborted_) return Admission::aborted;
  if (!ready) return Admission::expired;
  running_.push_back(&token);
  return Admission::admitted;
}

void RenderGate::leave(CancelToken& token) {
  std::lock_guard lock(mutex_);
  running_.erase(std::find(running_.begin(), running_.end(), &token));
  changed_.notify_all();
}

void RenderGate::close() {
  std::lock_guard lock(mutex_);
  closed_ = true;
}

void RenderGate::abort() {
  std::lock_guard lock(mutex_);
  aborted_ = true;
  for (CancelToken* token : running_) token->cancelled.store(true, std::memory_order_relaxed);
  changed_.notify_all();
}

bool RenderGate::wait_idle(std::chrono::steady_clock::time_point until) {
  std::unique_lock lock(mutex_);
  return changed_.wait_until(lock, until, [&] { return running_.empty() && queue_.empty(); });
}

GateLoad RenderGate::load() const {
  std::lock_guard lock(mutex_);
  return {running_.size(), queue_.size(), concurrency_, queue_limit_, closed_ || aborted_};
}

}  // namespace rr::server
