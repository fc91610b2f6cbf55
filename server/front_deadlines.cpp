// Deadline arithmetic and the deadline set (see front_deadlines.hpp). Rates are whole bytes per
// second; the time granted for n bytes at rate r is n * 1000 / r milliseconds, rounded down.
#include "server/front_deadlines.hpp"

#include <algorithm>

namespace rr::server {
namespace {

std::chrono::milliseconds time_for(uint64_t bytes, uint64_t rate) {
  return std::chrono::milliseconds(rate ? bytes * 1000 / rate : 0);
}

}  // namespace

FrontClock::time_point body_deadline(const DeadlinePolicy& policy, FrontClock::time_point start, uint64_t declared,
                                     uint64_t received) {
  std::chrono::milliseconds extra = time_for(declared, policy.min_transfer_rate);
  if (policy.min_body_rate) extra = std::min(extra, time_for(std::min(received, declared), policy.min_body_rate));
  return start + policy.body_timeout + extra;
}

FrontClock::time_point write_deadline(const DeadlinePolicy& policy, FrontClock::time_point start, uint64_t bytes) {
  return start + policy.write_timeout + time_for(bytes, policy.min_transfer_rate);
}

std::string late_body_detail(const DeadlinePolicy& policy) {
  std::string earned = policy.min_body_rate ? " received, at most 1 s per " + std::to_string(policy.min_transfer_rate) +
                                                  " bytes declared"
                                            : "";
  return "The request body did not arrive in time (" + std::to_string(policy.body_timeout.count()) +
         " ms plus 1 s per " + std::to_string(policy.min_body_rate ? policy.min_body_rate : policy.min_transfer_rate) +
         " bytes" + earned + ").";
}

void Deadlines::move(uint64_t id, FrontClock::time_point& current, FrontClock::time_point next) {
  if (current == next) return;
  if (current != FrontClock::time_point::max()) timers_.erase({current, id});
  current = next;
  if (next != FrontClock::time_point::max()) timers_.insert({next, id});
}

FrontClock::time_point Deadlines::next() const {
  return timers_.empty() ? FrontClock::time_point::max() : timers_.begin()->first;
}

bool Deadlines::pop_due(FrontClock::time_point now, uint64_t& id) {
  if (timers_.empty() || timers_.begin()->first > now) return false;
  id = timers_.begin()->second;
  timers_.erase(timers_.begin());
  return true;
}

}  // namespace rr::server
