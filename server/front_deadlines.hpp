// The connection front's deadlines: how long each phase of a connection may take, and the ordered
// set of running deadlines the event loop sleeps until. A phase's time is a total, never reset per
// read: a client that sends one byte at a time gets no more time than one that sends nothing. A body
// and an answer get their timeout plus their length at min_transfer_rate; a body's extra time is
// also earned only by bytes received, at min_body_rate, so a trickled body runs out by its timeout
// whatever length it declares. Pure, no sockets.
#pragma once

#include <chrono>
#include <cstdint>
#include <set>
#include <string>
#include <utility>

namespace rr::server {

using FrontClock = std::chrono::steady_clock;

struct DeadlinePolicy {
  std::chrono::milliseconds keep_alive_timeout{5000};
  std::chrono::milliseconds header_timeout{10000};
  std::chrono::milliseconds body_timeout{20000};
  std::chrono::milliseconds write_timeout{10000};
  uint64_t min_transfer_rate = 256u << 10;  // bytes per second granted per declared body or answer byte
  uint64_t min_body_rate = 500;             // a body's bytes received earn 1 s per this many; 0: no minimum rate
};

// When a body whose head arrived at `start`, declaring `declared` bytes of which `received` have
// arrived, is late: body_timeout plus the lesser of declared / min_transfer_rate (the total) and
// received / min_body_rate (what the bytes so far earned). The loop moves it as bytes arrive.
FrontClock::time_point body_deadline(const DeadlinePolicy& policy, FrontClock::time_point start, uint64_t declared,
                                     uint64_t received);
// When an answer of `bytes` bytes started at `start` is late (write_timeout plus bytes at min_transfer_rate).
FrontClock::time_point write_deadline(const DeadlinePolicy& policy, FrontClock::time_point start, uint64_t bytes);
// The 408's detail for a late body, with its numbers.
std::string late_body_detail(const DeadlinePolicy& policy);

// The running deadlines, one per connection id, ordered by time. The connection keeps its own
// deadline (time_point::max(): none), which `move` needs to find the old entry.
class Deadlines {
 public:
  void move(uint64_t id, FrontClock::time_point& current, FrontClock::time_point next);
  // The nearest deadline, or time_point::max() when none runs.
  FrontClock::time_point next() const;
  // Takes the id of a deadline at or before `now` out of the set; false when none is due.
  bool pop_due(FrontClock::time_point now, uint64_t& id);

 private:
  std::set<std::pair<FrontClock::time_point, uint64_t>> timers_;
};

}  // namespace rr::server
