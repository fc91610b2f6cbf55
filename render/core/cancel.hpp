// Cooperative cancellation of a render: the server sets a deadline (or cancels) and the render checks
// it between stages and every few thousand polygons inside long loops, then unwinds by throwing
// RenderCancelled. Checking is a relaxed atomic load and a clock read, cheap enough for inner loops
// that check every ~1k items.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <stdexcept>

namespace rr {

class RenderCancelled : public std::runtime_error {
 public:
  RenderCancelled() : std::runtime_error("render cancelled: deadline exceeded") {}
};

struct CancelToken {
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  std::atomic<bool> cancelled{false};

  bool expired() const {
    return cancelled.load(std::memory_order_relaxed) || std::chrono::steady_clock::now() >= deadline;
  }
};

// Throws RenderCancelled when `token` (may be null: never cancelled) has expired.
inline void check_cancel(const CancelToken* token) {
  if (token && token->expired()) throw RenderCancelled();
}

// Checks a token once per `interval` units of work, for loops whose iterations differ in cost (a BSP
// node of 10^5 polygons against one of 3): callers add what each step costs, in a unit they choose so
// that `interval` units take about a millisecond, and the check stays a counter compare in between.
class CancelMeter {
 public:
  CancelMeter(const CancelToken* token, size_t interval) : token_(token), interval_(interval) {}

  void add(size_t units) {
    done_ += units;
    if (done_ < interval_) return;
    done_ = 0;
    check_cancel(token_);
  }

 private:
  const CancelToken* token_;
  size_t interval_;
  size_t done_ = 0;
};

}  // namespace rr
