// Cooperative cancellation of a render: the server sets a deadline (or cancels) and the render checks
// it between stages and every few thousand polygons inside long loops, then unwinds by throwing
// RenderCancelled. Checking is a relaxed atomic load and a clock read, cheap enough for inner loops
// that check every ~1k items.
#pragma once

#include <atomic>
#include <chrono>
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

}  // namespace rr
